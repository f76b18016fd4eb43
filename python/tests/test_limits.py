"""Inputs at and past the limits: data that holds itself, counts whose
product exhausts memory, floats that must keep every bit, Ctrl-C before
the first array, and what a session's metrics must hold."""

import json
import re
import subprocess
import sys

import numpy as np
import pytest

import e3d


def test_data_that_holds_itself_is_a_scene_error():
    looped = []
    looped.append(looped)
    with pytest.raises(e3d.SceneError, match="nested more than 100 levels deep") as e:
        e3d.Scene.builtin("two_rooms").with_({"walls": looped})
    assert e.value.field.startswith("walls[0][0]")
    d = {}
    d["self"] = d
    with pytest.raises(e3d.SceneError, match="a dict or list that holds itself"):
        e3d.Scene.from_dict({"name": "x", "world": d})
    deep = 0
    for _ in range(30_000):
        deep = [deep]
    with pytest.raises(e3d.SceneError, match="nested more than 100 levels deep"):
        e3d.Scene.from_dict({"name": "x", "world": deep})


def test_overrides_keep_every_bit_of_a_float():
    scene = e3d.Scene.builtin("puck_rooms")
    rng = np.random.default_rng(0)
    for x in list(rng.uniform(0.1, 5.0, size=200)) + [2.5410453838964226]:
        s = scene.with_({"bodies.puck.linear_damping": float(x)})
        puck = [b for b in s.to_dict()["world"]["Physics"]["bodies"] if b["name"] == "puck"][0]
        assert puck["linear_damping"] == float(x)
        assert s == e3d.Scene.from_text(s.to_ron())
    with pytest.raises(e3d.SceneError, match="is out of range for any field"):
        e3d.Scene.builtin("two_rooms").with_({"rows": 2**70})


def test_counts_whose_records_would_exhaust_memory_are_refused():
    with pytest.raises(ValueError, match="at most 100000000 commands in all per session"):
        e3d.run_episodes("four_rooms", episodes=10**8, commands=64, seed=0)
    with pytest.raises(ValueError, match=r"sessions = 1000000000: expected at most 100000"):
        e3d.run_sessions("two_rooms", trials=1, sessions=10**9)
    with pytest.raises(ValueError, match="seeds: expected at most 100000 seeds"):
        e3d.run_sessions("two_rooms", trials=1, seeds=range(10**9))
    with pytest.raises(ValueError, match="give either seed or seeds"):
        e3d.run_episodes("two_rooms", episodes=3, seed=5, seeds=[1])
    with pytest.raises(ValueError, match="no session: expected at least one seed"):
        e3d.run_episodes("two_rooms", episodes=3, seeds=[])


def test_the_cli_refuses_episodes_past_the_cap(cli, tmp_path):
    r = cli("run", "four_rooms", "--trials", "100000000", "--commands", "64",
            "--out", str(tmp_path / "out"), check=False)
    assert r.returncode != 0 and "at most 100000000 commands in all per session" in r.stderr
    assert not (tmp_path / "out").exists()


def test_on_trials_on_a_continuous_scene_is_refused():
    with pytest.raises(ValueError, match="on_trials: scene `arm7_continuous` is continuous"):
        e3d.run_session("arm7_continuous", trials=20, on_trials=lambda *a: None)


def test_metrics_hold_every_metric_of_summary_json(cli, tmp_path):
    cli("run", "two_rooms", "--trials", "300", "--seed", "5", "--out", str(tmp_path))
    summary = json.loads((tmp_path / "summary.json").read_text())
    rec = e3d.run_session("two_rooms", trials=300, seed=5)
    batch = e3d.run_sessions("two_rooms", trials=300, seeds=[5])
    assert batch.metrics["coverage"][0] == summary["coverage"]
    assert batch.metrics["trials_to_50_percent"][0] == summary["trials_to_50_percent"]
    for m in (rec.metrics, batch[0].metrics):
        for k, v in m.items():
            assert summary.get(k) == v, k  # None where summary.json leaves it out (qd_score)
        for k in ("coverage", "coverage_cells", "trials_to_50_percent", "trials_to_90_percent",
                  "discovery_trials", "normalized_entropy_reachable"):
            assert k in m, k


