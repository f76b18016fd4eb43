import threading

import numpy as np
import pytest

import e3d

from conftest import read_csv


def random_commands(scene, n, seed):
    rng = np.random.default_rng(seed)
    cols = [rng.integers(0, k, size=n) for k in scene.alphabet_sizes]
    return np.stack(cols, axis=1).astype(np.uint8)


def cli_exec(cli, scene_name, commands_text):
    r = cli("scene", "exec", scene_name, "-", input="\n".join(commands_text) + "\n")
    return read_csv(r.stdout)


@pytest.mark.parametrize("name", [n for n in e3d.Scene.builtins() if not e3d.Scene.builtin(n).is_continuous])
def test_execute_batch_equals_scene_exec_bit_for_bit(cli, name):
    scene = e3d.Scene.builtin(name)
    cmds = random_commands(scene, 200, seed=1)
    cmds = np.concatenate([cmds, cmds[:20]])  # repeats: looked up, not simulated
    out = scene.world().execute_batch(cmds)
    assert len(out) == len(cmds)
    assert out.effect.dtype == np.int64
    assert out.reward.dtype == out.x.dtype == out.y.dtype == np.float64
    rows = cli_exec(cli, name, scene.format(cmds))
    assert [r["command"] for r in rows] == scene.format(cmds)
    assert out.effect.tolist() == [int(r["effect"]) for r in rows]
    # the CLI prints the shortest text that reads back as the same f64
    assert out.reward.tolist() == [float(r["reward"]) for r in rows]
    assert out.x.tolist() == [float(r["x"]) for r in rows]
    assert out.y.tolist() == [float(r["y"]) for r in rows]


def test_execute_one_command():
    scene = e3d.Scene.builtin("two_rooms")
    w = scene.world()
    o = w.execute("SEEEEES")
    assert (o.effect, o.reward) == (2 * 6 + 5, 1.0)
    assert (o.x, o.y) == (5.5, 0.5)
    assert w.execute(np.array([1, 0, 0, 0, 0, 0, 1], dtype=np.uint8)) == o
    assert w.execute([1, 0, 0, 0, 0, 0, 1]) == o


@pytest.mark.parametrize("name", ["puck_rooms", "swimmer", "cart_pole"])
def test_prefix_states_give_the_bits_of_every_step(cli, name):
    # one command at a time: the default world starts commands that share
    # a prefix from the state kept; prefix_states=0 simulates every step;
    # both equal `e3d scene exec` bit for bit
    scene = e3d.Scene.builtin(name)
    base = random_commands(scene, 40, seed=4)
    cmds = np.concatenate([base, base[:, ::-1]])  # shared prefixes, both ways
    cmds[40:, :3] = base[:40, :3]
    reusing, plain = scene.world(), scene.world(prefix_states=0)
    assert (reusing.prefix_states, plain.prefix_states) == (2048, 0)
    a = [reusing.execute(c) for c in cmds]
    b = [plain.execute(c) for c in cmds]
    assert a == b
    rows = cli_exec(cli, name, scene.format(cmds))
    assert [o.x for o in a] == [float(r["x"]) for r in rows]
    assert [o.effect for o in a] == [int(r["effect"]) for r in rows]


def test_prefix_states_must_be_a_count():
    scene = e3d.Scene.builtin("puck_rooms")
    with pytest.raises(ValueError, match="prefix_states"):
        scene.world(prefix_states=-1)
    assert scene.world(prefix_states=None).prefix_states == 2048


def test_the_memo_keeps_each_command_once():
    scene = e3d.Scene.builtin("puck_rooms")
    w = scene.world()
    cmds = random_commands(scene, 50, seed=2)
    first = w.execute_batch(cmds)
    n = w.memo_len
    assert n == len({bytes(r) for r in cmds})
    again = w.execute_batch(cmds[::-1])
    assert w.memo_len == n
    assert again.effect.tolist() == first.effect[::-1].tolist()
    assert again.x.tolist() == first.x[::-1].tolist()


def test_a_batch_of_known_and_new_commands():
    # the known commands are looked up, the new ones simulated in even
    # pieces: the outcomes of a new world, in order, each kept once
    scene = e3d.Scene.builtin("puck_rooms")
    cmds = random_commands(scene, 120, seed=5)
    w = scene.world()
    w.execute_batch(cmds[::3])
    mixed = w.execute_batch(cmds)
    fresh = scene.world().execute_batch(cmds)
    assert mixed.effect.tolist() == fresh.effect.tolist()
    assert mixed.x.tolist() == fresh.x.tolist()
    assert mixed.y.tolist() == fresh.y.tolist()
    assert w.memo_len == len({bytes(r) for r in cmds})
    done = []
    again = w.execute_batch(np.concatenate([cmds, random_commands(scene, 40, seed=6)]),
                            progress=lambda d, t: done.append((d, t)))
    assert done[-1] == (160, 160)
    assert again.effect[:120].tolist() == fresh.effect.tolist()


