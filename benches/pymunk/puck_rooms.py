#!/usr/bin/env python3
"""puck_rooms in pymunk: the baseline of e3d's speed targets.

The project's speed targets are stated against "pymunk's single-rollout
rate on puck_rooms measured in the same run". This script builds the scene
of scenes/puck_rooms.ron in pymunk and executes N random distinct commands,
one rollout at a time: with `--mode fresh` (the default) on a new space
for every rollout, with `reuse` on one space with the puck put back at its
start (what a user writes), with `cache` as `reuse` with the puck's state
after each slot kept by command prefix (e3d's prefix states). The three
give the same terminal points to the bit.

Every number is read from the RON file (a tiny ad-hoc parser for the few
fields needed, below; a file with shorthand `walls` is first expanded into
plain bodies by e3d itself, see `expanded_text`), not hard-coded: `dt`, the `Fixed` walls (`Cuboid`
width, height, position, friction, restitution), the puck (`Ball` radius,
`mass`, `position`, `linear_damping`, friction, restitution), the
`Sequential(phase, settle)` schedule, `slots`, the `alphabet`'s impulses
and the effect `grid`.

Usage:

    python3 puck_rooms.py N [--scene FILE] [--seed S]
                            [--commands-out FILE] [--outcomes-out FILE]

prints the rate, then a CSV line

    pymunk,puck_rooms,<N>,<seconds>,<rollouts_per_s>,<mode>

`--commands-out` writes the N commands, one per line (feed them to
`e3d scene exec puck_rooms -` to time e3d on the same commands);
`--outcomes-out` writes `command,effect,x,y` of every rollout, like e3d's
`scene exec` CSV without the reward.

What is matched to Rapier, and how (this is a model of the same scene, not
the same simulator; docs/benchmarks.md says what was compared):

- damping: Rapier damps implicitly, v <- v / (1 + c dt) after each step's
  move; pymunk multiplies v by `space.damping ** dt` each step (Chipmunk
  also moves first, then updates the velocity), so `space.damping` is set
  to (1 / (1 + c dt)) ** (1 / dt): the same factor per step.
- restitution: Rapier averages the two colliders' coefficients, Chipmunk
  multiplies them; the walls get elasticity 1 and the puck the average of
  its restitution and the walls' (all the walls share one), so every
  puck-wall contact has Rapier's coefficient. Friction is 0 in the file,
  0 in both.
- rotation locked: the puck's moment is infinite.
- contact slop: Chipmunk's default `collision_slop` is 0.1 (made for
  pixels); it is set to 0.001 m.
"""

import argparse
import math
import random
import re
import sys
import time
from pathlib import Path

import pymunk

DEFAULT_SCENE = Path(__file__).resolve().parents[2] / "scenes" / "puck_rooms.ron"

NUM = r"(-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?)"
PAIR = r"\(\s*" + NUM + r"\s*,\s*" + NUM + r"\s*\)"


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def field(text, name, pattern=NUM, default=None):
    """The first `name: <pattern>` in text, its groups as floats."""
    m = re.search(r"\b" + name + r"\s*:\s*" + pattern, text)
    if m is None:
        if default is not None:
            return default
        raise ValueError(f"no field `{name}` in: {text[:120]}...")
    g = [float(x) for x in m.groups()]
    return g[0] if len(g) == 1 else tuple(g)


def body_entries(text):
    """The text of each `(name: "...", ...)` entry of `bodies: [...]`."""
    start = text.index("bodies:")
    i = text.index("[", start) + 1
    depth, entries, cur = 0, [], None
    while True:
        ch = text[i]
        if ch == "(":
            if depth == 0:
                cur = i
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0:
                entries.append(text[cur : i + 1])
        elif ch == "]" and depth == 0:
            return entries
        i += 1


def expanded_text(path):
    """The scene's text with its shorthands (`walls`, `chains`) expanded
    into plain bodies, by e3d itself: the Python package if it is
    installed (`Scene.load(path).to_ron()`), else the CLI (`$E3D_BIN`,
    the repository's target/release/e3d, or `e3d` on the PATH) as `e3d
    scene check FILE --expanded`. The same text either way."""
    try:
        import e3d

        return e3d.Scene.load(str(path)).to_ron()
    except ImportError:
        pass
    import os
    import shutil
    import subprocess

    root = Path(__file__).resolve().parents[2]
    for exe in (os.environ.get("E3D_BIN"), root / "target" / "release" / "e3d", shutil.which("e3d")):
        if exe and Path(exe).is_file():
            return subprocess.run(
                [str(exe), "scene", "check", str(path), "--expanded"],
                check=True, capture_output=True, text=True,
            ).stdout
    sys.exit(
        f"{path} has shorthand walls: install the e3d Python package or build the CLI "
        "(cargo build --release) so that they can be expanded"
    )


