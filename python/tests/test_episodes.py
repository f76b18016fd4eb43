"""Episodes from Python: scenes with start contexts and closed loops
(``run_episodes``, ``EpisodeWorld``, the Gymnasium environment on them),
against the CLI's ``e3d run --commands K [--closed-loop]``."""

import json

import numpy as np
import pytest

import e3d
from conftest import read_csv


def _check_against_cli(cli, tmp_path, rec, args):
    out = tmp_path / "cli"
    cli("run", *args, "--out", out)
    rows = read_csv((out / "trials.csv").read_text())
    summary = json.loads((out / "summary.json").read_text())
    scene = e3d.Scene.resolve(str(args[0]))
    k = rec.commands_per_episode
    assert len(rows) == len(rec.effects) == rec.episodes * k
    names = summary["start_contexts"]
    for j, row in enumerate(rows):
        assert int(row["episode"]) == j // k + 1 and int(row["command"]) == j % k + 1
        assert int(row["context"]) == rec.contexts[j]
        assert row["start"] == names[rec.starts[j // k]]
        assert row["symbols"] == scene.format(rec.commands[j])
        assert int(row["effect"]) == rec.effects[j]
        assert float(row["reward"]) == rec.rewards[j]
    (s,) = summary["sessions"]
    assert s["seed"] == rec.seed and s["episodes"] == rec.episodes
    assert s["first_reward_episode"] == rec.first_reward_episode
    assert s["cumulative_reward"] == rec.cumulative_reward
    assert s["entropy_per_start"] == rec.entropy_per_start
    assert summary["learner"] == rec.learner
    return summary


def test_start_contexts_equal_the_cli_bit_for_bit(cli, root, tmp_path):
    path = root / "scenes" / "two_rooms_contexts.ron"
    rec = e3d.run_episodes(path, episodes=400, seed=3)
    assert (rec.learner, rec.commands_per_episode, rec.episodes) == ("e3d", 1, 400)
    # both start contexts drawn, the observation being the start context
    assert set(rec.starts.tolist()) == {0, 1}
    assert rec.contexts.tolist() == rec.starts.tolist()
    summary = _check_against_cli(cli, tmp_path, rec, [path, "--trials", 400, "--seed", 3])
    assert summary["start_contexts"] == ["room_a", "room_b"]
    assert len(rec.entropy_per_start) == 2 and min(rec.entropy_per_start) > 0.5


@pytest.mark.parametrize("learner,name,first,total", [("e3d", "e3d_closed_loop", 65, 4.0),
                                                      ("egreedy", "qlearning", 128, 111.0)])
def test_closed_loop_equals_the_cli_bit_for_bit(cli, root, tmp_path, learner, name, first, total):
    # four_rooms with its reward cell moved to (2, 4), 6 moves from the
    # start, so that 300 episodes find it
    text = (root / "scenes" / "four_rooms.ron").read_text()
    near = tmp_path / "four_rooms_near.ron"
    near.write_text(text.replace("reward: (cells: [(2, 11)]", "reward: (cells: [(2, 4)]"))
    rec = e3d.run_episodes(near, episodes=300, commands=3, seed=5,
                           learner=learner, closed_loop=True)
    assert (rec.learner, rec.commands_per_episode) == (name, 3)
    assert (rec.first_reward_episode, rec.cumulative_reward) == (first, total)
    assert rec.commands.shape == (900, 5) and rec.commands.dtype == np.uint8
    # the observation is the current cell: each command after the first
    # starts where the last one ended
    eff = rec.effects.reshape(300, 3)
    ctx = rec.contexts.reshape(300, 3)
    assert (ctx[:, 1:] == eff[:, :-1]).all()
    assert (ctx[:, 0] == 0).all()  # the start cell (0, 0)
    # rewards only after an episode's last command
    assert (rec.rewards.reshape(300, 3)[:, :2] == 0).all()
    _check_against_cli(cli, tmp_path, rec, [near, "--trials", 300, "--commands", 3,
                                            "--closed-loop", "--learner", learner, "--seed", 5])


def test_seeds_run_in_parallel_equal_one_by_one():
    many = e3d.run_episodes("four_rooms", episodes=100, commands=2, seeds=[7, 8, 9])
    assert [r.seed for r in many] == [7, 8, 9]
    for r in many:
        one = e3d.run_episodes("four_rooms", episodes=100, commands=2, seed=r.seed)
        assert one.effects.tolist() == r.effects.tolist()
        assert one.commands.tolist() == r.commands.tolist()
    assert many[0].commands.tolist() != many[1].commands.tolist()


def test_episode_world_replays_run_episodes(root):
    path = root / "scenes" / "two_rooms_contexts.ron"
    rec = e3d.run_episodes(path, episodes=50, commands=2, seed=1)
    ew = e3d.EpisodeWorld(path, commands=2)
    assert (ew.observe, ew.num_contexts, ew.num_starts) == ("state", 18, 2)
    k = 2
    for i in range(rec.episodes):
        context = ew.reset(start=int(rec.starts[i]))
        assert ew.start == rec.starts[i]
        for j in range(k):
            assert context == rec.contexts[i * k + j]
            context, out, done = ew.step(rec.commands[i * k + j])
            assert out.effect == rec.effects[i * k + j]
            assert out.reward == rec.rewards[i * k + j]
            assert done == (j == k - 1)
    with pytest.raises(RuntimeError, match="call reset"):
        ew.step(rec.commands[0])


def test_three_commands_reach_the_far_room():
    ew = e3d.EpisodeWorld("four_rooms", commands=3)
    assert ew.reset(seed=0) == 0
    c1, o1, d1 = ew.step("SEEEE")
    assert (c1, o1.reward, d1) == (1 * 12 + 4, 0.0, False)
    c2, o2, d2 = ew.step("EEEEE")
    assert (c2, o2.reward, d2) == (1 * 12 + 9, 0.0, False)
    c3, o3, d3 = ew.step("EESEE")
    assert (c3, o3.reward, d3) == (2 * 12 + 11, 1.0, True)
    # the same cell in the middle of an episode is not rewarded
    ew = e3d.EpisodeWorld("four_rooms", commands=4)
    ew.reset()
    for c in ["SEEEE", "EEEEE", "EESEE"]:
        assert ew.step(c)[1].reward == 0.0
    assert ew.step("NNNNN")[1].reward == 0.0


def test_episode_world_pickles_mid_episode(root):
    import pickle

    ew = e3d.EpisodeWorld(root / "scenes" / "two_rooms_contexts.ron", commands=3)
    ew.reset(seed=4)
    ew.step("EEEEEEE")
    back = pickle.loads(pickle.dumps(ew))
    assert (back.commands, back.observe, back.start) == (3, "state", ew.start)
    for c in ["SSSSSSS", "WWWWWWW"]:
        a, b = ew.step(c), back.step(c)
        assert (a[0], a[1], a[2]) == (b[0], b[1], b[2])
    # the generator goes on with the same draws
    assert [ew.reset() for _ in range(30)] == [back.reset() for _ in range(30)]
    with pytest.raises(ValueError, match="EpisodeWorld: not a pickled state"):
        back.__setstate__("{}")


def test_bad_episode_arguments_name_what_was_expected(root):
    with pytest.raises(ValueError, match=r"observe = `cell`: expected None, \"start\""):
        e3d.run_episodes("four_rooms", observe="cell")
    with pytest.raises(ValueError, match="commands = 65: expected at most 64"):
        e3d.run_episodes("four_rooms", commands=65)
    with pytest.raises(ValueError, match="commands = 0"):
        e3d.EpisodeWorld("four_rooms", commands=0)
    with pytest.raises(ValueError, match="episodes = 0"):
        e3d.run_episodes("four_rooms", episodes=0)
    with pytest.raises(ValueError, match="episodes = 1000000000: expected at most 100000000"):
        e3d.run_episodes("four_rooms", episodes=10**9)
    with pytest.raises(ValueError, match="seed"):
        e3d.run_episodes("four_rooms", seed=-1)
    with pytest.raises(ValueError, match="closed loop takes learner e3d .* or egreedy .*, not count"):
        e3d.run_episodes("four_rooms", commands=3, closed_loop=True, learner="count")
    with pytest.raises(ValueError, match="start = 2: expected a start context in \\[0, 2\\)"):
        e3d.EpisodeWorld(root / "scenes" / "two_rooms_contexts.ron").reset(start=2)
    with pytest.raises(ValueError, match="takes continuous values"):
        e3d.run_episodes("arm7_continuous", commands=2)


gym = pytest.importorskip("gymnasium")


def test_gym_env_on_start_contexts_and_closed_loops(root):
    import warnings

    from gymnasium.utils.env_checker import check_env

    from e3d.gym import E3dEnv

    contexts = E3dEnv(root / "scenes" / "two_rooms_contexts.ron")
    assert contexts.observation_space.n == 2  # the start context
    multi = E3dEnv("four_rooms", commands=3)
    assert multi.observation_space.n == 36  # the current cell
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        check_env(contexts, skip_render_check=True)
        check_env(multi, skip_render_check=True)
        check_env(gym.make("e3d/E3d-v0", scene="four_rooms", commands=3).unwrapped)

    # an episode is K steps, rewarded after the last
    obs, info = multi.reset(seed=0)
    assert (obs, info["start"]) == (0, 0)
    steps = [multi.step(multi.scene.parse(c)[0]) for c in ["SEEEE", "EEEEE", "EESEE"]]
    assert [s[0] for s in steps] == [16, 21, 35]
    assert [s[1] for s in steps] == [0.0, 0.0, 1.0]
    assert [s[2] for s in steps] == [False, False, True]
    assert steps[2][4]["command"] == "EESEE"

    # the start contexts follow the seed: the same seed, the same starts
    def starts(seed, n=40):
        contexts.reset(seed=seed)
        out = []
        for _ in range(n):
            obs, info = contexts.reset()
            assert obs == info["start"]
            out.append(obs)
        return out

    a = starts(11)
    assert a == starts(11) and set(a) == {0, 1}
    assert a != starts(12)
    assert contexts.reset(options={"start": 1})[0] == 1

    # an environment on episodes pickles with its episode
    import pickle

    multi.reset(seed=2)
    multi.step(multi.scene.parse("SEEEE")[0])
    back = pickle.loads(pickle.dumps(multi))
    a = multi.scene.parse("EEEEE")[0]
    assert back.step(a)[:4] == multi.step(a)[:4]


def test_vector_env_refuses_episodes(root):
    from e3d.gym import E3dVectorEnv

    with pytest.raises(ValueError, match="has start contexts.*SyncVectorEnv"):
        E3dVectorEnv(root / "scenes" / "two_rooms_contexts.ron", 4)


class _PerContextE3d:
    """A contextual learner in Python: an E3dLearner per context."""

    name = "py_per_context"

    def __init__(self, scene, targets):
        self.ls = [e3d.E3dLearner(scene, target=t) for t in targets]
        self.seen = []

    def propose(self, context, rng):
        return self.ls[context].propose(rng)

    def learn(self, context, command, effect, reward, nxt):
        self.seen.append((context, nxt))
        self.ls[context].learn(command, effect, reward)


def test_python_contextual_learners_and_a_target_per_context(root):
    path = root / "scenes" / "two_rooms_contexts.ron"
    targets = [{(0, 0): 1.0, (1, 1): 1.0}, None]
    built_in = e3d.run_episodes(path, episodes=300, seed=3, targets=targets)
    shared = e3d.run_episodes(path, episodes=300, seed=3)
    py = _PerContextE3d(path, targets)
    rec = e3d.run_episodes(path, episodes=300, seed=3, learner=py)
    # the Python learner is the built-in one, bit for bit, with p*(e|s)
    assert rec.learner == "py_per_context"
    assert rec.effects.tolist() == built_in.effects.tolist()
    assert rec.commands.tolist() == built_in.commands.tolist()
    assert built_in.effects.tolist() != shared.effects.tolist()
    assert {c for c, _ in py.seen} == {0, 1} and all(n is None for _, n in py.seen)
    # one learner per seed
    many = e3d.run_episodes(path, episodes=50, seeds=[1, 2], learner=[_PerContextE3d(path, [None, None]) for _ in range(2)])
    assert [r.seed for r in many] == [1, 2]
    assert many[0].effects.tolist() == e3d.run_episodes(path, episodes=50, seed=1).effects.tolist()


def test_python_contextual_learner_errors(root):
    path = root / "scenes" / "two_rooms_contexts.ron"

    class Boom(_PerContextE3d):
        def learn(self, context, command, effect, reward, nxt):
            if len(self.seen) == 5:
                raise RuntimeError("boom at 5")
            super().learn(context, command, effect, reward, nxt)

    with pytest.raises(RuntimeError, match="boom at 5"):
        e3d.run_episodes(path, episodes=100, seed=1, learner=Boom(path, [None, None]))
    with pytest.raises(ValueError, match="1 targets for 2 contexts"):
        e3d.run_episodes(path, episodes=10, seed=1, targets=[None])
    with pytest.raises(ValueError, match="either target"):
        e3d.run_episodes(path, episodes=10, seed=1, target={0: 1.0}, targets=[None, None])
    with pytest.raises(ValueError, match="1 Python learners for 2 seeds"):
        e3d.run_episodes(path, episodes=10, seeds=[1, 2], learner=[_PerContextE3d(path, [None, None])])


def test_a_physics_episode_world_pickled_mid_episode_goes_on(root):
    # a physics state's Rapier snapshot is not pickled: the copy draws the
    # start again from the same generator and replays the episode's commands
    import copy
    import pickle
    ew = e3d.EpisodeWorld(root / "scenes" / "puck_contexts.ron", commands=3)
    ew.reset(seed=1)
    ew.step([0] * 7)
    copies = [pickle.loads(pickle.dumps(ew)), copy.deepcopy(ew)]
    rest = ([1] * 7, [2] * 7)
    mine = [(o.x, o.y, o.effect, d) for _, o, d in (ew.step(c) for c in rest)]
    for back in copies:
        assert [(o.x, o.y, o.effect, d) for _, o, d in (back.step(c) for c in rest)] == mine
    assert mine[-1][3]
