import numpy as np
import pytest

import e3d

SHIPPED = ["two_rooms", "puck_rooms", "arm7", "pendulum3", "maze3", "puck_rooms14", "arm7x5", "three_rooms", "arm4_gravity", "arm7_continuous", "arm_push", "swimmer", "cart_pole", "four_rooms", "reacher", "swimmer_drag"]


def test_version():
    assert e3d.__version__ == "0.1.0"
    assert isinstance(e3d.E3D_VERSION, str)


def test_builtins_are_the_shipped_scenes():
    assert e3d.Scene.builtins() == SHIPPED


def test_load_equals_builtin(root):
    loaded = e3d.Scene.load(root / "scenes" / "puck_rooms.ron")
    assert loaded == e3d.Scene.builtin("puck_rooms")
    assert e3d.Scene.resolve("puck_rooms") == loaded


def test_two_rooms_summary():
    s = e3d.Scene.builtin("two_rooms")
    assert s.name == "two_rooms"
    assert s.kind == "grid"
    assert s.num_slots == 7
    assert s.alphabet_sizes == [4] * 7
    assert s.alphabets == ["ESWN"] * 7
    assert s.num_effects == 18
    assert s.num_commands == 4**7
    assert s.start_effect == 0
    assert s.effect_grid[:2] == (3, 6)
    r = s.reward_table()
    assert r.dtype == np.float64 and r.shape == (18,)
    assert r.sum() == 1.0 and r[2 * 6 + 5] == 1.0


def test_parse_and_format_round_trip():
    s = e3d.Scene.builtin("two_rooms")
    a = s.parse(["EESSEES", "NNNNNNN"])
    assert a.dtype == np.uint8 and a.shape == (2, 7)
    assert a[0].tolist() == [0, 0, 1, 1, 0, 0, 1]
    assert a[1].tolist() == [3] * 7
    assert s.parse("EESSEES").shape == (1, 7)
    assert s.format(a) == ["EESSEES", "NNNNNNN"]
    assert s.format(a[0]) == "EESSEES"
    assert s.format([0, 0, 1, 1, 0, 0, 1]) == "EESSEES"


def test_every_scene_parses_its_first_command():
    for name in SHIPPED:
        s = e3d.Scene.builtin(name)
        if s.is_continuous:
            continue
        first = "".join(a[0] for a in s.alphabets)
        assert s.parse([first]).tolist() == [[0] * s.num_slots]


def test_parse_errors_have_the_cli_text():
    s = e3d.Scene.builtin("two_rooms")
    with pytest.raises(ValueError, match=r"command `EES` has 3 symbols, expected 7 \(one per slot\)"):
        s.parse("EES")
    with pytest.raises(ValueError, match=r"symbol 'X' at slot 2 is not one of ESWN"):
        s.parse(["EEXSEES"])


def test_unknown_builtin():
    with pytest.raises(e3d.SceneError, match="nope: no built-in scene of that name; expected one of: two_rooms"):
        e3d.Scene.builtin("nope")


def test_scene_errors_name_file_line_and_column(tmp_path, cli):
    bad = tmp_path / "bad.ron"
    bad.write_text('Scene(\n    name: "x",\n    world: Grid(rows: 3, cols: 6, start: (0, 0), walls: []),\n    command: Repeat(slots: 7, alphabet: [(symbol: \'E\', action: Move(drow: 0, dcol: 1)), (symbol: \'E\', action: Idle)]),\n)\n')
    with pytest.raises(e3d.SceneError) as err:
        e3d.Scene.load(bad)
    assert isinstance(err.value, ValueError)
    msg = str(err.value)
    assert msg.startswith(f"{bad}:4:")
    r = cli("scene", "check", bad, check=False)
    assert r.returncode != 0
    assert r.stderr.strip() == f"error: {msg}"


def test_missing_file_error_is_the_clis(tmp_path, cli):
    missing = tmp_path / "missing.ron"
    with pytest.raises(e3d.SceneError) as err:
        e3d.Scene.resolve(str(missing))
    r = cli("scene", "check", missing, check=False)
    assert r.stderr.strip() == f"error: {err.value}"


def test_from_text_names_the_file():
    with pytest.raises(e3d.SceneError, match=r"^mine\.ron"):
        e3d.Scene.from_text("Scene(name: 3)", "mine.ron")
    with pytest.raises(e3d.SceneError, match="the file is empty"):
        e3d.Scene.from_text("  ")


