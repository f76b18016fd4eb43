#!/usr/bin/env python3
"""arm7 in MuJoCo, rolled out with `mujoco.rollout` (native, multi-threaded).

The peer of e3d's arm targets: the arm of scenes/arm7.ron as an MJCF model,
every command of the scene (3^7 = 2187: one torque in {-t_k, 0, +t_k} per
joint) executed open loop from the rest pose by MuJoCo's own rollout module
(`mujoco.rollout.rollout`, C++ threads, no Python per step), the same
semantics as `e3d scene exec arm7 -`.

Read from the RON file (a small ad-hoc parser): `dt`, the chain (`links`,
`length`, `width`, `mass`, `friction`, `limits`, `damping`), the
`Simultaneous(push, settle)` schedule, the torques of the `+` symbols and
the effect grid. The model:

- 7 boxes in series in the plane z = 0, hinges about z at each link's start
  (joint 1 at the origin, on the world), the tip a point at the end of link 7;
- joint damping b_k (MuJoCo integrates it implicitly, as Rapier's multibody
  does), limits [-2.5, 2.5] rad, gravity 0;
- one motor per hinge (gear 1): a torque on joint k is +t on link k and -t on
  link k-1, as in e3d;
- neighbours do not collide (MuJoCo excludes parent-child contacts), other
  links do (friction 1; MuJoCo contacts are soft, Rapier's restitution 0 has
  no counterpart);
- the scene's dt (1/60 s), MuJoCo's default Euler integrator.

Usage:

    python3 arm7_mujoco.py [--scene FILE] [--threads T] [--repeat R]
                           [--outcomes-out FILE] [--dt-divisor D]

prints `mujoco,arm7,<threads>,<rollouts>,<seconds>,<rollouts_per_s>` per
thread count (the best of R repeats), and with `--outcomes-out` writes
`command,effect,x,y` of every command (the cell index is row * cols + col,
row 0 at the top, as e3d's). `--dt-divisor D` steps D times per frame of
1/60 s (D x 120 steps of dt / D): a converged MuJoCo run to compare with.
"""

import argparse
import itertools
import math
import re
import sys
import time
from pathlib import Path

import mujoco
import numpy as np
from mujoco import rollout

DEFAULT_SCENE = Path(__file__).resolve().parents[2] / "scenes" / "arm7.ron"
NUM = r"(-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)"


def strip_comments(text):
    return re.sub(r"//[^\n]*", "", text)


def num(text, name):
    m = re.search(r"\b" + name + r"\s*:\s*" + NUM, text)
    if m is None:
        raise ValueError(f"no field `{name}`")
    return float(m.group(1))


def read_scene(path):
    t = strip_comments(Path(path).read_text())
    chain = re.search(r"chains\s*:\s*\[\s*\((.*?)\)\s*\]", t, re.S).group(1)
    s = {
        "dt": num(t, "dt"),
        "links": int(num(chain, "links")),
        "length": num(chain, "length"),
        "width": num(chain, "width"),
        "mass": num(chain, "mass"),
        "friction": num(chain, "friction"),
    }
    lim = re.search(r"limits\s*:\s*\(\s*" + NUM + r"\s*,\s*" + NUM, chain)
    s["limits"] = (float(lim.group(1)), float(lim.group(2)))
    damp = re.search(r"damping\s*:\s*\[([^\]]*)\]", chain).group(1)
    s["damping"] = [float(x) for x in damp.split(",") if x.strip()]
    sched = re.search(r"Simultaneous\(\s*push\s*:\s*" + NUM + r"\s*,\s*settle\s*:\s*" + NUM, t)
    s["push"], s["settle"] = float(sched.group(1)), float(sched.group(2))
    # the torque of each slot's '+' symbol (the alphabets are -t, 0, +t)
    s["torques"] = [
        float(m.group(1))
        for m in re.finditer(r"symbol:\s*'\+',\s*action:\s*Torque\([^)]*torque:\s*" + NUM, t)
    ]
    g = re.search(
        r"grid\s*:\s*\(\s*rows\s*:\s*(\d+)\s*,\s*cols\s*:\s*(\d+)\s*,\s*min\s*:\s*\(\s*"
        + NUM + r"\s*,\s*" + NUM + r"\s*\)\s*,\s*max\s*:\s*\(\s*" + NUM + r"\s*,\s*" + NUM,
        t,
    )
    s["grid"] = (int(g.group(1)), int(g.group(2)), float(g.group(3)), float(g.group(4)),
                 float(g.group(5)), float(g.group(6)))
    assert len(s["damping"]) == s["links"] and len(s["torques"]) == s["links"], s
    return s


