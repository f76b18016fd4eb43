"""Pictures: Scene.svg and _repr_svg_ are the CLI's `e3d scene render`."""

import pytest

import e3d


@pytest.mark.parametrize("name, command", [
    ("two_rooms", "SEEEEES"), ("puck_rooms", "SEEEEES"), ("arm7_continuous", "1.8, -1.2, 0.75, 0, 0, 0, 0"),
])
def test_svg_is_the_clis(cli, tmp_path, name, command):
    scene = e3d.Scene.builtin(name)
    plain = tmp_path / "plain.svg"
    cli("scene", "render", name, "--out", plain)
    assert scene.svg() == plain.read_text()
    assert scene._repr_svg_() == scene.svg()
    drawn = tmp_path / "drawn.svg"
    cli("scene", "render", name, "--command", command, "--out", drawn)
    assert scene.svg(command) == drawn.read_text()
    assert scene.svg(command) != scene.svg() and scene.svg().startswith("<svg")


def test_svg_errors():
    with pytest.raises(ValueError, match="symbol 'X'"):
        e3d.Scene.builtin("two_rooms").svg("XEEEEEE")


def test_render_is_the_svg_rasterised():
    import numpy as np
    scene = e3d.Scene.builtin("puck_rooms")
    img = scene.render("SEEEEES")
    assert img.dtype == np.uint8 and img.ndim == 3 and img.shape[2] == 3
    # the SVG's size in pixels (the legend grows with a command's path)
    import re
    w, h = (float(v) for v in re.search(r'width="([\d.]+)" height="([\d.]+)"', scene.svg("SEEEEES")).groups())
    assert img.shape[:2] == (int(np.ceil(h)), int(np.ceil(w)))
    assert scene.render(scale=0.5).shape[1] == int(np.ceil(w * 0.5))
    # mostly white paper, with the walls' dark grey and the path's orange drawn
    assert (img == 255).all(axis=2).mean() > 0.5
    dark = (img.max(axis=2) < 120).mean()
    assert 0.005 < dark < 0.2
    orange = (img[:, :, 0] > 180) & (img[:, :, 1] > 60) & (img[:, :, 1] < 150) & (img[:, :, 2] < 80)
    assert orange.sum() > 200
    plain = scene.render()
    orange_plain = (plain[:, :, 0] > 180) & (plain[:, :, 1] > 60) & (plain[:, :, 1] < 150) & (plain[:, :, 2] < 80)
    assert orange_plain.sum() < orange.sum() / 4
    for name in e3d.Scene.builtins():
        assert e3d.Scene.builtin(name).render(scale=0.25).shape[2] == 3
    with pytest.raises(ValueError, match="scale = 0"):
        scene.render(scale=0.0)


def test_geometry_is_the_scenes():
    g = e3d.Scene.builtin("puck_rooms").geometry()
    assert g["kind"] == "physics" and g["effect_grid"] == {"rows": 3, "cols": 6, "min": (0.0, 0.0), "max": (6.0, 3.0)}
    assert g["reward_cells"] == [(2, 5)] and g["tracked_body"] == "puck"
    bodies = {b["name"]: b for b in g["bodies"]}
    assert bodies["puck"]["shape"] == "ball" and bodies["puck"]["points"] == [bodies["puck"]["position"]]
    south = bodies["wall_south"]
    assert south["shape"] == "cuboid" and south["kind"] == "fixed" and len(south["points"]) == 5
    xs = [p[0] for p in south["points"]]
    assert min(xs) < 0.0 and max(xs) > 6.0
    arm = e3d.Scene.builtin("arm7").geometry()
    assert len(arm["joints"]) == 7 and arm["joints"][0]["parent"] == "ground"
    grid = e3d.Scene.builtin("two_rooms").geometry()
    assert grid["kind"] == "grid" and grid["start"] == (0, 0) and grid["walls"][0] == ((0, 2), (0, 3))


def test_session_record_draws_its_effect_counts():
    rec = e3d.run_session("two_rooms", trials=500, seed=1)
    svg = rec._repr_svg_()
    assert svg.startswith("<svg") and svg.endswith("</svg>")
    assert "two_rooms: e3d, seed 1, 500 trials" in svg
    # one cell a rect (18 cells), each with its count; the rewarded cell (2, 5) outlined in green
    import re
    cells = re.findall(r"<title>cell \((\d+), (\d+)\): ([\d.]+) trials", svg)
    assert len(cells) == 18
    counts = {(int(r), int(c)): float(n) for r, c, n in cells}
    assert [counts[(e // 6, e % 6)] for e in range(18)] == rec.effect_counts.tolist()
    assert svg.count('stroke="#2e8b57"') == 1
    # the darkest cell is the most visited
    top = max(counts, key=counts.get)
    assert f"<title>cell ({top[0]}, {top[1]})" in svg.split('fill="rgb(31,78,156)"')[1][:200]
    batch = e3d.run_sessions("two_rooms", trials=500, seeds=[1, 2])
    assert batch[0]._repr_svg_() == svg


def _cells(svg, unit):
    import re
    cells = re.findall(rf"<title>cell \((\d+), (\d+)\): ([\d.]+) {unit}", svg)
    return {(int(r), int(c)): float(n) for r, c, n in cells}


def test_a_batch_of_sessions_draws_their_effect_counts_together():
    batch = e3d.run_sessions("two_rooms", trials=300, seeds=[1, 2, 3])
    svg = batch._repr_svg_()
    assert svg.startswith("<svg") and svg.endswith("</svg>")
    assert "two_rooms: e3d, 3 sessions of 300 trials" in svg
    counts = _cells(svg, "trials")
    total = sum(batch[i].effect_counts for i in range(3))
    assert len(counts) == 18 and [counts[(e // 6, e % 6)] for e in range(18)] == total.tolist()
    assert sum(counts.values()) == 900


def test_an_episode_record_draws_where_its_episodes_ended(root):
    scene = e3d.Scene.load(root / "scenes" / "two_rooms_contexts.ron")
    rec = e3d.run_episodes(scene, episodes=40, commands=2, seed=3)
    svg = rec._repr_svg_()
    assert svg.startswith("<svg") and f"seed 3: 40 episodes of 2 commands" in svg
    counts = _cells(svg, "episodes")
    ends = rec.effects[1::2]
    assert len(ends) == 40 and sum(counts.values()) == 40
    for e in range(scene.num_effects):
        assert counts[(e // 6, e % 6)] == (ends == e).sum()