def test_ctrl_c_in_a_new_process_during_run_episodes_is_keyboard_interrupt(root):
    # before any array was made (numpy's C API then imported on first use
    # raised the pending KeyboardInterrupt as a Rust panic), and
    # run_episodes checks for Ctrl-C while it runs
    # bounded: should that Ctrl-C be lost (a bug, seen under heavy load),
    # the child prints its threads' stacks 20 s later, sends SIGINT every
    # second for 10 s, prints the stacks again and exits with status 3,
    # so the test fails with what the child was doing instead of hanging
    code = (
        "import faulthandler, os, signal, sys, threading, e3d\n"
        # started with SIGINT ignored (a background shell's), Python leaves it so
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "sent, done = [], threading.Event()\n"
        "def ctrl_c():\n"
        "    if done.wait(0.3): return\n"
        "    sent.append(1); os.kill(os.getpid(), signal.SIGINT)\n"
        "    if done.wait(20): return\n"
        "    faulthandler.dump_traceback(all_threads=True)\n"
        "    for _ in range(10):\n"
        "        if done.wait(1): return\n"
        "        sent.append(1); os.kill(os.getpid(), signal.SIGINT)\n"
        "    print(len(sent), 'SIGINTs sent, none stopped run_episodes', file=sys.stderr)\n"
        "    faulthandler.dump_traceback(all_threads=True)\n"
        "    os._exit(3)\n"
        "threading.Thread(target=ctrl_c, daemon=True).start()\n"
        "try:\n"
        f"    e3d.run_episodes({str(root / 'scenes' / 'puck_contexts.ron')!r}, episodes=10**7, seed=1)\n"
        "except KeyboardInterrupt:\n"
        "    done.set()\n"
        "    print('interrupted', len(sent))\n"
    )
    try:
        r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    except subprocess.TimeoutExpired as e:
        pytest.fail(f"the child did not end in 120 s (not even by its own exit); its stderr:\n{e.stderr}")
    assert r.stdout.strip() == "interrupted 1", f"status {r.returncode}; stderr:\n{r.stderr}"
    assert "Panic" not in r.stderr and "panicked" not in r.stderr


@pytest.mark.parametrize("call,name", [
    (lambda v: e3d.run_session("two_rooms", trials=v), "trials"),
    (lambda v: e3d.run_session("two_rooms", trials=5, seed=v), "seed"),
    (lambda v: e3d.run_session("two_rooms", trials=5, every=v, on_trials=lambda *a: None), "every"),
    (lambda v: e3d.run_sessions("two_rooms", trials=5, sessions=v), "sessions"),
    (lambda v: e3d.SessionRng(v), "seed"),
    (lambda v: e3d.Scene.builtin("two_rooms").world(v), "prefix_states"),
    (lambda v: e3d.EpisodeWorld("four_rooms", commands=v), "commands"),
    (lambda v: e3d.run_episodes("four_rooms", episodes=v), "episodes"),
])
def test_a_bool_or_an_array_is_no_integer(call, name):
    for v in (True, np.True_, np.zeros(3), np.array([2])):
        with pytest.raises(TypeError) as e:
            call(v)
        # named once: `argument 'trials': ...` (pyo3's prefix) or `trials: ...`
        assert re.match(rf"(argument '{name}': |{name}: )expected an integer, found",
                        str(e.value)), str(e.value)
    call(np.int64(2))  # numpy integers are


def test_messages_name_what_python_calls_them():
    with pytest.raises(ValueError, match=r"^lambda_ = -1"):
        e3d.run_session("two_rooms", trials=5, lambda_=-1.0)
    with pytest.raises(ValueError, match="policy of slot 0: 2 probabilities given, the slot has 4 symbols"):
        e3d.E3dLearner("two_rooms").set_policy(0, [0.5, 0.5])
    with pytest.raises(TypeError, match="effect_model"):
        e3d.E3dLearner("two_rooms").effect_model = "x"
    with pytest.raises(TypeError, match="^scene: expected a Scene, or a scene file's path"):
        e3d.run_session(1.5, trials=5)


def test_a_records_metrics_are_a_copy():
    rec = e3d.run_session("two_rooms", trials=20)
    rec.metrics["trials"] = -1
    assert rec.metrics["trials"] == 20
    batch = e3d.run_sessions("two_rooms", trials=20, seeds=[1, 2])
    batch.metrics["trials"] = None
    assert batch.metrics["trials"].tolist() == [20, 20]


def test_a_uint64_symbol_past_2_63_is_named_as_it_is():
    w = e3d.Scene.builtin("two_rooms").world()
    with pytest.raises(ValueError, match="symbol 9223372036854775808 at slot 0 is out of range"):
        w.execute(np.full(7, 2**63, np.uint64))
    with pytest.raises(ValueError, match="symbol -1 at slot 0 is out of range"):
        w.execute(np.full(7, -1, np.int64))


def test_choice_says_when_its_weights_overflow():
    rng = e3d.SessionRng(0)
    with pytest.raises(ValueError, match="the weights sum past the largest float"):
        rng.choice([1e308, 1e308])
    with pytest.raises(ValueError, match="expected finite weights >= 0, not all 0"):
        rng.choice([float("nan"), 1.0])
    assert rng.choice([0.0, 1e308]) == 1