def mjcf(s, dt):
    L, W, n = s["length"], s["width"], s["links"]
    lo, hi = s["limits"]
    body = ""
    close = ""
    for k in range(n):
        pos = "0 0 0" if k == 0 else f"{L} 0 0"
        body += (
            f'<body name="link{k + 1}" pos="{pos}">'
            f'<joint name="j{k + 1}" type="hinge" axis="0 0 1" range="{lo} {hi}" '
            f'limited="true" damping="{s["damping"][k]}"/>'
            f'<geom type="box" size="{L / 2} {W / 2} {W / 2}" pos="{L / 2} 0 0" '
            f'mass="{s["mass"]}" friction="{s["friction"]} 0.005 0.0001"/>'
        )
        if k == n - 1:
            body += f'<site name="tip" pos="{L} 0 0"/>'
        close += "</body>"
    motors = "".join(f'<motor joint="j{k + 1}" gear="1"/>' for k in range(n))
    return (
        f'<mujoco model="arm7"><compiler angle="radian"/><option timestep="{dt}" gravity="0 0 0"/>'
        f"<worldbody>{body}{close}</worldbody><actuator>{motors}</actuator></mujoco>"
    )


def tips(s, qpos):
    """The tip of the planar chain for each row of joint angles."""
    a = np.cumsum(qpos, axis=1)
    return s["length"] * np.stack([np.cos(a).sum(axis=1), np.sin(a).sum(axis=1)], axis=1)


def cell(s, x, y):
    rows, cols, x0, y0, x1, y1 = s["grid"]
    c = min(max(int(math.floor((x - x0) / ((x1 - x0) / cols))), 0), cols - 1)
    r = min(max(int(math.floor((y1 - y) / ((y1 - y0) / rows))), 0), rows - 1)
    return r * cols + c


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=str(DEFAULT_SCENE))
    ap.add_argument("--threads", default="1,2", help="comma-separated thread counts")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--outcomes-out")
    ap.add_argument("--dt-divisor", type=int, default=1)
    a = ap.parse_args()
    s = read_scene(a.scene)
    d = a.dt_divisor
    model = mujoco.MjModel.from_xml_string(mjcf(s, s["dt"] / d))
    n = s["links"]
    push = round(s["push"] / s["dt"]) * d
    steps = round((s["push"] + s["settle"]) / s["dt"]) * d
    cmds = ["".join(p) for p in itertools.product("-0+", repeat=n)]
    sign = {"-": -1.0, "0": 0.0, "+": 1.0}
    control = np.zeros((len(cmds), steps, model.nu))
    t = np.array(s["torques"])
    for i, c in enumerate(cmds):
        control[i, :push, :] = np.array([sign[ch] for ch in c]) * t
    data0 = mujoco.MjData(model)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    init = np.zeros((1, mujoco.mj_stateSize(model, spec)))
    mujoco.mj_getState(model, data0, init[0], spec)
    state = None
    for threads in [int(x) for x in a.threads.split(",")]:
        datas = [mujoco.MjData(model) for _ in range(threads)]
        best = math.inf
        for _ in range(a.repeat):
            t0 = time.perf_counter()
            state, _ = rollout.rollout(model, datas, init, control)
            best = min(best, time.perf_counter() - t0)
        print(f"mujoco,arm7,{threads},{len(cmds)},{best:.4f},{len(cmds) / best:.1f}")
        sys.stdout.flush()
    if a.outcomes_out:
        # FULLPHYSICS state: time, qpos, qvel, ...
        qpos = state[:, -1, 1 : 1 + model.nq]
        p = tips(s, qpos)
        with open(a.outcomes_out, "w") as f:
            for c, (x, y) in zip(cmds, p):
                f.write(f"{c},{cell(s, x, y)},{float(x)!r},{float(y)!r}\n")


if __name__ == "__main__":
    main()
