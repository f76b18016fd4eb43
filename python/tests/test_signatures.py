"""The hyper-parameters' defaults are written out in every signature (so
that `help()` and IDEs show them): each function and constructor that
takes them has the CLI's defaults, as `e3d run` writes them into
summary.json, and the type stubs say the same (stubtest checks the
stubs against these signatures)."""

import inspect
import json

import pytest

import e3d

TAKERS = {
    "run_session": e3d.run_session,
    "run_sessions": e3d.run_sessions,
    "run_episodes": e3d.run_episodes,
    "Learner": e3d.Learner,
    "Learner.contextual": e3d.Learner.contextual,
    "E3dLearner": e3d.E3dLearner,
}
NAMES = {"alpha": "alpha", "beta": "beta", "lambda_": "lambda", "eta": "eta", "epsilon": "epsilon"}


@pytest.fixture(scope="module")
def cli_defaults(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("defaults") / "run"
    cli("run", "two_rooms", "--trials", "10", "--out", out)
    summary = json.loads((out / "summary.json").read_text())
    return {k: summary[k] for k in NAMES.values()}


@pytest.mark.parametrize("name", sorted(TAKERS))
def test_every_signature_has_the_clis_defaults(cli_defaults, name):
    params = inspect.signature(TAKERS[name]).parameters
    seen = {py: params[py].default for py in NAMES if py in params}
    assert {"alpha", "beta", "lambda_", "eta"} <= set(seen), name
    assert seen == {py: cli_defaults[NAMES[py]] for py in seen}, name
    assert params["target"].default is None