def test_records_held_in_all_and_context_tables_are_capped():
    with pytest.raises(ValueError, match="trials and sessions: 100000 sessions of 100000000 trials"):
        e3d.run_sessions("two_rooms", trials=10**8, sessions=100_000)
    with pytest.raises(ValueError, match="episodes, commands and seeds"):
        e3d.run_episodes("four_rooms", episodes=10**6, commands=64, seeds=range(1000))
    big = e3d.Scene.builtin("two_rooms").with_(
        {"world.Grid.rows": 256, "world.Grid.cols": 256, "world.Grid.walls": []})
    with pytest.raises(ValueError, match="tables over 65536 contexts x 65536 effects: at most 4194304"):
        e3d.run_episodes(big, episodes=3, commands=2, observe="state", seed=0)
    with pytest.raises(ValueError, match="tables over 65536 contexts x 65536 effects"):
        e3d.Learner.contextual(big, "count", commands=2, observe="state")


def test_pickled_states_that_do_not_fit_are_refused():
    sc = e3d.Scene.builtin("arm7")
    m = sc.world().trace(sc.parse("+++++++")[0])
    f, (st,) = m.__reduce__()
    st = list(st)
    st[2] = st[2] + ["extra"]
    with pytest.raises(ValueError, match="Motion: not a pickled state"):
        f(tuple(st))
    ew = e3d.EpisodeWorld("four_rooms", commands=2)
    ew.reset(seed=0)
    cls, args, state = ew.__reduce__()
    bad = json.loads(state)
    bad["start"] = 999
    with pytest.raises(ValueError, match="EpisodeWorld: not a pickled state: start 999"):
        cls(*args).__setstate__(json.dumps(bad))


def test_more_arguments_named_as_python_names_them(root):
    with pytest.raises(ValueError, match=r"^lambda_ = NaN"):
        e3d.E3dLearner("two_rooms", lambda_=float("nan"))
    ctx = e3d.Learner.contextual(root / "scenes" / "two_rooms_contexts.ron")
    with pytest.raises(TypeError, match="next: expected an integer, found float"):
        ctx.learn(0, [0] * 7, 0, 0.0, 1.5)
    with pytest.raises(ValueError, match=r"key True is not an effect"):
        e3d.Learner("two_rooms", target={True: 1.0})
    batch = e3d.run_sessions("two_rooms", trials=5, seeds=[1, 2])
    for bad in (True, np.array([1])):
        with pytest.raises(TypeError, match="session index: expected an integer"):
            batch[bad]
    assert batch[np.int64(1)].seed == 2
    with pytest.raises(ValueError, match="command: value NaN at slot 2: expected finite numbers"):
        e3d.Learner("arm7_continuous").learn([0, 0, float("nan"), 0, 0, 0, 0], 1, 0.0)


def test_a_session_batch_state_whose_commands_do_not_fit_is_refused():
    import pickle
    batch = e3d.run_sessions("two_rooms", trials=5, seeds=[1, 2])
    assert pickle.loads(pickle.dumps(batch))[1].commands.tolist() == batch[1].commands.tolist()
    f, (st,) = batch.__reduce__()
    st = list(st)
    st[4] = {"not": "an array"}
    with pytest.raises(ValueError, match="SessionBatch: not a pickled state: commands of 2 sessions x 5 trials"):
        f(tuple(st))


def _float_arguments():
    """Every (callable, parameter) of the package with a float default."""
    import inspect
    found = set()
    for name in dir(e3d):
        obj = getattr(e3d, name)
        if name.startswith("_") or not callable(obj):
            continue
        members = [(name, obj)]
        if inspect.isclass(obj):
            members += [(f"{name}.{m}", getattr(obj, m)) for m in dir(obj) if not m.startswith("_")]
        for qual, f in members:
            try:
                params = inspect.signature(f).parameters.values()
            except (TypeError, ValueError):
                continue
            found |= {(qual, p.name) for p in params if isinstance(p.default, float)}
    return found


