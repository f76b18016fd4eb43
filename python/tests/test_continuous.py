"""Continuous scenes from Python: arm7_continuous loads, its worlds execute
values, and run_session(s) run the Gaussian E3D and uniform values, with
the CLI's numbers."""

import json

import numpy as np
import pytest

import e3d
from conftest import read_csv


def test_arm7_continuous_loads():
    assert "arm7_continuous" in e3d.Scene.builtins()
    s = e3d.Scene.resolve("arm7_continuous")
    assert s.is_continuous and s.num_slots == 7
    assert s.value_ranges[0] == (-1.8, 1.8)
    assert s.alphabet_sizes == [] and s.num_commands is None
    assert not e3d.Scene.builtin("two_rooms").is_continuous
    assert e3d.Scene.builtin("two_rooms").value_ranges == []
    with pytest.raises(ValueError, match="Scene.parse: scene `arm7_continuous` takes continuous values"):
        s.parse("EEE")


def test_session_is_the_clis(cli, tmp_path):
    out = tmp_path / "run"
    cli("run", "arm7_continuous", "--trials", 64, "--seed", 3, "--out", out)
    rows = read_csv((out / "trials.csv").read_text())
    summary = json.loads((out / "summary.json").read_text())["sessions"][0]
    rec = e3d.run_session("arm7_continuous", trials=64, seed=3)
    assert rec.learner == "e3d" and rec.commands.dtype == np.float64
    assert rec.commands.shape == (64, 7)
    assert rec.commands.tolist() == [[float(v) for v in r["values"].split(",")] for r in rows]
    assert rec.effects.tolist() == [int(r["effect"]) for r in rows]
    for k, v in rec.metrics.items():
        assert summary[k] == v, k
    assert rec.effect_counts.tolist() == summary["effect_counts"]
    assert rec.final_policy.tolist() == [[p["mean"], p["sd"]] for p in summary["final_policy"]]
    # the world gives the same outcomes, one at a time and in a batch
    world = e3d.Scene.builtin("arm7_continuous").world()
    batch = world.execute_batch(rec.commands[:40])
    assert batch.effect.tolist() == rec.effects[:40].tolist()
    assert batch.x.tolist() == [float(r["x"]) for r in rows[:40]]
    one = world.execute(rec.commands[5])
    assert (one.effect, one.x, one.y) == (int(rows[5]["effect"]), float(rows[5]["x"]), float(rows[5]["y"]))
    assert world.execute(rows[5]["values"]) == one


def test_uniform_values_and_lockstep_sessions():
    batch = e3d.run_sessions("arm7_continuous", learner="uniform", trials=30, seeds=[4, 9])
    assert batch.commands.shape == (2, 30, 7) and batch.learner == "uniform"
    for i, seed in enumerate([4, 9]):
        one = e3d.run_session("arm7_continuous", learner="uniform", trials=30, seed=seed)
        assert one.commands.tolist() == batch.commands[i].tolist()
        assert one.effects.tolist() == batch[i].effects.tolist()
    lo = np.array([r[0] for r in e3d.Scene.builtin("arm7_continuous").value_ranges])
    hi = np.array([r[1] for r in e3d.Scene.builtin("arm7_continuous").value_ranges])
    assert ((batch.commands >= lo) & (batch.commands <= hi)).all()


def test_continuous_errors():
    world = e3d.Scene.builtin("arm7_continuous").world()
    with pytest.raises(ValueError, match=r"row 1: "):
        world.execute_batch([[0.0] * 7, [9.0] + [0.0] * 6])
    with pytest.raises(ValueError, match=r"shape \[N, 7\]"):
        world.execute_batch(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="commands: an empty batch"):
        world.execute_batch(np.zeros((0, 7)))
    with pytest.raises(TypeError, match='takes continuous commands: expected one of "e3d", "uniform"'):
        e3d.run_session("arm7_continuous", learner=object(), trials=5)
    with pytest.raises(ValueError, match="learner `egreedy` takes symbols"):
        e3d.run_session("arm7_continuous", learner="egreedy", trials=5)
    with pytest.raises(ValueError, match="run live only"):
        e3d.run_session("arm7_continuous", trials=5, outcomes="table")


def test_trace_of_values():
    world = e3d.Scene.builtin("arm7_continuous").world()
    tr = world.trace("1.8, -1.2, 0.75, 0, 0, 0, 0")
    assert tr.outcome == world.execute([1.8, -1.2, 0.75, 0, 0, 0, 0])
    assert len(tr) > 100 and tr.x.shape[0] == len(tr)
