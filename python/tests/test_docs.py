"""docs/python.md's code blocks, run in order in one namespace from the
repository's root, so that the page stays runnable. A block that imports
an optional package that is not installed (pandas, tqdm) is skipped, and
so are the blocks after it that need its names; the values the page
states in prose are checked below."""

import ast
import importlib.util
import os
import re

import pytest

OPTIONAL = {"pandas", "tqdm", "polars", "submitit"}


def blocks(text):
    out = []
    for m in re.finditer(r"^( *)```python\n(.*?)^\1```", text, re.S | re.M):
        indent = len(m.group(1))
        out.append("\n".join(line[indent:] for line in m.group(2).splitlines()))
    return out


def missing_optional(code):
    # a cluster's job array (submitit's AutoExecutor picks Slurm wherever
    # sbatch is installed, configured or not): its recipe runs on
    # submitit's LocalExecutor in test_researcher_gaps.py
    if "AutoExecutor" in code:
        return "submitit"
    for node in ast.walk(ast.parse(code)):
        names = []
        if isinstance(node, ast.Import):
            names = [a.name.split(".")[0] for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module:
            names = [node.module.split(".")[0]]
        for n in names:
            if n in OPTIONAL and importlib.util.find_spec(n) is None:
                return n
    return None


def test_python_md_runs_in_order(root, capsys):
    pytest.importorskip("gymnasium")
    text = (root / "docs" / "python.md").read_text()
    codes = blocks(text)
    assert len(codes) >= 12
    ns = {}
    here = os.getcwd()
    os.chdir(root)
    skipped = []
    try:
        for i, code in enumerate(codes):
            m = missing_optional(code)
            if m:
                skipped.append(m)
                continue
            try:
                exec(compile(code, f"docs/python.md block {i + 1}", "exec"), ns)
            except Exception as e:  # name the block in the failure
                raise AssertionError(f"docs/python.md block {i + 1} failed: {e!r}\n{code}") from e
    finally:
        os.chdir(here)
    # the values the page states
    scene = ns["scene"]
    assert (scene.name, scene.kind) == ("two_rooms", "grid")
    assert scene.num_slots == 7 and scene.alphabets[0] == "ESWN"
    assert (scene.num_effects, scene.num_commands) == (18, 16384)
    assert ns["arm"].value_ranges[0] == (-1.8, 1.8)
    assert repr(ns["o"]) == "Outcome(effect=17, reward=1.0, x=5.5, y=0.5)"
    assert ns["batch"].commands.shape == (4, 2000, 7)
    assert ns["infos"]["final_obs"].shape == (64,)
    assert (ns["out"] / "results.csv").is_file()
    assert ns["l"].keys() == ["q", "policy", "p", "target"] and ns["l"]["q"].shape == (7, 4)
    assert len(ns["saved"]) == 1129
    assert (ns["cl"].name, ns["cl"]["q"].shape) == ("e3d_closed_loop", (18, 7, 4))
    assert set(skipped) <= OPTIONAL
