"""Errors as Python users expect them: ValueError naming the argument,
every built-in learner listed, SceneError's parts as attributes, and no
Rust panic reaching Python."""

import threading

import numpy as np
import pytest

import e3d

# the library's LearnerKind::ALL, in its order
LEARNERS = ["e3d", "uniform", "egreedy", "e3d_relax", "count", "smm", "goal_babbling", "archive",
            "archive_reached", "map_elites", "qlearning_moves"]


@pytest.mark.parametrize("kw, match", [
    ({"seed": -1}, r"^seed = -1: expected an integer from 0 to 2\^64 - 1$"),
    ({"seed": 2**64}, r"^seed = 18446744073709551616: expected an integer from 0"),
    ({"trials": -5}, r"^trials = -5: expected an integer from 1"),
    ({"trials": 0}, r"^trials = 0: expected an integer from 1"),
])
def test_run_session_integer_arguments_raise_value_error_naming_them(kw, match):
    with pytest.raises(ValueError, match=match):
        e3d.run_session("two_rooms", trials=kw.pop("trials", 10), **kw)


def test_integer_arguments_of_the_wrong_type_raise_type_error():
    # the package checks them once, each message naming the keyword once
    with pytest.raises(TypeError, match=r"^seed: expected an integer, found str$"):
        e3d.run_session("two_rooms", trials=10, seed="1")
    with pytest.raises(TypeError, match=r"^trials: expected an integer, found float$"):
        e3d.run_session("two_rooms", trials=10.0)
    with pytest.raises(TypeError, match=r"^seeds\[1\]: expected an integer, found str$"):
        e3d.run_sessions("two_rooms", trials=10, seeds=[1, "2"])
    with pytest.raises(TypeError, match=r"^alpha: expected a number, found str$"):
        e3d.run_session("two_rooms", trials=10, alpha="1")
    # numpy integers are integers
    rec = e3d.run_session("two_rooms", trials=np.int64(10), seed=np.uint64(3))
    assert (rec.trials, rec.seed) == (10, 3)


def test_run_sessions_integer_arguments():
    with pytest.raises(ValueError, match=r"^seeds\[1\] = -2: expected an integer from 0"):
        e3d.run_sessions("two_rooms", trials=10, seeds=[0, -2])
    with pytest.raises(ValueError, match=r"^sessions = -2: expected an integer from 1"):
        e3d.run_sessions("two_rooms", trials=10, sessions=-2)
    with pytest.raises(ValueError, match=r"^seed = -1: "):
        e3d.run_sessions("two_rooms", trials=10, sessions=2, seed=-1)
    with pytest.raises(TypeError, match=r"^seeds: expected a sequence of integers, found int$"):
        e3d.run_sessions("two_rooms", trials=10, seeds=3)


def test_run_sweep_threads():
    with pytest.raises(ValueError, match=r"^threads = -1: expected an integer from 1"):
        e3d.run_sweep({"scenes": ["two_rooms"], "learners": ["e3d"], "sessions": 1, "trials": 10},
                      threads=-1)


def test_empty_batches_are_refused_alike():
    world = e3d.Scene.builtin("two_rooms").world()
    msgs = []
    for empty in ([], np.zeros((0, 7), dtype=np.uint8), np.zeros((0, 7), dtype=np.int64), ()):
        with pytest.raises(ValueError, match="commands: an empty batch") as err:
            world.execute_batch(empty)
        msgs.append(str(err.value))
    assert "expected at least one command" in msgs[0]
    assert world.memo_len == 0


def test_rng_integers_argument():
    class L:
        def __init__(self, n):
            self.n = n

        def propose(self, rng):
            rng.integers(self.n)
            return [0] * 7

        def learn(self, *a):
            pass

    with pytest.raises(ValueError, match=r"^n = -3: expected an integer from 1"):
        e3d.run_session("two_rooms", learner=L(-3), trials=3)
    with pytest.raises(ValueError, match=r"^n = 0: "):
        e3d.run_session("two_rooms", learner=L(0), trials=3)