def parse_scene(path):
    text = strip_comments(Path(path).read_text())
    if re.search(r"\b(walls|chains)\s*:\s*\[", text):
        text = strip_comments(expanded_text(path))
    s = {"dt": field(text, "dt", default=1.0 / 60.0)}
    s["walls"], s["puck"] = [], None
    for e in body_entries(text):
        name = re.search(r'name\s*:\s*"([^"]*)"', e).group(1)
        if re.search(r"kind\s*:\s*Fixed", e):
            m = re.search(r"Cuboid\(\s*width\s*:\s*" + NUM + r"\s*,\s*height\s*:\s*" + NUM, e)
            s["walls"].append(
                {
                    "name": name,
                    "size": (float(m.group(1)), float(m.group(2))),
                    "position": field(e, "position", PAIR),
                    "friction": field(e, "friction", default=0.5),
                    "restitution": field(e, "restitution", default=0.0),
                }
            )
        else:
            assert s["puck"] is None, "one dynamic body"
            assert re.search(r"lock_rotation\s*:\s*true", e), "a puck that does not rotate"
            s["puck"] = {
                "name": name,
                "radius": field(e, "radius"),
                "mass": field(e, "mass"),
                "position": field(e, "position", PAIR),
                "damping": field(e, "linear_damping"),
                "friction": field(e, "friction", default=0.5),
                "restitution": field(e, "restitution", default=0.0),
            }
    m = re.search(r"Sequential\(\s*phase\s*:\s*" + NUM + r"\s*,\s*settle\s*:\s*" + NUM, text)
    s["phase"], s["settle"] = float(m.group(1)), float(m.group(2))
    g = re.search(r"grid\s*:\s*\(([^()]*(?:\([^()]*\)[^()]*)*)\)", text).group(1)
    s["grid"] = {
        "rows": int(field(g, "rows")),
        "cols": int(field(g, "cols")),
        "min": field(g, "min", PAIR),
        "max": field(g, "max", PAIR),
    }
    s["slots"] = int(field(text, "slots"))
    s["alphabet"] = [
        (sym, (float(x), float(y)))
        for sym, x, y in re.findall(
            r"symbol\s*:\s*'(.)'\s*,\s*action\s*:\s*Impulse\([^)]*impulse\s*:\s*" + PAIR, text
        )
    ]
    assert s["alphabet"], "an alphabet of impulses"
    return s


def steps(duration, dt):
    n = round(duration / dt)
    assert abs(n * dt - duration) < 1e-9, "a whole number of steps"
    return n


class PuckRooms:
    def __init__(self, scene):
        self.s = scene
        self.dt = scene["dt"]
        self.phase_steps = steps(scene["phase"], self.dt)
        self.settle_steps = steps(scene["settle"], self.dt)
        self.impulse = dict(scene["alphabet"])
        p = scene["puck"]
        # Rapier: v <- v / (1 + c dt) per step; Chipmunk: v <- v * damping ** dt
        self.damping = (1.0 / (1.0 + p["damping"] * self.dt)) ** (1.0 / self.dt)
        wall_e = {w["restitution"] for w in scene["walls"]}
        assert len(wall_e) == 1, "the walls share one restitution"
        # Rapier averages the restitutions, Chipmunk multiplies them
        self.puck_elasticity = (p["restitution"] + wall_e.pop()) / 2.0
        self.steps_per_command = scene["slots"] * self.phase_steps + self.settle_steps

    def build(self):
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        space.damping = self.damping
        space.collision_slop = 0.001
        for w in self.s["walls"]:
            body = pymunk.Body(body_type=pymunk.Body.STATIC)
            body.position = w["position"]
            box = pymunk.Poly.create_box(body, w["size"])
            box.elasticity = 1.0
            box.friction = w["friction"]
            space.add(body, box)
        p = self.s["puck"]
        puck = pymunk.Body(p["mass"], math.inf)
        puck.position = p["position"]
        disc = pymunk.Circle(puck, p["radius"])
        disc.elasticity = self.puck_elasticity
        disc.friction = p["friction"]
        space.add(puck, disc)
        return space, puck

    def execute(self, command):
        """One rollout on a fresh space: the puck's terminal (x, y)."""
        space, puck = self.build()
        return self.rollout(space, puck, command, 0, None)

    def rollout(self, space, puck, command, start, cache):
        """Steps `command[start:]` on `space` (the puck at the state after
        `command[:start]`); with a `cache`, keeps the puck's state after
        each slot's phase under the command's prefix."""
        dt = self.dt
        for i in range(start, len(command)):
            puck.apply_impulse_at_local_point(self.impulse[command[i]])
            for _ in range(self.phase_steps):
                space.step(dt)
            if cache is not None:
                cache[command[: i + 1]] = (tuple(puck.position), tuple(puck.velocity))
        for _ in range(self.settle_steps):
            space.step(dt)
        return puck.position.x, puck.position.y


    def effect(self, x, y):
        """The effect cell row * cols + col, clamped to the border (as e3d)."""
        g = self.s["grid"]
        w = (g["max"][0] - g["min"][0]) / g["cols"]
        h = (g["max"][1] - g["min"][1]) / g["rows"]
        col = min(max(math.floor((x - g["min"][0]) / w), 0), g["cols"] - 1)
        row = min(max(math.floor((g["max"][1] - y) / h), 0), g["rows"] - 1)
        return row * g["cols"] + col


