"""progress=callable on the long calls, and Ctrl-C (KeyboardInterrupt)."""

import faulthandler
import os
import signal
import threading
import time

import numpy as np
import pytest

import e3d


class Calls:
    def __init__(self):
        self.calls = []
        self.times = []

    def __call__(self, done, total):
        self.calls.append((done, total))
        self.times.append(time.perf_counter())

    def check(self, total):
        assert self.calls, "progress was never called"
        assert self.calls[-1] == (total, total)
        done = [d for d, _ in self.calls]
        assert done == sorted(done) and len(set(done)) == len(done)
        assert all(t == total for _, t in self.calls)
        # a modest rate: at most one call every 0.1 s, but the last
        gaps = np.diff(self.times[:-1])
        assert np.all(gaps >= 0.095), gaps


def test_run_session_progress():
    # an outcome table: millions of trials a second, so long enough to be seen
    p = Calls()
    rec = e3d.run_session("two_rooms", trials=4_000_000, seed=1, progress=p)
    p.check(4_000_000)
    assert len(p.calls) >= 2
    plain = e3d.run_session("two_rooms", trials=4_000_000, seed=1)
    assert np.array_equal(rec.effects, plain.effects)


def test_python_learner_progress():
    class Uniform:
        def propose(self, rng):
            return [rng.integers(4) for _ in range(7)]

        def learn(self, command, effect, reward):
            pass

    p = Calls()
    e3d.run_session("two_rooms", learner=Uniform(), trials=2000, progress=p)
    p.check(2000)


def test_run_sessions_progress():
    p = Calls()
    e3d.run_sessions("puck_rooms", trials=500, seeds=range(4), outcomes="live", progress=p)
    p.check(2000)


def test_execute_batch_progress():
    scene = e3d.Scene.builtin("puck_rooms")
    cmds = np.random.default_rng(0).integers(0, 4, size=(1500, 7)).astype(np.uint8)
    cmds = np.concatenate([cmds, cmds[:100]])
    p = Calls()
    out = scene.world().execute_batch(cmds, progress=p)
    p.check(1600)
    assert out.effect.tolist() == scene.world().execute_batch(cmds).effect.tolist()


def test_run_sweep_progress(root, monkeypatch):
    monkeypatch.chdir(root)
    p = Calls()
    sweep = {"scenes": ["scenes/puck_rooms.ron"], "learners": ["e3d", "uniform"],
             "sessions": 3, "trials": 400, "seed": 1}
    e3d.run_sweep(sweep, threads=2, progress=p)
    p.check(2 * 3 * 400)


def test_an_exception_from_progress_stops_the_call():
    def boom(done, total):
        raise ZeroDivisionError("from progress")

    start = time.perf_counter()
    with pytest.raises(ZeroDivisionError, match="from progress"):
        e3d.run_session("puck_rooms", trials=1_000_000, outcomes="live", progress=boom)
    with pytest.raises(ZeroDivisionError, match="from progress"):
        e3d.run_sessions("puck_rooms", trials=1_000_000, seeds=[0, 1], outcomes="live",
                         progress=boom)
    assert time.perf_counter() - start < 10


def test_progress_must_be_callable():
    with pytest.raises(TypeError, match="progress: expected a callable"):
        e3d.run_session("two_rooms", trials=10, progress=3)
    with pytest.raises(TypeError, match="progress: expected a callable"):
        e3d.run_session("two_rooms", learner=Uniform(), trials=10, progress="no")
    with pytest.raises(TypeError, match="progress: expected a callable"):
        e3d.Scene.builtin("two_rooms").world().execute_batch(["EEEEEEE"], progress=[])