def test_unknown_learner_lists_every_builtin_learner():
    with pytest.raises(ValueError) as err:
        e3d.run_session("two_rooms", learner="nope", trials=10)
    msg = str(err.value)
    assert msg.startswith("unknown learner `nope`; expected one of: ")
    assert msg.split(": ", 1)[1].split(", ") == LEARNERS
    with pytest.raises(TypeError) as err:
        e3d.run_session("two_rooms", learner=object(), trials=10)
    listed = ", ".join(f'"{n}"' for n in LEARNERS)
    assert f"learner: expected one of {listed} or an object with propose" in str(err.value)
    with pytest.raises(TypeError) as err:
        e3d.run_sessions("two_rooms", learner=3, trials=10, sessions=2)
    assert f"expected one of {listed} or a sequence of Python learners" in str(err.value)
    # every listed learner runs: per-move Q-learning in episodes only
    for name in LEARNERS[:-1]:
        assert e3d.run_session("two_rooms", learner=name, trials=20).learner == name
    with pytest.raises(ValueError, match=r"^learner `qlearning_moves` chooses each move"):
        e3d.run_session("two_rooms", learner="qlearning_moves", trials=20)
    rec = e3d.run_episodes("two_rooms", episodes=20, learner="qlearning_moves", seed=0)
    assert rec.commands_per_episode == 7  # the 7 moves of a two_rooms command, one by one


def test_scene_error_attributes_of_a_syntax_error():
    with pytest.raises(e3d.SceneError) as err:
        e3d.Scene.from_text('Scene(name: "x", wrold: Grid(rows: 1))', "x.ron")
    e = err.value
    assert (e.file, e.line, e.column, e.field) == ("x.ron", 1, 18, "wrold")
    assert str(e).startswith("x.ron:1:18: unknown field `wrold`")
    # every RON mistake that is about a field names it; one that is not, None
    cases = [
        ('Scene(name: 3)', "name", "field `name`: expected string"),
        ('Scene(name: "x", name: "y")', "name", "field `name` given twice"),
        ('Scene(name: "x", world: Grid(rows: 1, cols: 2, start: (0, 0)))', "command", "missing field `command`"),
        ('Scene(name: "x", world: Grdi(rows: 1))', "world", "unknown variant `Grdi`"),
        ('Scene(', None, "unexpected end of RON"),
        ('[1, 2]', None, "expected opening `(` for struct `Scene`"),
    ]
    for text, field, message in cases:
        with pytest.raises(e3d.SceneError) as err:
            e3d.Scene.from_text(text, "x.ron")
        assert err.value.field == field and message in str(err.value), (text, str(err.value))


def test_scene_error_attributes_of_an_invalid_value(tmp_path):
    bad = tmp_path / "bad.ron"
    bad.write_text('Scene(\n    name: "x",\n    world: Grid(rows: 3, cols: 6, start: (0, 0), walls: []),\n'
                   '    command: Repeat(slots: 7, alphabet: [(symbol: \'E\', action: Move(drow: 0, dcol: 1)),'
                   ' (symbol: \'E\', action: Idle)]),\n)\n')
    with pytest.raises(e3d.SceneError) as err:
        e3d.Scene.load(bad)
    e = err.value
    assert e.file == str(bad)
    assert e.line == 4 and isinstance(e.column, int) and e.column > 1
    assert isinstance(e.field, str) and e.field
    assert str(e).startswith(f"{bad}:4:{e.column}: ")


def test_scene_error_attributes_without_position():
    with pytest.raises(e3d.SceneError) as err:
        e3d.Scene.builtin("nope")
    assert (err.value.file, err.value.line, err.value.column, err.value.field) == ("nope", None, None, None)
    with pytest.raises(e3d.SceneError) as err:
        e3d.Scene.from_text("  ", "blank.ron")
    assert (err.value.file, err.value.line) == ("blank.ron", None)
    # raised from Python, the attributes exist too
    e = e3d.SceneError("mine")
    assert (e.file, e.line, e.column, e.field) == (None, None, None, None)


def test_sweep_error_attributes():
    with pytest.raises(e3d.SceneError) as err:
        e3d.run_sweep('Sweep(\n    scenes: ["two_rooms"],\n    learners: [e3d, nope],\n    sessions: 1,\n    trials: 10,\n)\n')
    assert (err.value.file, err.value.line) == ("<string>", 3)
    assert err.value.column >= 20


