#!/usr/bin/env python3
"""arm7 in Box2D v3 (pyb2d3): the arm of scenes/arm7.ron, one rollout at a time.

The numbers are read from the RON file by benches/peers/arm7_mujoco.py's
parser. 7 boxes in series on revolute joints (joint 1 on a static ground
at the origin), limits [-2.5, 2.5] rad, neighbours do not collide, the
others do (friction 1, restitution 0), gravity 0, 8 steps of one substep per frame of 1/60 s (see below).

Box2D v3's revolute joint has no viscous damping: the joint damping b_k is
applied as a torque -b_k (w_k - w_{k-1}) on link k and its opposite on link
k-1, from the velocities before each Box2D step (explicit, where Rapier and
MuJoCo integrate it implicitly). Explicit damping blows up at dt 1/60
(b_1 dt / I = 16 for a link's own inertia I), so each frame of 1/60 s is 8
Box2D steps of one substep each (`world.step(dt / 8, 1)`), the torques
recomputed before each (8 substeps a frame, against Box2D's default 4). Forces are cleared after every Box2D
step, so the command's torques are applied again before each step of the
push. A rollout runs in Python, one call per torque: the rate measures
Box2D behind its Python bindings, not Box2D's C alone.

Usage:

    python3 arm7_box2d.py N [--seed S] [--outcomes-out FILE]

executes N random distinct commands and prints
`box2d,arm7,<N>,<seconds>,<rollouts_per_s>`; `--outcomes-out` writes
`command,effect,x,y` (e3d's cell numbering).
"""

import argparse
import itertools
import math
import random
import sys
import time
from pathlib import Path

import pyb2d3 as b2

# Box2D steps per 1/60 s frame (one substep each), the damping torques
# recomputed before each: explicit damping is stable at dt/8, not at dt
SUBSTEPS = 8

sys.path.insert(0, str(Path(__file__).resolve().parent))
from arm7_mujoco import DEFAULT_SCENE, cell, read_scene  # noqa: E402


def rollout(s, command):
    L, W, n, dt = s["length"], s["width"], s["links"], s["dt"]
    world = b2.World(gravity=(0.0, 0.0))
    world.sleeping_enabled = False
    ground = world.create_static_body(position=(0.0, 0.0))
    density = s["mass"] / (L * W)
    links = []
    parent = ground
    for k in range(n):
        body = world.create_dynamic_body(position=(k * L + L / 2, 0.0))
        sd = b2.shape_def(
            density=density, material=b2.surface_material(friction=s["friction"], restitution=0.0)
        )
        body.create_polygon_shape(sd, b2.box(L / 2, W / 2))
        lo, hi = s["limits"]
        jd = b2.revolute_joint_def(
            body_a=parent,
            body_b=body,
            local_anchor_a=(0.0, 0.0) if k == 0 else (L / 2, 0.0),
            local_anchor_b=(-L / 2, 0.0),
            enable_limit=True,
            lower_angle=lo,
            upper_angle=hi,
            collide_connected=False,
        )
        world.create_revolute_joint(jd)
        links.append(body)
        parent = body
    sign = {"-": -1.0, "0": 0.0, "+": 1.0}
    torques = [sign[ch] * t for ch, t in zip(command, s["torques"])]
    damping = s["damping"]
    h = dt / SUBSTEPS
    push = round(s["push"] / dt)
    steps = round((s["push"] + s["settle"]) / dt)
    for step in range(steps * SUBSTEPS):
        w_prev = 0.0
        for k, body in enumerate(links):
            w = body.angular_velocity
            t = -damping[k] * (w - w_prev)
            if step < push * SUBSTEPS:
                t += torques[k]
            if t != 0.0:
                body.apply_torque(t, True)
                if k > 0:
                    links[k - 1].apply_torque(-t, True)
            w_prev = w
        world.step(h, 1)
    tip = links[-1].world_point((L / 2, 0.0))
    x, y = tip
    world.destroy()
    return x, y


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("n", type=int)
    ap.add_argument("--scene", default=str(DEFAULT_SCENE))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--outcomes-out")
    a = ap.parse_args(argv)
    s = read_scene(a.scene)
    cmds = ["".join(p) for p in itertools.product("-0+", repeat=s["links"])]
    cmds = random.Random(a.seed).sample(cmds, a.n)
    start = time.perf_counter()
    out = [rollout(s, c) for c in cmds]
    secs = time.perf_counter() - start
    if a.outcomes_out:
        with open(a.outcomes_out, "w") as f:
            f.write("command,effect,x,y\n")
            for c, (x, y) in zip(cmds, out):
                f.write(f"{c},{cell(s, x, y)},{x!r},{y!r}\n")
    print(f"box2d,arm7,{a.n},{secs:.4f},{a.n / secs:.2f}")


if __name__ == "__main__":
    main(sys.argv[1:])
