"""The MJCF export loads in MuJoCo and `e3d.crosscheck` runs the same
commands in both (skipped where the `mujoco` package is not installed:
`pip install 'e3d[mujoco]'`)."""

import numpy as np
import pytest

import e3d

PHYSICS = [n for n in e3d.Scene.builtins() if e3d.Scene.builtin(n).kind == "physics"]


def test_to_mjcf_without_mujoco():
    xml = e3d.Scene.builtin("reacher").to_mjcf()
    assert '<joint name="elbow" type="hinge"' in xml
    with pytest.raises(ValueError, match="is a grid"):
        e3d.Scene.builtin("two_rooms").to_mjcf()
    scene = e3d.Scene.builtin("cart_pole")
    # the pole at +0.5 rad, the cart at the left end: row 2 of 9, column 0 of 7
    assert scene.effect_of([0.5, -1.4]) == 2 * 7 + 0
    with pytest.raises(ValueError, match="expected 2 feature values"):
        scene.effect_of([0.5])


@pytest.mark.parametrize("name", PHYSICS)
def test_every_physics_scene_loads_in_mujoco(name):
    mujoco = pytest.importorskip("mujoco")
    model = mujoco.MjModel.from_xml_string(e3d.Scene.builtin(name).to_mjcf())
    assert model.nbody >= 2
    assert model.numeric("e3d_schedule").data[3] == 4


def test_crosscheck_of_the_reacher_and_the_cart_pole():
    pytest.importorskip("mujoco")
    out = e3d.crosscheck("reacher", commands=20, seed=1)
    assert len(out["command"]) == 20 and out["distance"].shape == (20,)
    # no contact on the arm: the two engines agree to a millimetre
    assert not out["contact"].any()
    assert np.median(out["distance"]) < 1e-3, out["distance"]
    assert out["agree"].mean() >= 0.9
    out = e3d.crosscheck("cart_pole", commands=10, seed=2)
    assert np.median(out["distance"]) < 1e-2, out["distance"]
    assert (out["e3d_effect"] == out["mujoco_effect"]).mean() >= 0.8


def test_crosscheck_applies_the_swimmers_drag():
    pytest.importorskip("mujoco")
    # the drag travels in the export (e3d_drag_<body>) and is applied in
    # MuJoCo as xfrc_applied: the centres of mass agree to millimetres
    # (without it MuJoCo's swimmer would not move: 5 cm apart)
    xml = e3d.Scene.builtin("swimmer_drag").to_mjcf()
    assert '<numeric name="e3d_drag_link1" data="0.02 0.5 0"/>' in xml
    out = e3d.crosscheck("swimmer_drag", commands=10, seed=0)
    assert not out["contact"].any()
    assert np.median(out["distance"]) < 3e-3, out["distance"]
    assert out["agree"].mean() >= 0.8