class Reused:
    """What a user writes: one space for every rollout, the puck put back at
    its start (position, velocity, forces) before each; with `cache`, also
    the puck's state after each slot's phase kept by command prefix, a
    rollout starting from the deepest prefix kept (e3d's prefix states)."""

    def __init__(self, world, cache):
        self.world = world
        self.space, self.puck = world.build()
        self.start = tuple(self.puck.position)
        self.cache = {} if cache else None

    def execute(self, command):
        start, state = 0, (self.start, (0.0, 0.0))
        if self.cache is not None:
            for k in range(len(command) - 1, 0, -1):
                kept = self.cache.get(command[:k])
                if kept is not None:
                    start, state = k, kept
                    break
        puck = self.puck
        puck.position, puck.velocity = state
        puck.angular_velocity = 0.0
        puck.force = (0.0, 0.0)
        self.space.reindex_shapes_for_body(puck)
        return self.world.rollout(self.space, puck, command, start, self.cache)


def command_of(index, symbols, slots):
    out = []
    for _ in range(slots):
        index, k = divmod(index, len(symbols))
        out.append(symbols[k])
    return "".join(out)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("n", type=int, help="the number of distinct random commands")
    ap.add_argument("--scene", default=str(DEFAULT_SCENE), help="the RON file (default: puck_rooms)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--commands-out", help="write the commands here, one per line")
    ap.add_argument("--outcomes-out", help="write command,effect,x,y here")
    ap.add_argument(
        "--mode",
        choices=["fresh", "reuse", "cache"],
        default="fresh",
        help="fresh: a new space per rollout (default); reuse: one space, the puck reset; "
        "cache: reuse plus the puck's state kept by command prefix",
    )
    a = ap.parse_args(argv)

    scene = parse_scene(a.scene)
    world = PuckRooms(scene)
    symbols = [sym for sym, _ in scene["alphabet"]]
    total = len(symbols) ** scene["slots"]
    if not 0 < a.n <= total:
        ap.error(f"N must be in 1..={total}")
    rng = random.Random(a.seed)
    commands = [command_of(i, symbols, scene["slots"]) for i in rng.sample(range(total), a.n)]
    if a.commands_out:
        Path(a.commands_out).write_text("".join(c + "\n" for c in commands))

    runner = world if a.mode == "fresh" else Reused(world, cache=a.mode == "cache")
    outcomes = []
    start = time.perf_counter()
    for c in commands:
        outcomes.append(runner.execute(c))
    secs = time.perf_counter() - start

    if a.outcomes_out:
        with open(a.outcomes_out, "w") as f:
            f.write("command,effect,x,y\n")
            for c, (x, y) in zip(commands, outcomes):
                f.write(f"{c},{world.effect(x, y)},{x!r},{y!r}\n")
    rate = a.n / secs
    print(
        f"pymunk {pymunk.version} (Chipmunk {pymunk.chipmunk_version.split('-')[0]}), {a.mode}: "
        f"{a.n} rollouts of {world.steps_per_command} steps in {secs:.3f} s: "
        f"{rate:.1f} rollouts/s ({rate * world.steps_per_command:.0f} steps/s)"
    )
    print(f"pymunk,puck_rooms,{a.n},{secs:.4f},{rate:.2f},{a.mode}")


if __name__ == "__main__":
    main(sys.argv[1:])