def test_session_rng_kept_after_propose_raises_runtime_error():
    kept = []

    class Keeper:
        def propose(self, rng):
            kept.append(rng)
            return [rng.integers(4) for _ in range(7)]

        def learn(self, *a):
            pass

    e3d.run_session("two_rooms", learner=Keeper(), trials=3)
    with pytest.raises(RuntimeError, match="SessionRng used outside the propose"):
        kept[0].random()


def test_session_rng_from_another_thread_is_no_panic():
    errors = []

    class Threaded:
        def propose(self, rng):
            out = []
            t = threading.Thread(target=lambda: out.append(rng.integers(4)))
            t.start()
            t.join()
            return [out[0]] + [0] * 6

        def learn(self, *a):
            pass

    class Late:
        """Hands the generator to a thread that uses it after propose returned."""
        def propose(self, rng):
            def late():
                try:
                    rng.random()
                except RuntimeError as e:
                    errors.append(e)
            self.t = threading.Thread(target=late)
            return [0] * 7

        def learn(self, *a):
            self.t.start()
            self.t.join()

    class SameThread:
        def propose(self, rng):
            return [rng.integers(4)] + [0] * 6

        def learn(self, *a):
            pass

    # within the call, another thread may draw: the same draws as on this one
    rec = e3d.run_session("two_rooms", learner=Threaded(), trials=50, seed=4)
    same = e3d.run_session("two_rooms", learner=SameThread(), trials=50, seed=4)
    assert rec.commands.tolist() == same.commands.tolist()
    assert len(set(rec.commands[:, 0].tolist())) == 4
    assert rec.trials == 50
    e3d.run_session("two_rooms", learner=Late(), trials=3)
    assert len(errors) == 3 and all("outside the propose" in str(e) for e in errors)


@pytest.mark.parametrize("call", [
    lambda: e3d.run_session("two_rooms", trials=10**12),
    lambda: e3d.run_sessions("two_rooms", trials=10**12, seeds=range(2)),
])
def test_trials_are_capped_as_on_the_command_line(call):
    # 10**12 trials once aborted the interpreter (a record of every trial)
    with pytest.raises(ValueError, match=r"^trials = 1000000000000: expected at most 100000000"):
        call()


def test_environment_seeds_and_vector_actions_raise_errors_naming_them():
    from e3d.gym import E3dEnv, E3dVectorEnv

    for env in (E3dEnv("puck_rooms"), E3dVectorEnv("puck_rooms", 4)):
        with pytest.raises(ValueError, match=r"^seed = -1: expected an integer from 0 to 2\^64 - 1$"):
            env.reset(seed=-1)
        with pytest.raises(ValueError, match=r"^seed = 18446744073709551616: expected an integer"):
            env.reset(seed=2**64)
        with pytest.raises(TypeError, match=r"^seed: expected an integer, found float$"):
            env.reset(seed=1.5)
        env.reset(seed=np.uint64(7))
    venv = E3dVectorEnv("puck_rooms", 4)
    venv.reset(seed=0)
    for shape in [(3, 7), (5, 7), (7,), (4,)]:
        with pytest.raises(ValueError, match=r"^actions: expected one action per environment, "
                                             r"an array of shape \[4, 7\], found shape"):
            venv.step(np.zeros(shape, dtype=np.uint8))
    # the slots of each row are the world's to check
    with pytest.raises(ValueError, match="expected an array of shape \\[N, 7\\]"):
        venv.step(np.zeros((4, 6), dtype=np.uint8))


def test_continuous_actions_of_the_wrong_shape_or_not_finite_raise_value_error():
    from e3d.gym import E3dEnv, E3dVectorEnv

    env = E3dEnv("arm7_continuous")
    env.reset(seed=0)
    for bad in [np.zeros(3), np.zeros((2, 7)), np.zeros(()), np.zeros(8)]:
        with pytest.raises(ValueError, match=r"^action: expected 7 values in \[-1, 1\] \(one per slot\)"):
            env.step(bad)
    with pytest.raises(ValueError, match=r"^action: expected finite values in \[-1, 1\], found nan$"):
        env.step(np.full(7, np.nan))
    venv = E3dVectorEnv("arm7_continuous", 2)
    venv.reset(seed=0)
    with pytest.raises(ValueError, match=r"^action: expected 7 values"):
        venv.step(np.zeros((2, 6)))
    with pytest.raises(ValueError, match=r"^actions: expected one action per environment"):
        venv.step(np.zeros((3, 7)))


