"""Pickling: Scene (its RON text), World (its scene's world) and the
Gymnasium environment (with its generator's state), for multiprocessing,
joblib and deepcopy."""

import copy
import pickle

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
