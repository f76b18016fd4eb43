#!/usr/bin/env python3
"""puck_rooms in Box2D v3 (pyb2d3): a second peer for the puck.

The same model and the same commands as benches/pymunk/puck_rooms.py (its
RON parser is reused: walls, puck, damping, impulses, schedule, grid; the
same seed draws the same N distinct commands), in Box2D v3 through the
`pyb2d3` bindings: one rollout at a time, a fresh world each rollout, one
`world.step(dt, 4)` per step (Box2D's default 4 substeps).

What is matched to Rapier: linear damping (Box2D v3 damps as Rapier does,
v <- v / (1 + c h), but per substep h = dt / 4: its coefficient is set to
c' = 4 ((1 + c dt)^(1/4) - 1) / dt, the same factor per step), the contact restitution
(Box2D takes the larger of the two coefficients: both are set to Rapier's
average, and the restitution threshold to 0 so that slow bounces bounce),
friction 0 as in the file, rotation locked. It is a model of the same
scene, not the same simulator.

Usage:

    python3 puck_rooms_box2d.py N [--scene FILE] [--seed S] [--outcomes-out FILE]

(`--scene`: a RON file with the walls written out, as `e3d scene check
--expanded puck_rooms` prints it; the shipped file uses the `walls`
shorthand, which the parser does not read.)

prints `box2d,puck_rooms,<N>,<seconds>,<rollouts_per_s>`.
"""

import argparse
import random
import sys
import time
from pathlib import Path

import pyb2d3 as b2

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "pymunk"))
from puck_rooms import DEFAULT_SCENE, command_of, parse_scene, steps  # noqa: E402


class PuckRoomsBox2d:
    def __init__(self, scene):
        self.s = scene
        self.dt = scene["dt"]
        self.phase_steps = steps(scene["phase"], self.dt)
        self.settle_steps = steps(scene["settle"], self.dt)
        self.impulse = dict(scene["alphabet"])
        p = scene["puck"]
        wall_e = {w["restitution"] for w in scene["walls"]}
        assert len(wall_e) == 1, "the walls share one restitution"
        self.restitution = (p["restitution"] + wall_e.pop()) / 2.0
        c, dt = p["damping"], self.dt
        self.damping = 4.0 * ((1.0 + c * dt) ** 0.25 - 1.0) / dt

    def build(self):
        world = b2.World(gravity=(0.0, 0.0))
        world.restitution_threshold = 0.0
        world.sleeping_enabled = False
        for w in self.s["walls"]:
            body = world.create_static_body(position=w["position"])
            sd = b2.shape_def(
                material=b2.surface_material(friction=w["friction"], restitution=self.restitution)
            )
            body.create_polygon_shape(sd, b2.box(w["size"][0] / 2, w["size"][1] / 2))
        p = self.s["puck"]
        puck = world.create_dynamic_body(
            position=p["position"], linear_damping=self.damping, fixed_rotation=True
        )
        sd = b2.shape_def(
            density=1.0,
            material=b2.surface_material(friction=p["friction"], restitution=self.restitution),
        )
        circle = b2.Circle()
        circle.radius = p["radius"]
        puck.create_circle_shape(sd, circle)
        md = puck.mass_data
        md.mass = p["mass"]
        puck.mass_data = md
        return world, puck

    def execute(self, command):
        world, puck = self.build()
        dt = self.dt
        for symbol in command:
            puck.apply_linear_impulse_to_center(self.impulse[symbol], True)
            for _ in range(self.phase_steps):
                world.step(dt, 4)
        for _ in range(self.settle_steps):
            world.step(dt, 4)
        x, y = puck.position
        world.destroy()
        return x, y


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("n", type=int)
    ap.add_argument("--scene", default=str(DEFAULT_SCENE))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--outcomes-out")
    a = ap.parse_args(argv)
    scene = parse_scene(a.scene)
    world = PuckRoomsBox2d(scene)
    symbols = [sym for sym, _ in scene["alphabet"]]
    total = len(symbols) ** scene["slots"]
    rng = random.Random(a.seed)
    commands = [command_of(i, symbols, scene["slots"]) for i in rng.sample(range(total), a.n)]
    start = time.perf_counter()
    outcomes = [world.execute(c) for c in commands]
    secs = time.perf_counter() - start
    if a.outcomes_out:
        with open(a.outcomes_out, "w") as f:
            f.write("command,x,y\n")
            for c, (x, y) in zip(commands, outcomes):
                f.write(f"{c},{x!r},{y!r}\n")
    print(f"box2d,puck_rooms,{a.n},{secs:.4f},{a.n / secs:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