def test_batches_of_one_new_command_give_the_bits_of_every_step():
    # each call below holds one new command (the others known): it runs on
    # the world of `execute`, whose prefix states serve the later ones
    scene = e3d.Scene.builtin("puck_rooms")
    cmds = random_commands(scene, 24, seed=7)
    cmds[12:, :4] = cmds[:12, :4]  # shared prefixes
    w = scene.world()
    last = [w.execute_batch(cmds[: k + 1]) for k in range(len(cmds))][-1]
    plain = scene.world(prefix_states=0)
    every = [plain.execute(c) for c in cmds]
    assert last.x.tolist() == [o.x for o in every]
    assert last.y.tolist() == [o.y for o in every]
    assert last.effect.tolist() == [o.effect for o in every]
    assert w.memo_len == len({bytes(r) for r in cmds})
    # a lone new command of arm7, whose mirror image is known, is looked up
    arm = e3d.Scene.builtin("arm7")
    a = arm.world()
    a.execute_batch(arm.parse(["-++++--", "0000000"]))
    out = a.execute_batch(arm.parse(["+----++", "0+0-0+0"]))
    assert out.x.tolist() == [arm.world().execute(c).x for c in ["+----++", "0+0-0+0"]]
    assert a.memo_len == 3


def test_mirror_images_share_an_entry_and_stay_exact():
    # arm7 declares a FlipY symmetry: a command and its mirror image are one entry
    scene = e3d.Scene.builtin("arm7")
    w = scene.world()
    cmds = scene.parse(["-++++--", "+----++", "0000000", "+0-0+0-"])
    out = w.execute_batch(cmds)
    fresh = [scene.world().execute(c) for c in cmds]
    assert out.effect.tolist() == [o.effect for o in fresh]
    assert out.x.tolist() == [o.x for o in fresh]
    assert out.y.tolist() == [o.y for o in fresh]
    assert w.memo_len == 3


def test_lists_of_strings_and_other_integer_dtypes():
    scene = e3d.Scene.builtin("two_rooms")
    w = scene.world()
    a = w.execute_batch(["EESSEES", "SEEEEES"])
    b = w.execute_batch(scene.parse(["EESSEES", "SEEEEES"]).astype(np.int64))
    assert a.effect.tolist() == b.effect.tolist()
    c = w.execute_batch(scene.parse(["EESSEES", "SEEEEES"])[:, ::1].T.T)  # non-contiguous ok
    assert c.effect.tolist() == a.effect.tolist()


def test_empty_batch():
    # refused as `[]` is (tests/test_errors.py checks the message)
    scene = e3d.Scene.builtin("puck_rooms")
    with pytest.raises(ValueError, match="commands: an empty batch"):
        scene.world().execute_batch(np.zeros((0, 7), dtype=np.uint8))


@pytest.mark.parametrize(
    "bad, message",
    [
        (np.zeros(7, dtype=np.uint8), r"expected an array of shape \[N, 7\].*1 dimension"),
        (np.zeros((2, 6), dtype=np.uint8), r"found shape \[2, 6\]: the scene's commands have 7 slots"),
        (np.zeros((2, 7, 1), dtype=np.uint8), r"3 dimension"),
        (np.zeros((2, 7), dtype=np.float64), r"integer array.*found dtype float64"),
        (np.zeros((2, 7), dtype=bool), r"integer array.*found dtype"),
        (np.full((2, 7), 4, dtype=np.uint8), r"row 0: symbol 4 at slot 0 is out of range: slot 0 has 4 symbols \(ESWN\)"),
        (np.array([[0] * 7, [0] * 6 + [-1]]), r"row 1: symbol -1 at slot 6 is out of range"),
        ([[0, 1], [1]], r"expected commands as an integer array"),
        (["EESSEES", "EES"], r"command `EES` has 3 symbols, expected 7"),
    ],
)
def test_bad_batches_raise_value_error(bad, message):
    w = e3d.Scene.builtin("two_rooms").world()
    with pytest.raises(ValueError, match=message):
        w.execute_batch(bad)


def test_bad_single_commands_raise_value_error():
    w = e3d.Scene.builtin("two_rooms").world()
    with pytest.raises(ValueError, match=r"expected one command, an array of shape \[7\]"):
        w.execute(np.zeros((1, 7), dtype=np.uint8))
    with pytest.raises(ValueError, match="out of range"):
        w.execute([0, 0, 0, 0, 0, 0, 9])


def test_execute_batch_releases_the_gil():
    scene = e3d.Scene.builtin("puck_rooms")
    w = scene.world()
    cmds = random_commands(scene, 600, seed=3)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(1)

    t = threading.Thread(target=count)
    t.start()
    try:
        w.execute_batch(cmds)
    finally:
        stop.set()
        t.join()
    # the Python thread ran while the batch was simulated
    assert len(ticks) > 100


def test_a_blow_up_raises_simulation_error_with_the_clis_text(root, cli):
    path = root / "tests" / "scenes" / "blowup.ron"
    scene = e3d.Scene.load(path)
    w = scene.world()
    assert w.execute("00").effect == 3
    with pytest.raises(e3d.SimulationError) as err:
        w.execute_batch(["00", "0K", "T0"])
    assert isinstance(err.value, RuntimeError)
    r = cli("scene", "exec", path, "00", "0K", check=False)
    assert r.returncode != 0
    assert r.stderr.strip() == f"error: {err.value}"
    assert "command `0K`: the simulation blew up" in str(err.value)
    # the session stops with the same error
    class Kick:
        def propose(self, rng):
            return "0K"

        def learn(self, command, effect, reward):
            pass

    with pytest.raises(e3d.SimulationError, match="command `0K`"):
        e3d.run_session(scene, learner=Kick(), trials=3)
