import json
import math

import numpy as np
import pytest

import e3d

from conftest import read_csv


def same_metric(a, b):
    if a is None or (isinstance(a, float) and math.isnan(a)):
        return b is None or (isinstance(b, float) and math.isnan(b))
    return a == b


@pytest.mark.parametrize(
    "scene, learner, trials, extra",
    [
        ("two_rooms", "e3d", 300, {"beta": 100.0}),  # an outcome table: one session a group
        # lockstep groups, 32 copies a Rapier world
        ("puck_rooms", "e3d", 200, {"beta": 100.0, "outcomes": "memo"}),
        ("puck_rooms", "egreedy", 150, {"outcomes": "live"}),
        ("arm7", "uniform", 60, {"outcomes": "memo", "use_reward": False}),  # a mirror symmetry
    ],
)
def test_run_sessions_equals_separate_run_session_calls(scene, learner, trials, extra):
    seeds = [3, 0, 11, 7, 2]
    batch = e3d.run_sessions(scene, learner=learner, trials=trials, seeds=seeds, **extra)
    assert len(batch) == 5 and batch.seeds.tolist() == seeds and batch.seeds.dtype == np.uint64
    s = e3d.Scene.builtin(scene)
    assert batch.commands.shape == (5, trials, s.num_slots) and batch.commands.dtype == np.uint8
    assert batch.effects.shape == (5, trials) and batch.effects.dtype == np.int64
    assert batch.rewards.shape == (5, trials) and batch.rewards.dtype == np.float64
    for i, seed in enumerate(seeds):
        one = e3d.run_session(scene, learner=learner, trials=trials, seed=seed, **extra)
        assert batch.commands[i].tolist() == one.commands.tolist()
        assert batch.effects[i].tolist() == one.effects.tolist()
        assert batch.rewards[i].tolist() == one.rewards.tolist()
        rec = batch[i]
        assert rec.seed == seed and rec.learner == learner and rec.trials == trials
        assert rec.metrics == one.metrics
        for k, v in one.metrics.items():
            if k == "discovery_trials":  # a list per session: in batch[i].metrics only
                continue
            assert same_metric(v, batch.metrics[k][i].item()), k
    assert batch[-1].seed == seeds[-1]
    with pytest.raises(IndexError):
        batch[5]
    assert [r.seed for r in batch] == seeds


def test_a_slice_of_a_batch_is_the_batch_of_those_sessions():
    import pickle
    batch = e3d.run_sessions("two_rooms", trials=30, sessions=6, seed=4)
    for sl in (slice(1, 4), slice(None, None, -2), slice(4, 100), slice(3, 3)):
        part = batch[sl]
        rows = list(range(6))[sl]
        assert type(part) is e3d.SessionBatch and len(part) == len(rows)
        assert part.seeds.tolist() == batch.seeds[sl].tolist() == [4 + i for i in rows]
        assert part.trials == batch.trials and part.scene == batch.scene
        for name in ("commands", "effects", "rewards"):
            assert getattr(part, name).tolist() == getattr(batch, name)[sl].tolist()
        for k, v in part.metrics.items():
            assert np.array_equal(v, batch.metrics[k][sl], equal_nan=True), k
        for j, i in enumerate(rows):
            assert part[j].metrics == batch[i].metrics
            assert part[j].effect_counts.tolist() == batch[i].effect_counts.tolist()
        again = pickle.loads(pickle.dumps(part))
        assert again.effects.tolist() == part.effects.tolist() and len(again) == len(rows)
    assert "<svg" in batch[1:3]._repr_svg_()
    with pytest.raises(TypeError, match=r"^session index: expected an integer or a slice, found str$"):
        batch["1"]