def test_every_integer_argument_names_itself_when_negative_or_huge():
    # no OverflowError reaches the user: each integer argument is checked
    # and named, as seed and trials are
    l = e3d.E3dLearner("two_rooms")
    cmd = np.zeros(7, dtype=np.uint8)
    calls = {
        "slot": [lambda v: l.set_q(v, [0.0] * 4), lambda v: l.set_policy(v, [0.25] * 4)],
        "effect": [lambda v: l.learn(cmd, v, 0.0)],
        "every": [lambda v: e3d.run_session("two_rooms", trials=10, every=v)],
    }
    for name, fs in calls.items():
        for f in fs:
            for v in (-1, 2**64):
                with pytest.raises(ValueError, match=rf"^{name} = {v}: expected an integer from"):
                    f(v)
            # named once: pyo3 prefixes a TypeError of an argument it reads
            # with "argument 'NAME': ", the others name it themselves
            with pytest.raises(TypeError,
                               match=rf"^(argument '{name}': |{name}: )expected an integer, found float$"):
                f(1.5)


def test_learn_refuses_a_reward_that_is_not_a_finite_number():
    l = e3d.E3dLearner("two_rooms")
    cmd = np.zeros(7, dtype=np.uint8)
    for bad in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match=r"^reward = (NaN|inf): expected a finite number$"):
            l.learn(cmd, 0, bad)
    with pytest.raises(TypeError, match=r"^reward: expected a number, found str$"):
        l.learn(cmd, 0, "1")
    before = l.to_bytes()
    l.learn(cmd, 3, 1.0)
    assert l.to_bytes() != before


def test_contextual_learn_checks_context_effect_and_reward(root):
    l = e3d.Learner.contextual(e3d.Scene.load(root / "scenes" / "two_rooms_contexts.ron"))
    cmd = np.zeros(7, dtype=np.uint8)
    with pytest.raises(ValueError, match=r"^context = -1: expected an integer from 0"):
        l.learn(-1, cmd, 0, 0.0)
    with pytest.raises(ValueError, match=r"^context 5: expected a context in \[0, 2\)$"):
        l.learn(5, cmd, 0, 0.0)
    with pytest.raises(ValueError, match=r"^effect = -1: expected an integer from 0"):
        l.learn(0, cmd, -1, 0.0)
    with pytest.raises(ValueError, match=r"^reward = NaN: expected a finite number$"):
        l.learn(0, cmd, 0, float("nan"))
    with pytest.raises(ValueError, match=r"^next = -2: expected an integer from 0"):
        l.learn(0, cmd, 0, 0.0, -2)


def test_session_batch_indices_of_any_size():
    b = e3d.run_sessions("two_rooms", trials=10, seeds=[0, 1])
    assert b[-1].seed == 1 and b[0].seed == 0
    for i in (2, -3, 2**70, -(2**70)):
        with pytest.raises(IndexError, match=rf"^session {i} out of range: 2 sessions$"):
            b[i]
    with pytest.raises(TypeError, match=r"^session index: expected an integer or a slice, found str$"):
        b["0"]


def test_callables_scenes_and_env_counts_are_checked_before_any_work():
    from e3d.gym import E3dEnv, E3dVectorEnv

    with pytest.raises(TypeError, match=r"^on_trials: expected a callable, on_trials\(first, commands, effects, rewards\), found int$"):
        e3d.run_session("two_rooms", trials=10, on_trials=5)
    for bad in (3, 2.5, None):
        with pytest.raises(TypeError, match=r"^scene: expected a Scene, or a scene file's path or a built-in scene's name, found"):
            E3dEnv(bad)
    for bad in (2.5, "4", True):
        with pytest.raises(TypeError, match=r"^num_envs: expected an integer, found"):
            E3dVectorEnv("two_rooms", bad)
    assert E3dVectorEnv("two_rooms", np.int64(3)).num_envs == 3


