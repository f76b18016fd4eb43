import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")
from gymnasium.utils.env_checker import check_env  # noqa: E402

import e3d  # noqa: E402
from e3d.gym import E3dEnv  # noqa: E402


def test_import_e3d_does_not_import_gymnasium():
    import subprocess
    import sys

    code = "import sys, e3d; assert 'gymnasium' not in sys.modules; print('ok')"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.stdout.strip() == "ok", r.stderr


@pytest.mark.parametrize("name", e3d.Scene.builtins())
def test_check_env_passes_on_every_shipped_scene(name):
    import warnings

    env = E3dEnv(e3d.Scene.builtin(name))
    with warnings.catch_warnings():
        # a warning of the checker is a failure too
        warnings.simplefilter("error")
        check_env(env, skip_render_check=True)
        # through gymnasium.make: a spec, so the render modes are checked too
        made = gym.make("e3d/E3d-v0", scene=name)
        check_env(made.unwrapped)
        made.reset(seed=0)
        made.step(made.action_space.sample())
    if env.scene.is_continuous:
        assert env.action_space.shape == (env.scene.num_slots,)
        assert (env.action_space.low.tolist(), env.action_space.high.tolist()) == (
            [-1.0] * env.scene.num_slots, [1.0] * env.scene.num_slots)
    else:
        assert env.action_space.nvec.tolist() == env.scene.alphabet_sizes
    assert env.observation_space.n == env.scene.num_effects


def test_box_actions_on_a_continuous_scene():
    env = E3dEnv("arm7_continuous")
    env.reset(seed=0)
    lo = np.array([r[0] for r in env.scene.value_ranges])
    hi = np.array([r[1] for r in env.scene.value_ranges])
    assert env.values_of(np.full(7, -1.0)).tolist() == lo.tolist()
    assert env.values_of(np.full(7, 1.0)).tolist() == hi.tolist()
    assert env.values_of(np.full(7, 5.0)).tolist() == hi.tolist()
    assert env.values_of(np.zeros(7)).tolist() == ((lo + hi) / 2).tolist()
    action = np.array([1.0, -1.0, 0.5, 0, 0, 0, 0], dtype=np.float32)
    obs, reward, terminated, truncated, info = env.step(action)
    want = env.world.execute(info["values"])
    assert (int(obs), info["x"], info["y"]) == (want.effect, want.x, want.y)
    assert info["values"][:3].tolist() == [1.8, -1.2, lo[2] + 1.5 * 0.5 * (hi[2] - lo[2])]
    assert terminated and not truncated


def test_one_episode_is_one_command():
    env = E3dEnv("two_rooms")
    obs, info = env.reset(seed=0)
    assert obs == 0 and info == {}
    action = env.scene.parse("SEEEEES")[0]
    obs, reward, terminated, truncated, info = env.step(action)
    assert (obs, reward, terminated, truncated) == (17, 1.0, True, False)
    assert info["command"] == "SEEEEES" and (info["x"], info["y"]) == (5.5, 0.5)
    assert env.observation_space.contains(obs)


def test_no_reward_and_sampled_actions():
    env = E3dEnv("two_rooms", use_reward=False)
    env.reset(seed=1)
    env.action_space.seed(1)
    for _ in range(50):
        obs, reward, terminated, _, _ = env.step(env.action_space.sample())
        assert reward == 0.0 and terminated


def test_reset_is_deterministic_and_steps_match_the_world():
    env = E3dEnv("puck_rooms")
    a, _ = env.reset(seed=5)
    b, _ = env.reset(seed=5)
    assert a == b == env.scene.start_effect
    cmds = np.random.default_rng(0).integers(0, 4, size=(20, 7)).astype(np.uint8)
    out = env.scene.world().execute_batch(cmds)
    for c, e, r in zip(cmds, out.effect, out.reward):
        env.reset()
        obs, reward, *_ = env.step(c)
        assert (obs, reward) == (e, r)


def test_bad_actions_raise_value_error():
    env = E3dEnv("two_rooms")
    env.reset()
    with pytest.raises(ValueError):
        env.step([0, 0, 0])
    with pytest.raises(ValueError):
        env.step([9] * 7)


def test_render_modes_are_none_and_rgb_array():
    env = E3dEnv("two_rooms", render_mode=None)
    assert env.render_mode is None and env.metadata["render_modes"] == ["rgb_array"]
    assert env.render() is None
    assert E3dEnv("two_rooms", render_mode="rgb_array").render().shape[2] == 3