def test_run_sessions_equals_e3d_run_sessions(cli, tmp_path):
    out = tmp_path / "run"
    cli("run", "puck_rooms", "--sessions", 4, "--seed", 9, "--trials", 400,
        "--beta", 100, "--out", out)
    rows = read_csv((out / "trials.csv").read_text())
    summary = json.loads((out / "summary.json").read_text())
    batch = e3d.run_sessions("puck_rooms", trials=400, sessions=4, seed=9, beta=100.0)
    assert batch.seeds.tolist() == [9, 10, 11, 12]
    scene = e3d.Scene.builtin("puck_rooms")
    for i in range(4):
        mine = [r for r in rows if int(r["session"]) == i]
        assert [int(r["trial"]) for r in mine] == list(range(1, 401))
        assert scene.format(batch.commands[i]) == [r["command"] for r in mine]
        assert batch.effects[i].tolist() == [int(r["effect"]) for r in mine]
        assert batch.rewards[i].tolist() == [float(r["reward"]) for r in mine]
        want = summary["sessions"][i]
        assert want["seed"] == 9 + i
        for k in ["normalized_entropy", "normalized_entropy_last_1000", "kl_to_target",
                  "distinct_effects", "cumulative_reward", "first_reward_trial", "trials"]:
            assert same_metric(want[k], batch.metrics[k][i].item()), k
            assert batch[i].metrics[k] == want[k], k


def test_metrics_arrays():
    batch = e3d.run_sessions("two_rooms", learner="uniform", trials=50, seeds=[0, 1, 2],
                             use_reward=False)
    m = batch.metrics
    assert m["distinct_effects"].dtype == np.int64 and m["trials"].tolist() == [50] * 3
    assert m["normalized_entropy"].dtype == np.float64
    # no reward seen: no first reward trial (NaN in the arrays, None per session)
    assert np.isnan(m["first_reward_trial"]).all()
    assert batch[0].metrics["first_reward_trial"] is None
    assert "two_rooms: outcome table" in batch.execution


class Uniform:
    name = "py-uniform"

    def __init__(self, scene):
        self.sizes = scene.alphabet_sizes
        self.seen = []

    def propose(self, rng):
        return [rng.integers(k) for k in self.sizes]

    def learn(self, command, effect, reward):
        self.seen.append(effect)


def test_python_learners_in_lockstep():
    scene = e3d.Scene.builtin("puck_rooms")
    learners = [Uniform(scene) for _ in range(3)]
    batch = e3d.run_sessions(scene, learner=learners, trials=200, seeds=[5, 6, 7])
    theirs = e3d.run_sessions(scene, learner="uniform", trials=200, seeds=[5, 6, 7])
    assert batch.learner == "py-uniform"
    assert batch.commands.tolist() == theirs.commands.tolist()
    assert batch.effects.tolist() == theirs.effects.tolist()
    for learner, effects in zip(learners, batch.effects):
        assert learner.seen == effects.tolist()


def test_python_learner_exception_in_lockstep():
    class Boom(Uniform):
        def learn(self, command, effect, reward):
            if len(self.seen) == 10:
                raise KeyError("ten")
            super().learn(command, effect, reward)

    scene = e3d.Scene.builtin("two_rooms")
    with pytest.raises(KeyError, match="ten"):
        e3d.run_sessions(scene, learner=[Uniform(scene), Boom(scene)], trials=50, seeds=[0, 1])


def test_bad_arguments():
    with pytest.raises(ValueError, match="either seeds or sessions"):
        e3d.run_sessions("two_rooms", seeds=[1], sessions=2)
    with pytest.raises(ValueError, match="expected seeds"):
        e3d.run_sessions("two_rooms")
    with pytest.raises(ValueError, match="at least one seed"):
        e3d.run_sessions("two_rooms", seeds=[])
    with pytest.raises(ValueError, match="pass 2\\^64 - 1"):
        e3d.run_sessions("two_rooms", sessions=2, seed=2**64 - 1)
    with pytest.raises(ValueError, match="one learner per seed"):
        e3d.run_sessions("two_rooms", learner=[Uniform(e3d.Scene.builtin("two_rooms"))], seeds=[0, 1])
    with pytest.raises(ValueError, match="unknown learner `nope`"):
        e3d.run_sessions("two_rooms", learner="nope", seeds=[0])
    with pytest.raises(ValueError, match="trials = 0"):
        e3d.run_sessions("two_rooms", trials=0, seeds=[0])


def test_a_failing_session_raises_the_clis_error(root):
    path = root / "tests" / "scenes" / "blowup.ron"

    class Kick:
        def propose(self, rng):
            return "0K"

        def learn(self, command, effect, reward):
            pass

    class Still(Kick):
        def propose(self, rng):
            return "00"

    with pytest.raises(e3d.SimulationError, match="command `0K`: the simulation blew up"):
        e3d.run_sessions(e3d.Scene.load(path), learner=[Still(), Kick()], trials=3, seeds=[0, 1])
