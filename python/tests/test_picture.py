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
