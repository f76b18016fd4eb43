"""The Stable-Baselines3 adapter (e3d.sb3): its stepping against
E3dVectorEnv always; against SB3's DummyVecEnv and with PPO when
stable_baselines3 is installed (it needs torch), skipped otherwise."""

import numpy as np
import pytest

pytest.importorskip("gymnasium")

import e3d  # noqa: E402
from e3d.gym import E3dEnv, E3dVectorEnv  # noqa: E402
from e3d.sb3 import E3dSB3VecEnv  # noqa: E402


def test_sb3_protocol_steps_the_vector_env():
    venv = E3dSB3VecEnv("puck_rooms", 3)
    ref = E3dVectorEnv("puck_rooms", 3)
    a = venv.venv.scene.parse(["SEEEEES", "EEEEEEE", "SSEEENN"])
    assert venv.num_envs == 3 and venv.action_space == ref.single_action_space
    assert venv.reset().tolist() == ref.reset(seed=0)[0].tolist()
    obs, rew, done, infos = venv.step(a)
    obs2, rew2, term2, _, infos2 = ref.step(a)
    assert obs.tolist() == obs2.tolist() and rew.dtype == np.float32
    assert rew.tolist() == rew2.astype(np.float32).tolist() and done.tolist() == [True] * 3
    assert [i["terminal_observation"] for i in infos] == infos2["final_obs"].tolist()
    assert [i["x"] for i in infos] == infos2["final_info"]["x"].tolist()
    assert all(i["TimeLimit.truncated"] is False for i in infos)
    assert venv.get_attr("use_reward") == [True] * 3 and venv.env_is_wrapped(object) == [False] * 3


def _sb3():
    return pytest.importorskip("stable_baselines3")


def test_sb3_vec_env_steps_as_dummy_vec_env():
    _sb3()
    from stable_baselines3.common.vec_env import DummyVecEnv
    venv = E3dSB3VecEnv("two_rooms", 4)
    dummy = DummyVecEnv([lambda: E3dEnv("two_rooms") for _ in range(4)])
    scene = e3d.Scene.builtin("two_rooms")
    a = scene.parse(["EEEEEES", "SSEEEEE", "NNNNNNN", "EESSEES"]).astype(np.int64)
    o1, o2 = venv.reset(), dummy.reset()
    assert o1.tolist() == o2.tolist()
    for _ in range(2):
        obs, rew, done, infos = venv.step(a)
        obs2, rew2, done2, infos2 = dummy.step(a)
        assert obs.tolist() == obs2.tolist() and rew.tolist() == rew2.tolist()
        assert done.tolist() == done2.tolist() == [True] * 4
        assert [i["terminal_observation"] for i in infos] == [i["terminal_observation"] for i in infos2]


def test_ppo_learns_a_few_steps():
    _sb3()
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback

    seen = []

    class Watch(BaseCallback):
        def _on_step(self):
            seen.append((np.array(self.locals["actions"]), self.locals["infos"],
                         np.array(self.locals["rewards"])))
            return True

    model = PPO("MlpPolicy", E3dSB3VecEnv("two_rooms", 8), n_steps=16, batch_size=64, seed=0, device="cpu")
    model.learn(256, callback=Watch())
    assert model.num_timesteps >= 256 and len(seen) == 32
    # what PPO was told of each step is what its commands did
    world = e3d.Scene.builtin("two_rooms").world()
    for actions, infos, rewards in seen:
        assert actions.shape == (8, 7)
        out = world.execute_batch(actions.astype(np.int64))
        assert [i["terminal_observation"] for i in infos] == out.effect.tolist()
        assert rewards.tolist() == out.reward.astype(np.float32).tolist()
    effects = {e for _, infos, _ in seen for e in (i["terminal_observation"] for i in infos)}
    assert len(effects) > 3


def test_discrete_actions_are_command_indices():
    venv = E3dSB3VecEnv("two_rooms", 3, discrete=True)
    scene = e3d.Scene.builtin("two_rooms")
    assert venv.action_space.n == scene.num_commands == 4**7
    # index i is the command of index i: slot 0 most significant
    cmds = venv.commands(np.array([0, 1, 4**7 - 1]))
    assert cmds.tolist() == [[0] * 7, [0] * 6 + [1], [3] * 7]
    venv.reset()
    a = np.array([5, 4**6 * 2 + 3, 12345])
    obs, rew, done, infos = venv.step(a)
    out = scene.world().execute_batch(venv.commands(a))
    assert [i["terminal_observation"] for i in infos] == out.effect.tolist()
    assert rew.tolist() == out.reward.astype(np.float32).tolist()
    with pytest.raises(ValueError, match="discrete=True: scene `arm7_continuous` has continuous commands"):
        E3dSB3VecEnv("arm7_continuous", 2, discrete=True)


def test_dqn_learns_a_few_steps_on_discrete_actions():
    _sb3()
    from stable_baselines3 import DQN
    from stable_baselines3.common.callbacks import BaseCallback

    seen = []

    class Watch(BaseCallback):
        def _on_step(self):
            seen.append((np.array(self.locals["actions"]), self.locals["infos"],
                         np.array(self.locals["rewards"])))
            return True

    venv = E3dSB3VecEnv("two_rooms", 4, discrete=True)
    model = DQN("MlpPolicy", venv, learning_starts=32, buffer_size=2000, batch_size=32,
                train_freq=1, seed=0, device="cpu")
    model.learn(256, callback=Watch())
    assert model.num_timesteps >= 256 and len(seen) == 64
    world = e3d.Scene.builtin("two_rooms").world()
    for actions, infos, rewards in seen:
        assert actions.shape == (4,)
        out = world.execute_batch(venv.commands(actions))
        assert [i["terminal_observation"] for i in infos] == out.effect.tolist()
        assert rewards.tolist() == out.reward.astype(np.float32).tolist()
    assert len({int(a) for actions, _, _ in seen for a in actions}) > 50


def test_discrete_actions_are_checked():
    from e3d.sb3 import E3dSB3VecEnv

    env = E3dSB3VecEnv("two_rooms", 4, discrete=True)
    env.reset()
    with pytest.raises(ValueError, match=r"^actions: expected one command index per environment \(4\)"):
        env.step(np.array([1, 2, 3]))
    with pytest.raises(ValueError, match=r"^actions: expected command indices from 0 to 16383"):
        env.step(np.array([0, 1, 2, 16384]))
    with pytest.raises(ValueError, match=r"^actions: expected command indices"):
        env.step(np.array([0.5, 1, 2, 3]))
    # commands() decodes any number of indices
    assert env.commands(np.arange(6)).shape == (6, 7)
