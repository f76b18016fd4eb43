import csv

import numpy as np
import pytest

import e3d


@pytest.mark.parametrize(
    "name, commands",
    [
        ("puck_rooms", ["SEEEEES", "NNWWSSE"]),
        # arm7 has a FlipY symmetry: the second command is simulated as its
        # mirror image and its motion reflected; both equal the CLI's
        ("arm7", ["+0-0+0-", "-0+0-0+"]),
        ("pendulum3", None),
    ],
)
def test_trace_equals_scene_exec_trace(cli, tmp_path, name, commands):
    scene = e3d.Scene.builtin(name)
    if commands is None:
        commands = [scene.format([0] * scene.num_slots)]
    path = tmp_path / "trace.csv"
    cli("scene", "exec", "--trace", path, name, *commands)
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, rows = rows[0], rows[1:]
    world = scene.world()
    for c in commands:
        m = world.trace(c)
        mine = [r for r in rows if r[0] == c]
        assert m.command == c and len(m) == len(mine)
        cols = m.columns()
        assert ["command", *cols] == header
        for j, name_ in enumerate(header[1:], start=1):
            want = [float(r[j]) for r in mine]
            assert cols[name_].tolist() == want, name_
        # the outcome is execute's
        assert m.outcome == world.execute(c)


def test_motion_arrays():
    scene = e3d.Scene.builtin("arm7")
    m = scene.world().trace(scene.parse("+0-0+0-")[0])
    f = len(m)
    assert f == 121  # the start and 120 steps
    assert m.time.shape == (f,) and m.time[0] == 0.0 and np.all(np.diff(m.time) > 0)
    b, j = len(m.bodies), len(m.joints)
    assert j == 7
    for a in (m.x, m.y, m.angle, m.vx, m.vy, m.omega):
        assert a.shape == (f, b) and a.dtype == np.float64
    assert m.joint_angle.shape == (f, j) and m.joint_velocity.shape == (f, j)
    assert m.joint_angle[15, 0] > 0.0  # joint 1 pushed by +
    assert np.all(m.joint_angle[0] == 0.0)
    cols = m.columns()
    assert cols["step"].tolist() == list(range(f))
    assert cols[f"{m.joints[0]}.angle"].tolist() == m.joint_angle[:, 0].tolist()
    assert cols[f"{m.bodies[1]}.vx"].tolist() == m.vx[:, 1].tolist()


def test_trace_refuses_grids_and_bad_commands(cli):
    w = e3d.Scene.builtin("two_rooms").world()
    with pytest.raises(ValueError) as err:
        w.trace("EEEEEEE")
    r = cli("scene", "exec", "--trace", "/dev/null", "two_rooms", "EEEEEEE", check=False)
    assert r.returncode != 0 and r.stderr.strip() == f"error: {err.value}"
    p = e3d.Scene.builtin("puck_rooms").world()
    with pytest.raises(ValueError, match="out of range"):
        p.trace([9] * 7)
    with pytest.raises(ValueError, match=r"expected one command"):
        p.trace(np.zeros((2, 7), dtype=np.uint8))


def test_a_blow_up_in_trace_raises_simulation_error(root):
    scene = e3d.Scene.load(root / "tests" / "scenes" / "blowup.ron")
    with pytest.raises(e3d.SimulationError, match="command `0K`"):
        scene.world().trace("0K")