def test_a_table_cache_that_is_a_file_is_refused(tmp_path):
    f = tmp_path / "afile"
    f.write_text("x")
    with pytest.raises(ValueError, match=r"^table_cache = .*afile: exists and is not a folder"):
        e3d.run_session("puck_rooms", trials=10, table_cache=f)
    with pytest.raises(ValueError, match=r"^table_cache = .*afile: exists and is not a folder"):
        e3d.run_sessions("puck_rooms", trials=10, seeds=[0, 1], table_cache=f)
    with pytest.raises(ValueError, match=r"^table_cache = .*afile: exists and is not a folder"):
        e3d.run_sweep({"scenes": ["two_rooms"], "learners": ["e3d"], "sessions": 1, "trials": 10},
                      table_cache=f)
    assert f.read_text() == "x"


def test_sb3_adapter_arguments_are_checked_with_their_names():
    pytest.importorskip("gymnasium")
    from e3d.gym import E3dVectorEnv
    from e3d.sb3 import E3dSB3VecEnv

    with pytest.raises(ValueError, match=r"^num_envs = 1180591620717411303424: expected an integer from 1 to"):
        E3dSB3VecEnv("two_rooms", 2**70)
    with pytest.raises(TypeError, match=r"^num_envs: expected an integer, found bool"):
        E3dSB3VecEnv("two_rooms", True)
    for bad in ("yes", 1, None):
        with pytest.raises(TypeError, match=r"^discrete: expected True or False, found"):
            E3dSB3VecEnv("two_rooms", 2, discrete=bad)
    with pytest.raises(TypeError, match=r"^use_reward: expected True or False, found str"):
        E3dSB3VecEnv("two_rooms", 2, use_reward="no")
    assert E3dSB3VecEnv("two_rooms", 2, discrete=np.True_).discrete is True
    venv = E3dSB3VecEnv("two_rooms", 3)
    assert venv.get_attr("use_reward", np.int64(2)) == [True]
    assert venv.get_attr("use_reward", [0, np.int64(2)]) == [True, True]
    assert venv.get_attr("use_reward", []) == []
    for bad in (True, 1.0, "0", [0, True]):
        with pytest.raises(TypeError, match=r"^indices: expected an integer, found"):
            venv.get_attr("use_reward", bad)
    for bad in (3, -1, 2**70, [0, 3]):
        with pytest.raises(ValueError, match=r"^indices: -?\d+ is no copy's index: expected integers from 0 to 2$"):
            venv.env_is_wrapped(object, bad)
    assert E3dVectorEnv.MAX_NUM_ENVS == 1 << 20


def test_docs_python_lists_the_learners_as_the_library_does(root):
    # docs/python.md quotes the unknown-learner message and names the
    # learners that run on a continuous scene: both as the library says
    import re

    text = " ".join((root / "docs" / "python.md").read_text().split())
    with pytest.raises(ValueError) as e:
        e3d.run_session("two_rooms", learner="nope", trials=1)
    assert f"(`{e.value}`)" in text
    with pytest.raises(ValueError) as e:
        e3d.run_session("arm7_continuous", learner="egreedy", trials=1)
    assert str(e.value) in text
    section = text[text.index("### Continuous scenes"):text.index("## Worlds")]
    runs = re.search(r"`run_sessions` take (.*?); the learners of symbols only \((.*?)\) raise", section)
    assert runs, section
    take, refuse = (re.findall(r'"(\w+)"', part) for part in runs.groups())
    assert sorted(take + refuse) == sorted(LEARNERS)
    for name in take:
        assert len(e3d.run_sessions("arm7_continuous", learner=name, trials=3, seeds=[0, 1])) == 2
    for name in refuse:
        with pytest.raises(ValueError, match=rf"^learner `{name}` takes symbols; continuous commands take one of: "
                                             + ", ".join(take) + "$"):
            e3d.run_session("arm7_continuous", learner=name, trials=3)
