import json

import numpy as np
import pytest

import e3d

from conftest import read_csv


def cli_run(cli, tmp_path, scene, *args):
    out = tmp_path / "run"
    cli("run", scene, *args, "--out", out)
    rows = read_csv((out / "trials.csv").read_text())
    summary = json.loads((out / "summary.json").read_text())
    return rows, summary


@pytest.mark.parametrize(
    "scene, learner, extra",
    [
        ("two_rooms", "e3d", {}),
        ("two_rooms", "uniform", {}),
        ("two_rooms", "egreedy", {"alpha": 0.5, "epsilon": 0.2}),
        ("two_rooms", "goal_babbling", {"k": 3, "goal_progress": 0.5}),
        ("two_rooms", "archive", {"k": 1, "rarity": 2.0}),
        ("puck_rooms", "e3d", {"beta": 100.0}),
        ("puck_rooms", "e3d", {"use_reward": False}),
    ],
)
def test_run_session_equals_e3d_run(cli, tmp_path, scene, learner, extra):
    trials, seed = 300, 5
    args = ["--learner", learner, "--trials", trials, "--seed", seed]
    for k, v in extra.items():
        if k == "use_reward":
            args.append("--no-reward")
        else:
            args += [f"--{k.replace('_', '-')}", v]
    rows, summary = cli_run(cli, tmp_path, scene, *args)
    rec = e3d.run_session(scene, learner=learner, trials=trials, seed=seed, **extra)
    assert rec.effects.tolist() == [int(r["effect"]) for r in rows]
    assert rec.rewards.tolist() == [float(r["reward"]) for r in rows]
    s = e3d.Scene.builtin(scene)
    assert s.format(rec.commands) == [r["command"] for r in rows]
    for k in ["normalized_entropy", "normalized_entropy_last_1000", "kl_to_target",
              "distinct_effects", "cumulative_reward", "first_reward_trial"]:
        assert rec.metrics[k] == summary[k], k


def test_record_shapes_and_types():
    rec = e3d.run_session("two_rooms", trials=1200, seed=0, beta=100.0)
    assert rec.commands.shape == (1200, 7) and rec.commands.dtype == np.uint8
    assert rec.effects.shape == (1200,) and rec.effects.dtype == np.int64
    assert rec.rewards.shape == (1200,) and rec.rewards.dtype == np.float64
    assert rec.trials == 1200 and rec.seed == 0 and rec.learner == "e3d"
    assert set(rec.metrics) == {
        "normalized_entropy", "normalized_entropy_last_1000", "kl_to_target",
        "distinct_effects", "cumulative_reward", "first_reward_trial", "trials",
        "reachable_effects", "normalized_entropy_reachable", "coverage_cells", "coverage",
        "trials_to_50_percent", "trials_to_90_percent", "discovery_trials", "qd_score",
    }
    assert rec.metrics["cumulative_reward"] == rec.rewards.sum()
    assert "two_rooms: outcome table" in rec.execution


def test_strategies_give_the_same_session():
    recs = [
        e3d.run_session("puck_rooms", trials=200, seed=9, outcomes=o)
        for o in [None, "table", "memo", "live"]
    ]
    for r in recs[1:]:
        assert r.effects.tolist() == recs[0].effects.tolist()
        assert r.rewards.tolist() == recs[0].rewards.tolist()


def test_table_cache(tmp_path):
    a = e3d.run_session("puck_rooms", trials=100, seed=1, table_cache=tmp_path)
    assert any(tmp_path.iterdir())
    b = e3d.run_session("puck_rooms", trials=100, seed=1, table_cache=tmp_path)
    assert a.effects.tolist() == b.effects.tolist()


def test_bad_arguments():
    with pytest.raises(ValueError, match="unknown learner `nope`; expected one of: e3d, uniform, egreedy"):
        e3d.run_session("two_rooms", learner="nope")
    with pytest.raises(ValueError, match=r"alpha = -1: expected a finite number > 0"):
        e3d.run_session("two_rooms", alpha=-1.0)
    with pytest.raises(ValueError, match=r"eta = 2: expected a number in \(0, 1\]"):
        e3d.run_session("two_rooms", eta=2.0)
    with pytest.raises(ValueError, match="trials = 0"):
        e3d.run_session("two_rooms", trials=0)
    with pytest.raises(ValueError, match="outcomes = `fast`"):
        e3d.run_session("two_rooms", outcomes="fast")
    with pytest.raises(e3d.SceneError, match="no such file, and no built-in scene"):
        e3d.run_session("no_such_scene")
    with pytest.raises(e3d.SceneError, match=r"of that name \(did you mean `puck_rooms`\?\); expected"):
        e3d.run_session("puck_room")
    with pytest.raises(e3d.SceneError, match=r"^puck_room: no built-in scene of that name \(did you mean `puck_rooms`\?\)"):
        e3d.Scene.builtin("puck_room")
    with pytest.raises(TypeError, match="has no `propose`"):
        e3d.run_session("two_rooms", learner=object())


