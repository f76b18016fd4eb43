"""E3dVectorEnv: execute_batch as a gymnasium VectorEnv, same-step autoreset."""

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")
from gymnasium.vector import AutoresetMode, SyncVectorEnv  # noqa: E402

import e3d  # noqa: E402
from e3d.gym import E3dEnv, E3dVectorEnv  # noqa: E402


@pytest.mark.parametrize("name", ["two_rooms", "puck_rooms", "arm7_continuous"])
def test_equals_sync_vector_env_in_same_step_mode(name):
    n = 8
    vec = E3dVectorEnv(name, n)
    sync = SyncVectorEnv([lambda: E3dEnv(name) for _ in range(n)], autoreset_mode=AutoresetMode.SAME_STEP)
    assert vec.metadata["autoreset_mode"] == AutoresetMode.SAME_STEP
    assert vec.action_space == sync.action_space
    assert vec.observation_space == sync.observation_space
    o1, _ = vec.reset(seed=3)
    o2, _ = sync.reset(seed=3)
    assert o1.tolist() == o2.tolist()
    for _ in range(3):
        a = vec.action_space.sample()
        obs, rew, term, trunc, info = vec.step(a)
        obs2, rew2, term2, trunc2, info2 = sync.step(a)
        assert obs.tolist() == obs2.tolist() == [vec.scene.start_effect] * n
        assert rew.tolist() == rew2.tolist()
        assert term.all() and term2.all() and not trunc.any() and not trunc2.any()
        assert info["final_obs"].tolist() == [int(x) for x in info2["final_obs"]]
        assert info["final_info"]["x"].tolist() == info2["final_info"]["x"].tolist()
        assert info["_final_obs"].all()


def test_a_rewarded_command_is_rewarded_every_step():
    vec = E3dVectorEnv("two_rooms", 2)
    vec.reset(seed=0)
    a = vec.scene.parse(["SEEEEES", "EEEEEEE"])
    rewards = [vec.step(a)[1].tolist() for _ in range(4)]
    assert rewards == [[1.0, 0.0]] * 4
    assert E3dVectorEnv("two_rooms", 2, use_reward=False).step(a)[1].tolist() == [0.0, 0.0]
    with pytest.raises(ValueError, match="num_envs = 0"):
        E3dVectorEnv("two_rooms", 0)


def test_render_after_reset_is_the_bare_scene():
    # as E3dEnv: reset forgets the last step's commands
    vec = E3dVectorEnv("puck_rooms", 2, render_mode="rgb_array")
    bare = vec.scene.render().tolist()
    vec.reset(seed=0)
    assert [p.tolist() for p in vec.render()] == [bare, bare]
    vec.step(vec.scene.parse(["SEEEEES", "EEEEEEE"]))
    assert vec.render()[0].tolist() == vec.scene.render("SEEEEES").tolist() != bare
    vec.reset()
    assert [p.tolist() for p in vec.render()] == [bare, bare]
    vec.step(vec.scene.parse(["SEEEEES", "EEEEEEE"]))
    vec.reset(seed=[1, 2])
    assert [p.tolist() for p in vec.render()] == [bare, bare]


def test_num_envs_and_seeds_are_checked_with_their_names():
    for bad in (2**70, 2**64, E3dVectorEnv.MAX_NUM_ENVS + 1, 0, -1):
        with pytest.raises(ValueError, match=rf"^num_envs = {bad}: expected an integer from 1 to {E3dVectorEnv.MAX_NUM_ENVS}$"):
            E3dVectorEnv("two_rooms", bad)
    for bad in (True, np.bool_(True), 3.0, "3", None):
        with pytest.raises(TypeError, match=r"^num_envs: expected an integer, found"):
            E3dVectorEnv("two_rooms", bad)
    vec = E3dVectorEnv("two_rooms", 3)
    # gymnasium's list of seeds: one per copy
    for bad in ([], [1], [1, 2, 3, 4], ()):
        with pytest.raises(ValueError, match=rf"^seed: expected None, an integer or a list of num_envs = 3 seeds, found a list of {len(bad)}$"):
            vec.reset(seed=bad)
    with pytest.raises(TypeError, match=r"^seed: expected an integer, found bool"):
        vec.reset(seed=[1, True, 2])
    with pytest.raises(ValueError, match=r"^seed = 1180591620717411303424: expected an integer from 0 to 2\^64 - 1$"):
        vec.reset(seed=[0, 2**70, 0])
    with pytest.raises(TypeError, match=r"^seed: expected an integer, found bool"):
        vec.reset(seed=True)
    assert vec.reset(seed=[5, None, 7])[0].tolist() == [vec.scene.start_effect] * 3
    assert vec.reset(seed=(np.uint64(2**64 - 1), 0, 0))[0].tolist() == [vec.scene.start_effect] * 3
    for bad in ("no", 0):
        with pytest.raises(TypeError, match=r"^use_reward: expected True or False"):
            E3dVectorEnv("two_rooms", 2, use_reward=bad)
