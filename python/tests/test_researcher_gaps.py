"""What a researcher found missing: the terminal point for Python
learners, EpisodeRecord.metrics, the SB3 env's render_mode and commands,
Scene.with_ on the scene's optional fields, Motion.columns without the
still bodies, errors naming the user's propose, E3D's final state in
run_sessions' records, and run_sweep's shards."""

import importlib.util
import pickle

import numpy as np
import pytest

import e3d
from e3d.sb3 import E3dSB3VecEnv


class Points:
    """A uniform learner whose learn takes the terminal point."""

    def __init__(self, sizes):
        self.sizes, self.seen = sizes, []

    def propose(self, rng):
        return [rng.integers(k) for k in self.sizes]

    def learn(self, command, effect, reward, point=None):
        self.seen.append((command.copy(), effect, point))


def test_python_learner_learn_receives_the_terminal_point():
    scene = e3d.Scene.builtin("puck_rooms")
    p = Points(scene.alphabet_sizes)
    e3d.run_session(scene, learner=p, trials=20, seed=1)
    world = scene.world()
    assert len(p.seen) == 20
    for command, effect, point in p.seen:
        out = world.execute(command)
        assert point == (out.x, out.y) and effect == out.effect


def test_learn_without_point_is_called_as_before_and_kwargs_get_it():
    class Three:
        def propose(self, rng):
            return "EEEEEEE"

        def learn(self, command, effect, reward):
            self.n = getattr(self, "n", 0) + 1

    class Kw:
        def propose(self, rng):
            return "EEEEEEE"

        def learn(self, command, effect, reward, **kw):
            self.kw = kw

    t, k = Three(), Kw()
    e3d.run_session("two_rooms", learner=t, trials=5)
    e3d.run_session("two_rooms", learner=k, trials=5)
    assert t.n == 5
    # a grid's point: the centre of the terminal cell
    out = e3d.Scene.builtin("two_rooms").world().execute("EEEEEEE")
    assert k.kw == {"point": (out.x, out.y)}


def test_contextual_python_learner_receives_the_point():
    class Ctx:
        def __init__(self):
            self.points = []

        def propose(self, context, rng):
            return [rng.integers(4) for _ in range(5)]

        def learn(self, context, command, effect, reward, next, point=None):
            self.points.append(point)

    c = Ctx()
    e3d.run_episodes("four_rooms", episodes=10, commands=2, learner=c, seed=3)
    assert len(c.points) == 20 and all(isinstance(p, tuple) and len(p) == 2 for p in c.points)


def test_propose_errors_name_the_users_method():
    class Floats:
        def propose(self, rng):
            return [0.5] * 7

        def learn(self, command, effect, reward):
            pass

    with pytest.raises(ValueError, match=r"^Floats\.propose\(rng\) returned a bad command: "):
        e3d.run_session("two_rooms", learner=Floats(), trials=3)

    class Far:
        def propose(self, context, rng):
            return [9] * 5

        def learn(self, context, command, effect, reward, next):
            pass

    with pytest.raises(ValueError, match=r"^Far\.propose\(context, rng\) returned .*out of range"):
        e3d.run_episodes("four_rooms", episodes=3, learner=Far())


def test_episode_record_metrics_are_a_session_records_over_terminal_effects():
    rec = e3d.run_episodes("four_rooms", episodes=300, commands=2, seed=5)
    m = rec.metrics
    session = e3d.run_session("two_rooms", trials=10, seed=0).metrics
    assert set(m) == set(session)
    ends = rec.effects[1::2]
    assert m["trials"] == rec.episodes == 300
    assert m["distinct_effects"] == len(set(ends.tolist()))
    assert m["coverage"] == m["distinct_effects"] / m["coverage_cells"]
    assert m["cumulative_reward"] == pytest.approx(rec.cumulative_reward)
    counts = np.bincount(ends, minlength=rec.num_effects) / len(ends)
    nz = counts[counts > 0]
    assert m["normalized_entropy"] == pytest.approx(-(nz * np.log(nz)).sum() / np.log(rec.num_effects))
    first = rec.first_reward_episode
    assert m["first_reward_trial"] == first
    assert m["discovery_trials"][0] == 1
    rec.metrics["trials"] = 0  # a copy
    assert rec.metrics["trials"] == 300
    assert pickle.loads(pickle.dumps(rec)) == rec


def test_sb3_env_takes_render_mode():
    venv = E3dSB3VecEnv("two_rooms", 3, render_mode="rgb_array")
    venv.reset()
    venv.step(np.zeros((3, 7), dtype=np.int64))
    images = venv.get_images()
    assert len(images) == 3 and all(im.dtype == np.uint8 and im.ndim == 3 for im in images)
    tiled = venv.render()
    assert tiled.ndim == 3 and tiled.shape[0] >= images[0].shape[0]
    assert E3dSB3VecEnv("two_rooms", 2).render() is None
    with pytest.raises(ValueError, match="render_mode"):
        E3dSB3VecEnv("two_rooms", 2, render_mode="human")