def test_rgb_array_render():
    from e3d.gym import E3dEnv, E3dVectorEnv
    env = E3dEnv("puck_rooms", render_mode="rgb_array")
    env.reset(seed=0)
    bare = env.render()
    env.step(env.scene.parse("SEEEEES")[0])
    drawn = env.render()
    assert bare.shape[2] == 3 and drawn.dtype == np.uint8
    assert drawn.tolist() == env.scene.render("SEEEEES").tolist()
    assert E3dEnv("puck_rooms").render() is None and bare.shape == env.scene.render().shape
    with pytest.raises(ValueError, match="render_mode = 'human'"):
        E3dEnv("puck_rooms", render_mode="human")
    venv = E3dVectorEnv("puck_rooms", 2, render_mode="rgb_array")
    venv.reset(seed=0)
    venv.step(venv.scene.parse(["SEEEEES", "EEEEEEE"]))
    pics = venv.render()
    assert len(pics) == 2 and pics[0].tolist() == drawn.tolist()


def test_commands_is_an_integer_checked_as_the_others():
    # None is the default (1), as elsewhere; a float, a str or a bool is refused
    assert E3dEnv("arm7_continuous", commands=None).episodes is None
    assert E3dEnv("two_rooms", commands=None).episodes is None
    assert E3dEnv("arm7_continuous", commands=np.int64(1)).episodes is None
    assert E3dEnv("two_rooms", commands=np.int64(2)).episodes.commands == 2
    for scene in ("arm7_continuous", "two_rooms"):
        for bad in (1.9, "1", True, 1.0):
            with pytest.raises(TypeError, match=r"^commands: expected an integer, found"):
                E3dEnv(scene, commands=bad)
    with pytest.raises(ValueError, match="takes continuous values: its episodes are one command"):
        E3dEnv("arm7_continuous", commands=2)


def test_values_of_on_a_scene_of_symbols_says_it_takes_symbols():
    with pytest.raises(ValueError, match=r"^values_of: scene `two_rooms` takes symbols"):
        E3dEnv("two_rooms").values_of(np.zeros(7))
    env = E3dEnv("arm7_continuous")
    assert env.values_of(np.ones(7)).tolist() == [hi for _, hi in env.scene.value_ranges]
    with pytest.raises(TypeError, match=r"^rows: expected True or False"):
        env.values_of(np.zeros((2, 7)), rows="yes")


def test_use_reward_is_a_bool():
    for bad in ("no", 0, 1, None, "False"):
        with pytest.raises(TypeError, match=r"^use_reward: expected True or False, found"):
            E3dEnv("two_rooms", use_reward=bad)
    assert E3dEnv("two_rooms", use_reward=np.False_).use_reward is False
    env = E3dEnv("two_rooms", use_reward=False)
    env.reset()
    assert env.step(env.scene.parse("SEEEEES")[0])[1] == 0.0


def test_reset_options_and_start_are_checked(root):
    env = E3dEnv(str(root / "scenes" / "two_rooms_contexts.ron"))
    assert env.reset(seed=0, options={"start": np.int64(1)})[1] == {"start": 1}
    for bad in (True, 1.0, "1"):
        with pytest.raises(TypeError, match=r"^start: expected an integer, found"):
            env.reset(options={"start": bad})
    with pytest.raises(TypeError, match=r"^options: expected None or a dict"):
        env.reset(options=[1])
    with pytest.raises(ValueError, match=r"^start = 5"):
        env.reset(options={"start": 5})


@pytest.mark.parametrize("name", ["two_rooms", "arm7_continuous"])
def test_check_env_warns_as_docs_python_says(name):
    # docs/python.md: no warning on make(...).unwrapped nor on a bare E3dEnv
    # with skip_render_check=True; one of the checker's own warnings each
    # on a bare E3dEnv (no spec) and on make's wrapped environment
    import warnings

    def warned(env, **kw):
        with warnings.catch_warnings(record=True) as w:
            warnings.simplefilter("always")
            check_env(env, **kw)
        return [str(x.message) for x in w]

    assert warned(gym.make("e3d/E3d-v0", scene=name).unwrapped) == []
    assert warned(E3dEnv(name), skip_render_check=True) == []
    bare = warned(E3dEnv(name))
    assert len(bare) == 1 and "Not able to test alternative render modes due to the environment not having a spec" in bare[0]
    wrapped = warned(gym.make("e3d/E3d-v0", scene=name))
    assert len(wrapped) == 1 and "is different from the unwrapped version" in wrapped[0]