@pytest.mark.parametrize("name", e3d.Scene.builtins())
def test_dict_form_reads_back_equal(name):
    scene = e3d.Scene.builtin(name)
    d = scene.to_dict()
    assert set(d) >= {"name", "world", "command"}
    assert e3d.Scene.from_dict(d) == scene
    assert e3d.Scene.from_text(scene.to_ron()) == scene


def test_from_dict_errors_name_the_path():
    d = e3d.Scene.builtin("puck_rooms").to_dict()
    d["world"]["Physics"]["bodies"][6]["linear_damping"] = "x"
    with pytest.raises(e3d.SceneError, match=r"^<dict>: world\.Physics\.bodies\[6\]\.linear_damping: invalid type: string \"x\", expected f64") as e:
        e3d.Scene.from_dict(d)
    assert e.value.field == "world.Physics.bodies[6].linear_damping" and e.value.file == "<dict>"
    d = e3d.Scene.builtin("puck_rooms").to_dict()
    d["world"]["Physics"]["bodies"][1]["shape"] = {"Blob": {}}
    with pytest.raises(e3d.SceneError, match=r"bodies\[1\]\.shape\.Blob: unknown variant `Blob`, expected one of `Ball`"):
        e3d.Scene.from_dict(d)
    d = e3d.Scene.builtin("puck_rooms").to_dict()
    d["wrold"] = d.pop("world")
    with pytest.raises(e3d.SceneError, match=r"unknown field `wrold`"):
        e3d.Scene.from_dict(d)
    # the validation's messages and field, as for a file
    d = e3d.Scene.builtin("puck_rooms").to_dict()
    d["world"]["Physics"]["bodies"][6]["linear_damping"] = -1.0
    with pytest.raises(e3d.SceneError, match=r"linear_damping.*a finite number >= 0, found -1") as e:
        e3d.Scene.from_dict(d)
    assert e.value.field == "linear_damping"
    with pytest.raises(TypeError, match="expected a dict"):
        e3d.Scene.from_dict([1, 2])


def test_with_overrides_by_path():
    scene = e3d.Scene.builtin("puck_rooms")
    heavy = scene.with_({"bodies.puck.linear_damping": 2.0, "name": "damped"})
    assert heavy.name == "damped" and heavy != scene
    puck = [b for b in heavy.to_dict()["world"]["Physics"]["bodies"] if b["name"] == "puck"][0]
    assert puck["linear_damping"] == 2.0
    # the same with the full path, and an index instead of the name
    assert scene.with_({"world.Physics.bodies.6.linear_damping": 2.0, "name": "damped"}) == heavy
    # the damping changes what the commands do
    cmds = scene.parse(["SEEEEES", "EEEEEEE", "SSEEENN"])
    assert scene.world().execute_batch(cmds).x.tolist() != heavy.world().execute_batch(cmds).x.tolist()
    assert e3d.Scene.builtin("two_rooms").with_({"rows": 4}).num_effects == 24
    with pytest.raises(e3d.SceneError, match=r"no item named `puckx`; the names: wall_south"):
        scene.with_({"bodies.puckx.linear_damping": 2.0})
    with pytest.raises(e3d.SceneError, match=r"unknown field `lin`, expected one of `name`, `kind`, `shape`") as e:
        scene.with_({"bodies.puck.lin": 2.0})
    assert e.value.field == "world.Physics.bodies[6].lin"
    # a section the scene leaves out is created, a list's item by [index]
    noisy = scene.with_({"noise.actions.Gaussian.sd": 0.05, "world.bodies[6].mass": 2.0})
    assert noisy.to_dict()["world"]["Physics"]["noise"] == {"actions": {"Gaussian": {"sd": 0.05}}}
    with pytest.raises(e3d.SceneError, match=r"found -1"):
        scene.with_({"bodies.puck.linear_damping": -1.0})


def test_from_dict_expands_shorthand_walls():
    scene = e3d.Scene.builtin("puck_rooms")
    d = scene.to_dict()
    p = d["world"]["Physics"]
    p["bodies"] = [b for b in p["bodies"] if b["name"] == "puck"]
    p["walls"] = [
        {"name": "wall", "room": [[0.0, 0.0], [6.0, 3.0]], "placement": "Outside", "thickness": 0.1,
         "friction": 0.0, "restitution": 0.5},
        {"name": "inner", "points": [[3.0, 0.0], [3.0, 3.0]], "doors": [[[3.0, 1.0], [3.0, 2.0]]],
         "names": ["inner_low", "inner_high"], "thickness": 0.1, "friction": 0.0, "restitution": 0.5},
    ]
    # the walls of scenes/puck_rooms.ron, written as a dict: the same scene
    assert e3d.Scene.from_dict(d) == scene