class Uniform:
    """The uniform policy, written in Python: one rng.integers(k) per slot."""

    name = "py-uniform"

    def __init__(self, scene):
        self.sizes = scene.alphabet_sizes
        self.seen = []

    def propose(self, rng):
        return [rng.integers(k) for k in self.sizes]

    def learn(self, command, effect, reward):
        assert command.dtype == np.uint8
        self.seen.append(effect)


def test_python_learner_runs_and_learns():
    scene = e3d.Scene.builtin("two_rooms")
    learner = Uniform(scene)
    rec = e3d.run_session(scene, learner=learner, trials=500, seed=3)
    assert rec.learner == "py-uniform"
    assert learner.seen == rec.effects.tolist()
    again = e3d.run_session(scene, learner=Uniform(scene), trials=500, seed=3)
    assert again.commands.tolist() == rec.commands.tolist()
    other = e3d.run_session(scene, learner=Uniform(scene), trials=500, seed=4)
    assert other.commands.tolist() != rec.commands.tolist()
    # the world's outcomes: the same as executing the commands
    out = scene.world().execute_batch(rec.commands)
    assert out.effect.tolist() == rec.effects.tolist()


def test_python_learner_draws_from_the_session_generator():
    # a Python learner that draws as the library's uniform policy does
    # (one random_range(0..k) per slot) proposes the same commands
    scene = e3d.Scene.builtin("two_rooms")
    mine = e3d.run_session(scene, learner=Uniform(scene), trials=300, seed=11)
    theirs = e3d.run_session(scene, learner="uniform", trials=300, seed=11)
    assert mine.commands.tolist() == theirs.commands.tolist()


def test_python_learner_exceptions_propagate():
    class Boom:
        def __init__(self):
            self.n = 0

        def propose(self, rng):
            self.n += 1
            if self.n == 7:
                raise KeyError("seven")
            return "EEEEEEE"

        def learn(self, command, effect, reward):
            pass

    b = Boom()
    with pytest.raises(KeyError, match="seven"):
        e3d.run_session("two_rooms", learner=b, trials=100)
    assert b.n == 7

    class Bad:
        def propose(self, rng):
            return [9] * 7

        def learn(self, command, effect, reward):
            pass

    with pytest.raises(ValueError, match="out of range"):
        e3d.run_session("two_rooms", learner=Bad(), trials=10)


def test_rng_methods():
    seen = {}

    class Probe:
        def propose(self, rng):
            seen["r"] = rng.random()
            seen["c"] = rng.choice([0.0, 1.0, 0.0])
            with pytest.raises(ValueError):
                rng.integers(0)
            return "EEEEEEE"

        def learn(self, command, effect, reward):
            pass

    e3d.run_session("two_rooms", learner=Probe(), trials=1)
    assert 0.0 <= seen["r"] < 1.0 and seen["c"] == 1


def test_goal_babbling_and_archive_parameters_reach_the_learner():
    # k, sigma, rarity and goal_progress (the CLI's --k, --sigma, --rarity,
    # --goal-progress; the CLI comparison above checks the same trials)
    def commands(scene, learner, trials, **kw):
        return e3d.run_session(scene, learner=learner, trials=trials, seed=5, **kw).commands.tolist()
    assert commands("two_rooms", "goal_babbling", 300) != commands(
        "two_rooms", "goal_babbling", 300, k=3, goal_progress=0.5)
    assert commands("two_rooms", "archive", 300) != commands("two_rooms", "archive", 300, rarity=2.0)
    assert commands("arm7_continuous", "goal_babbling", 40) != commands(
        "arm7_continuous", "goal_babbling", 40, sigma=0.3)
    # a Learner made with them runs as run_session with them
    held = e3d.Learner("two_rooms", learner="archive", k=1, rarity=2.0)
    assert commands("two_rooms", held, 300) == commands("two_rooms", "archive", 300, k=1, rarity=2.0)
    assert e3d.run_sessions("two_rooms", learner="archive", trials=300, seeds=[5], k=1,
                            rarity=2.0)[0].commands.tolist() == commands(
        "two_rooms", "archive", 300, k=1, rarity=2.0)
    with pytest.raises(ValueError, match=r"^k = 0: expected an integer from 1"):
        e3d.run_session("two_rooms", learner="archive", k=0)
    with pytest.raises(ValueError, match=r"goal_progress"):
        e3d.run_session("two_rooms", learner="goal_babbling", goal_progress=2.0)