def test_sb3_env_takes_commands():
    venv = E3dSB3VecEnv("four_rooms", 2, commands=2, render_mode="rgb_array")
    obs = venv.reset()
    assert obs.shape == (2,) and obs.dtype == np.int64
    obs, rewards, dones, infos = venv.step(np.zeros((2, 5), dtype=np.int64))
    assert not dones.any() and all("terminal_observation" not in i for i in infos)
    obs, rewards, dones, infos = venv.step(np.zeros((2, 5), dtype=np.int64))
    assert dones.all() and all("terminal_observation" in i for i in infos)
    assert len(venv.get_images()) == 2
    # one command: the batched env as before
    one = E3dSB3VecEnv("four_rooms", 2, commands=1)
    assert one.envs is None
    with pytest.raises(ValueError, match="continuous"):
        E3dSB3VecEnv("arm7_continuous", 2, commands=2)


def test_scene_with_sets_the_scenes_optional_fields():
    scene = e3d.Scene.builtin("two_rooms")
    assert scene.with_({"slots": 7}).num_slots == 7
    # `slots` checks the number of slots; `command.slots` changes it
    with pytest.raises(e3d.SceneError, match="slots"):
        scene.with_({"slots": 15})
    assert scene.with_({"command.slots": 15, "slots": 15}).num_slots == 15
    with pytest.raises(e3d.SceneError, match="set `slots` whole"):
        scene.with_({"slots.x": 1})


def test_motion_columns_without_the_still_bodies():
    tr = e3d.Scene.builtin("puck_rooms").world().trace("SEEEEES")
    assert len(tr.columns()) == 44
    still = tr.still_bodies()
    assert len(still) == 6 and "puck" not in still
    cols = tr.columns(still=False)
    assert list(cols) == ["step", "time"] + [f"puck.{f}" for f in ("x", "y", "angle", "vx", "vy", "omega")]
    with pytest.raises(TypeError, match="still"):
        tr.columns(still="no")


def test_run_sessions_records_keep_e3ds_final_state():
    batch = e3d.run_sessions("two_rooms", trials=300, seeds=[3, 4])
    for i, seed in enumerate([3, 4]):
        alone = e3d.run_session("two_rooms", trials=300, seed=seed)
        assert batch[i] == alone
        assert batch[i].q is not None and batch[i].effect_model is not None
        assert batch[i].policy_effect_distribution is not None
    assert batch[1:][0] == batch[1]
    assert pickle.loads(pickle.dumps(batch)) == batch
    # learners without them: None, as run_session gives
    u = e3d.run_sessions("two_rooms", learner="uniform", trials=50, seeds=[1])
    assert u[0].q is None and u[0] == e3d.run_session("two_rooms", learner="uniform", trials=50, seed=1)


SWEEP = {"scenes": ["two_rooms"], "learners": ["e3d", "uniform"], "sessions": 3, "trials": 200,
         "seed": 9}
FILES = ["results.csv", "summary.csv", "sweep.ron", "version.txt", "journal.txt"]


def test_run_sweep_shards_merge_to_one_process_bytes(tmp_path):
    one = e3d.run_sweep(SWEEP, threads=1, out=tmp_path / "one")
    a = e3d.run_sweep(SWEEP, threads=1, out=tmp_path / "s1", shard=(1, 2))
    b = e3d.run_sweep(SWEEP, threads=1, out=tmp_path / "s2", shard="2/2")
    assert len(a["seed"]) + len(b["seed"]) == len(one["seed"]) == 6
    merged = e3d.merge_sweeps([tmp_path / "s1", tmp_path / "s2"], tmp_path / "merged")
    assert merged["seed"].tolist() == one["seed"].tolist()
    for f in FILES:
        assert (tmp_path / "merged" / f).read_bytes() == (tmp_path / "one" / f).read_bytes(), f


def test_run_sweep_shard_arguments():
    with pytest.raises(ValueError, match="give out="):
        e3d.run_sweep(SWEEP, shard=(1, 2))
    with pytest.raises(ValueError, match="1 <= K <= N"):
        e3d.run_sweep(SWEEP, shard=(3, 2), out="x")
    with pytest.raises(ValueError, match="1 <= K <= N"):
        e3d.run_sweep(SWEEP, shard="0/2", out="x")
    with pytest.raises(TypeError, match="shard"):
        e3d.run_sweep(SWEEP, shard=2, out="x")


@pytest.mark.skipif(importlib.util.find_spec("submitit") is None, reason="submitit is not installed")
def test_run_sweep_shards_as_a_submitit_job_array(tmp_path):
    import submitit

    executor = submitit.LocalExecutor(folder=tmp_path / "logs")
    shards = [(k, 2) for k in (1, 2)]
    dirs = [tmp_path / f"shard{k}" for k, _ in shards]
    jobs = executor.map_array(lambda s, d: len(e3d.run_sweep(SWEEP, threads=1, out=d, shard=s)["seed"]),
                              shards, dirs)
    assert sum(j.result() for j in jobs) == 6
    e3d.merge_sweeps(dirs, tmp_path / "merged")
    e3d.run_sweep(SWEEP, threads=1, out=tmp_path / "one")
    for f in FILES:
        assert (tmp_path / "merged" / f).read_bytes() == (tmp_path / "one" / f).read_bytes(), f