class CtrlC:
    """Sends this process SIGINT (Ctrl-C) from another thread ``after``
    seconds into the ``with`` block. Bounded: should the call still run
    ``grace`` seconds later (that Ctrl-C lost: a bug, seen under heavy
    load), it prints every thread's Python stack and sends SIGINT every
    second until the block ends, so that the test fails on ``sent``
    instead of hanging. Within the block a Ctrl-C raises
    KeyboardInterrupt; one arriving as it ends is ignored (it would stop
    pytest itself)."""

    def __init__(self, after, grace=20.0):
        self.after, self.grace, self.sent = after, grace, 0
        self.done = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)

    def _kill(self):
        self.sent += 1
        os.kill(os.getpid(), signal.SIGINT)

    def _run(self):
        if self.done.wait(self.after):
            return
        self._kill()
        if self.done.wait(self.grace):
            return
        faulthandler.dump_traceback(all_threads=True)
        while not self.done.wait(1.0):
            self._kill()

    def _on_sigint(self, signum, frame):
        if not self.done.is_set():
            raise KeyboardInterrupt

    def __enter__(self):
        self.previous = signal.signal(signal.SIGINT, self._on_sigint)
        self.thread.start()
        return self

    def __exit__(self, *exc):
        self.done.set()
        self.thread.join()
        signal.signal(signal.SIGINT, self.previous)

    def check(self):
        assert self.sent == 1, (
            f"the first Ctrl-C did not stop the call: {self.sent} SIGINTs were sent, one every "
            f"second after {self.grace} s (the stacks are above)")


class Uniform:
    def propose(self, rng):
        return [rng.integers(4) for _ in range(7)]

    def learn(self, command, effect, reward):
        pass


@pytest.mark.parametrize(
    "call",
    [
        lambda: e3d.run_session("puck_rooms", trials=10_000_000, outcomes="live"),
        lambda: e3d.run_session("puck_rooms", learner=Uniform(), trials=10_000_000, outcomes="live"),
        lambda: e3d.run_sessions("puck_rooms", trials=10_000_000, seeds=range(3), outcomes="live"),
        lambda: e3d.Scene.builtin("puck_rooms14").world().execute_batch(
            np.random.default_rng(0).integers(0, 4, size=(200_000, 14))),
        lambda: e3d.run_sweep({"scenes": ["two_rooms"], "learners": ["e3d"],
                               "sessions": 100_000, "trials": 2000}, threads=2),
    ],
    ids=["run_session", "python_learner", "run_sessions", "execute_batch", "run_sweep"],
)
def test_ctrl_c_interrupts_long_calls(call):
    start = time.perf_counter()
    with CtrlC(0.5) as ctrl_c:
        with pytest.raises(KeyboardInterrupt):
            call()
    ctrl_c.check()
    assert time.perf_counter() - start < 5


def test_ctrl_c_stops_a_sweep_into_a_folder_and_resume_completes_it(tmp_path, cli):
    sweep = tmp_path / "s.ron"
    sweep.write_text('Sweep(scenes: ["two_rooms"], learners: [e3d, uniform], '
                     "sessions: 600, trials: 2000, seed: 3)\n")
    out = tmp_path / "py"

    def ctrl_c_once_started(done, total):
        # Ctrl-C as soon as some sessions are in the journal
        if done > 0:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        e3d.run_sweep(sweep, threads=2, out=out, progress=ctrl_c_once_started)
    assert (out / "journal.txt").exists() and not (out / "results.csv").exists()
    ran = sum(not line.startswith("#") for line in (out / "journal.txt").read_text().splitlines())
    assert 0 < ran < 1200
    p = Calls()
    cols = e3d.run_sweep(sweep, threads=2, out=out, resume=True, progress=p)
    # the sessions of the first run count as done from the start
    assert p.calls[0][0] >= ran * 2000 and p.calls[-1] == (1200 * 2000, 1200 * 2000)
    assert len(cols["seed"]) == 1200
    cli("sweep", sweep, "--out", tmp_path / "cli")
    for f in ["results.csv", "summary.csv"]:
        assert (out / f).read_bytes() == (tmp_path / "cli" / f).read_bytes(), f


@pytest.mark.parametrize("learner", ["e3d", "python"])
def test_ctrl_c_stops_a_table_build_and_leaves_no_table(tmp_path, learner):
    # arm7x5's table simulates 39063 commands (about a minute on two
    # cores): Ctrl-C half a second in stops the build itself, not the
    # session after it, so no table file is written into the cache (the
    # build ran to its end, wrote the table, then raised)
    cache = tmp_path / "cache"
    chosen = "e3d" if learner == "e3d" else Uniform()
    with CtrlC(0.5) as ctrl_c:
        with pytest.raises(KeyboardInterrupt):
            e3d.run_session("arm7x5", learner=chosen, trials=10, outcomes="table",
                            table_cache=cache)
    ctrl_c.check()
    left = sorted(p.name for p in cache.iterdir()) if cache.exists() else []
    assert not [n for n in left if n.endswith(".e3dtable") or ".tmp-" in n], left
