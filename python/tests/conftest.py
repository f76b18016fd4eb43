"""Shared fixtures: the repository's root and the e3d CLI to compare with.

The CLI is ``$E3D_BIN`` or the repository's ``target/release/e3d`` (built by
``cargo build --release``, which scripts/test-python.sh runs); tests that
compare with it are skipped when neither exists.
"""

import csv
import io
import os
import pathlib
import signal
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# A shell without job control starts a background command (`cmd &`,
# `nohup ... &`, CI runners) with SIGINT ignored, and Python then leaves
# it ignored: the Ctrl-C tests' SIGINT did nothing, so a 10-million-trial
# call ran to its end (the "hang" seen under load, with the main thread
# waiting in `watched`) or `pytest.raises(KeyboardInterrupt)` failed.
# The tests send themselves SIGINT: restore Python's handler (children
# then start with it too).
if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)


def _cli_path():
    p = os.environ.get("E3D_BIN")
    if p:
        return pathlib.Path(p)
    return ROOT / "target" / "release" / "e3d"


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """Runs the CLI: cli(*args, input=None) -> CompletedProcess (text)."""
    path = _cli_path()
    if not path.exists():
        pytest.skip(f"no e3d CLI at {path}: run `cargo build --release` or set E3D_BIN")

    def run(*args, input=None, check=True):
        r = subprocess.run(
            [str(path), *map(str, args)],
            input=input,
            capture_output=True,
            text=True,
            cwd=ROOT,
        )
        if check and r.returncode != 0:
            raise AssertionError(f"e3d {' '.join(map(str, args))} failed: {r.stderr}")
        return r

    return run


def read_csv(text):
    return list(csv.DictReader(io.StringIO(text)))
