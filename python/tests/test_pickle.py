"""Pickling: Scene (its RON text), World (its scene's world), the
Gymnasium environment (with its generator's state), every result class
(field for field) and SessionRng (its state), for multiprocessing,
joblib and deepcopy."""

import copy
import pickle
from concurrent.futures import ProcessPoolExecutor
import multiprocessing

import numpy as np
import pytest

import e3d


@pytest.mark.parametrize("name", ["two_rooms", "puck_rooms", "arm7", "arm7_continuous"])
def test_scene_round_trips(name):
    s = e3d.Scene.builtin(name)
    back = pickle.loads(pickle.dumps(s))
    assert back == s and back.name == name
    assert copy.deepcopy(s) == s
    assert e3d.Scene.from_text(s.to_ron(), "x.ron") == s


def test_world_round_trips_with_the_same_outcomes():
    w = e3d.Scene.builtin("puck_rooms").world()
    cmds = e3d.Scene.builtin("puck_rooms").parse(["EESSEES", "SEEEEES", "NNNNWWW"])
    want = w.execute_batch(cmds)
    back = pickle.loads(pickle.dumps(w))
    assert back.scene == w.scene and back.memo_len == 0
    got = back.execute_batch(cmds)
    assert got.effect.tolist() == want.effect.tolist() and got.x.tolist() == want.x.tolist()
    assert copy.deepcopy(w).execute("EESSEES") == w.execute("EESSEES")
    lean = pickle.loads(pickle.dumps(e3d.Scene.builtin("puck_rooms").world(prefix_states=7)))
    assert lean.prefix_states == 7


def test_env_round_trips_with_its_generator():
    gym = pytest.importorskip("gymnasium")
    from e3d.gym import E3dEnv

    for name in ["two_rooms", "arm7_continuous"]:
        env = E3dEnv(name)
        env.reset(seed=3)
        env.action_space.seed(5)
        env.np_random.random()
        back = pickle.loads(pickle.dumps(env))
        assert back.np_random.random() == env.np_random.random()
        a = env.action_space.sample()
        assert np.array_equal(back.action_space.sample(), a)
        assert back.step(a)[:4] == env.step(a)[:4]
        assert isinstance(back.action_space, type(env.action_space))
    del gym


def _same(a, b):
    """Whether two pickled values are equal, numpy arrays by dtype and
    contents, containers item by item."""
    if isinstance(a, np.ndarray):
        return isinstance(b, np.ndarray) and a.dtype == b.dtype and a.shape == b.shape and (
            np.array_equal(a, b, equal_nan=a.dtype.kind == "f"))
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (list, tuple)):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, float) and a != a:
        return b != b
    return type(a) is type(b) and a == b


def _fields(obj):
    names = [n for n in dir(obj) if not n.startswith("_") and not callable(getattr(obj, n))]
    return {n: getattr(obj, n) for n in names}


def _results():
    w = e3d.Scene.builtin("puck_rooms").world()
    ctx = e3d.Scene.builtin("two_rooms")
    return {
        "Outcome": w.execute("EESSEES"),
        "BatchOutcome": w.execute_batch(["EESSEES", "SEEEEES"]),
        "Motion": w.trace("EESSEES"),
        "SessionRecord": e3d.run_session("two_rooms", trials=60, seed=2),
        "SessionRecord (continuous)": e3d.run_session("arm7_continuous", trials=4, seed=1),
        "SessionBatch": e3d.run_sessions("two_rooms", trials=40, seeds=[0, 5]),
        "EpisodeRecord": e3d.run_episodes(ctx, episodes=6, commands=2, seed=3),
    }


def test_every_result_round_trips_field_for_field():
    for kind, r in _results().items():
        for back in (pickle.loads(pickle.dumps(r)), copy.deepcopy(r)):
            assert type(back) is type(r), kind
            want, got = _fields(r), _fields(back)
            assert want and got.keys() == want.keys(), kind
            for name in want:
                assert _same(want[name], got[name]), (kind, name)
            assert repr(back) == repr(r)
    rec = _results()["SessionRecord"]
    assert pickle.loads(pickle.dumps(rec))._repr_svg_() == rec._repr_svg_()
    batch = _results()["SessionBatch"]
    again = pickle.loads(pickle.dumps(batch))
    assert len(again) == 2 and _same(_fields(again[1]), _fields(batch[1]))
    motion = _results()["Motion"]
    assert _same(pickle.loads(pickle.dumps(motion)).columns(), motion.columns())


def test_a_result_equals_its_copy_and_the_same_work_run_again():
    # == compares every field (arrays value by value, NaN equal to NaN), so
    # a reproducibility check reads `a == b`
    first, again = _results(), _results()
    for kind, r in first.items():
        assert r == again[kind] == pickle.loads(pickle.dumps(r)) == copy.deepcopy(r), kind
        assert not (r != again[kind]), kind
        assert r != 3 and r is not None, kind
    other = {
        "BatchOutcome": e3d.Scene.builtin("puck_rooms").world().execute_batch(["EESSEES", "SEEEEEN"]),
        "Motion": e3d.Scene.builtin("puck_rooms").world().trace("EESSEEN"),
        "SessionRecord": e3d.run_session("two_rooms", trials=60, seed=3),
        "SessionRecord (continuous)": e3d.run_session("arm7_continuous", trials=4, seed=2),
        "SessionBatch": e3d.run_sessions("two_rooms", trials=40, seeds=[0, 6]),
        "EpisodeRecord": e3d.run_episodes(e3d.Scene.builtin("two_rooms"), episodes=6, commands=2, seed=4),
    }
    for kind, r in other.items():
        assert r != first[kind], kind
    batch = first["SessionBatch"]
    assert batch[0:1] == batch[0:1] and batch[0:1] != batch[1:2]
    # NaN (no reward yet) in the batch's metrics compares equal to NaN
    assert np.isnan(batch.metrics["first_reward_trial"]).all()
    rec = first["SessionRecord"]
    with pytest.raises(TypeError, match="unhashable"):
        hash(rec)


def test_a_broken_state_is_refused_with_the_class_named():
    with pytest.raises(TypeError, match=r"Outcome._from_state: expected a state of 4 fields"):
        e3d.Outcome._from_state((1, 2.0))
    with pytest.raises(TypeError, match=r"Outcome._from_state: field 0"):
        e3d.Outcome._from_state(("x", 0.0, 0.0, 0.0))


def _session(seed):
    return e3d.run_session("two_rooms", trials=50, seed=seed)


def test_sessions_come_back_from_worker_processes():
    # what joblib and multiprocessing do: results cross the process boundary
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        got = list(pool.map(_session, [4, 9]))
    for seed, r in zip([4, 9], got):
        want = _session(seed)
        assert r.seed == seed and np.array_equal(r.effects, want.effects)
        assert r.metrics == want.metrics


def test_own_generator_round_trips_with_its_state():
    rng = e3d.SessionRng(11)
    rng.random()
    back = pickle.loads(pickle.dumps(rng))
    assert [back.random() for _ in range(5)] == [rng.random() for _ in range(5)]
    assert copy.deepcopy(rng).integers(7) == rng.integers(7)