def test_an_int_too_large_for_a_float_is_a_value_error_naming_the_argument(root):
    # Python's own conversion raises a bare OverflowError for 10**400; every
    # float argument takes it as an infinity and refuses it by name
    contexts = root / "scenes" / "two_rooms_contexts.ron"
    calls = {
        "E3dLearner": lambda **kw: e3d.E3dLearner("two_rooms", **kw),
        "E3dLearner.contextual": lambda **kw: e3d.E3dLearner.contextual(contexts, **kw),
        "Learner": lambda **kw: e3d.Learner("two_rooms", **kw),
        "Learner.contextual": lambda **kw: e3d.Learner.contextual(contexts, **kw),
        "Scene.render": lambda **kw: e3d.Scene.builtin("two_rooms").render(**kw),
        "run_episodes": lambda **kw: e3d.run_episodes(contexts, episodes=2, closed_loop=True, **kw),
        "run_session": lambda **kw: e3d.run_session("two_rooms", trials=2, **kw),
        "run_sessions": lambda **kw: e3d.run_sessions("two_rooms", trials=2, sessions=2, **kw),
    }
    arguments = _float_arguments()
    # a new float argument must be added to `calls`
    assert {q for q, _ in arguments} == set(calls)
    assert len(arguments) == 50
    for qual, name in sorted(arguments):
        for big in (10**400, -10**400):
            with pytest.raises(ValueError, match=rf"^{name} = -?inf: expected"):
                calls[qual](**{name: big})
    # a reward and a target weight too
    with pytest.raises(ValueError, match=r"^reward = inf: expected a finite number"):
        e3d.Learner("two_rooms").learn([0] * 7, 0, 10**400)
    with pytest.raises(ValueError, match=r"target"):
        e3d.Learner("two_rooms", target={0: 10**400})
    # and anything but a number is a TypeError naming the argument once
    for qual, name in sorted(arguments):
        with pytest.raises(TypeError) as e:
            calls[qual](**{name: "x"})
        assert re.fullmatch(rf"(argument '{name}': |{name}: )expected a number, found str",
                            str(e.value)), (qual, str(e.value))


def test_gamma_is_checked_open_loop_too(root):
    # the open loop has no discount, but a gamma out of [0, 1] is a mistake
    # either way: refused, not silently ignored
    contexts = root / "scenes" / "two_rooms_contexts.ron"
    with pytest.raises(ValueError, match=r"^gamma = 7: expected a number in \[0, 1\]"):
        e3d.Learner.contextual(contexts, gamma=7.0)
    with pytest.raises(ValueError, match=r"^gamma = 7: expected a number in \[0, 1\]"):
        e3d.run_episodes(contexts, episodes=2, gamma=7.0)
    with pytest.warns(UserWarning, match="gamma = 0.5 does nothing"):
        assert e3d.Learner.contextual(contexts, gamma=0.5) is not None


def test_a_hyper_parameter_the_learner_does_not_read_is_a_warning(root):
    import warnings
    contexts = root / "scenes" / "two_rooms_contexts.ron"
    cases = [
        (lambda: e3d.run_session("two_rooms", trials=5, learner="uniform", alpha=0.5),
         "alpha = 0.5 does nothing: learner uniform reads no hyper-parameter"),
        (lambda: e3d.run_sessions("two_rooms", trials=5, sessions=2, learner="egreedy", beta=3.0),
         "beta = 3 does nothing: learner egreedy reads alpha, epsilon"),
        (lambda: e3d.run_session("two_rooms", trials=5, epsilon=0.5),
         "epsilon = 0.5 does nothing: learner e3d reads alpha, beta, lambda_, eta"),
        (lambda: e3d.Learner("two_rooms", learner="count", eta=0.5),
         "eta = 0.5 does nothing: learner count reads alpha, beta, lambda_"),
        (lambda: e3d.run_session("two_rooms", trials=5, k=3),
         "k = 3 does nothing: learner e3d reads alpha, beta, lambda_, eta"),
        (lambda: e3d.run_session("two_rooms", trials=5, learner="archive", goal_progress=0.5),
         "goal_progress = 0.5 does nothing: learner archive reads k, sigma, rarity"),
        (lambda: e3d.run_session("two_rooms", trials=5, learner=e3d.Learner("two_rooms"), alpha=0.9),
         "alpha = 0.9 does nothing: an e3d.Learner keeps the parameters it was made with"),
        (lambda: e3d.run_episodes(contexts, episodes=3, gamma=0.5),
         "gamma = 0.5 does nothing: the open loop has no discount"),
        (lambda: e3d.Learner.contextual(contexts, gamma=0.5),
         "gamma = 0.5 does nothing: the open loop has no discount"),
    ]
    for call, message in cases:
        with pytest.warns(UserWarning, match=message) as record:
            call()
        assert len(record) == 1
        assert record[0].filename == __file__  # the caller's line
    # defaults, and the parameters a learner reads: no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        e3d.run_session("two_rooms", trials=5, learner="uniform")
        e3d.run_session("two_rooms", trials=5, alpha=0.5, lambda_=0.1)
        e3d.run_session("two_rooms", trials=5, learner="egreedy", epsilon=0.2)
        e3d.run_episodes(contexts, episodes=3, closed_loop=True, gamma=0.5)
