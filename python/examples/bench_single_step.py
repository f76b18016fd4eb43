"""One command at a time from Python: `World.execute` (and `E3dEnv.step`)
on puck_rooms against the pure-Python pymunk loop of
benches/pymunk/puck_rooms.py, on the same distinct commands, in one run
(pymunk reads the scene as `Scene.to_ron()` writes it: the walls written
out in full).

    python python/examples/bench_single_step.py [N] [RUNS]

pymunk executes N random distinct commands (its --seed 1), one rollout at
a time, and writes them; e3d then executes the same N commands one
`World.execute` call at a time on a new World (every call a simulation:
no command repeats, so the outcome memo never answers; a command that
shares a prefix with an earlier one starts from the phase-end state kept),
then on a new World that keeps no prefix state (`prefix_states=0`: every
step of every command simulated, as pymunk does), then with
`execute_batch` of one command at a time (a lone new command of a batch
runs on the same world of one copy), then with `E3dEnv.step` on a new
environment. Runs alternate; medians are printed, and
each target ratio run by run (each run's own pair, timed minutes apart
at most: steadier than the ratio of the medians on a shared machine):
`World.execute` against pymunk's fresh space, every step simulated against
pymunk reusing its space, `World.execute` against pymunk with the prefix
cache, on one core (RAYON_NUM_THREADS=1 is set: a single command never
uses more than one anyway).
"""

import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

os.environ.setdefault("RAYON_NUM_THREADS", "1")

import e3d  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    scene = e3d.Scene.builtin("puck_rooms")
    rates = {"pymunk": [], "pymunk reuse": [], "pymunk cache": [], "World.execute": [],
             "every step": [], "batch of one": [], "E3dEnv.step": []}
    with tempfile.TemporaryDirectory() as tmp:
        cmds_path = pathlib.Path(tmp) / "commands.txt"
        # the scene as pymunk's reader wants it: written out in full
        # (Scene.to_ron expands the shorthand walls of scenes/puck_rooms.ron)
        scene_path = pathlib.Path(tmp) / "puck_rooms.ron"
        scene_path.write_text(scene.to_ron())
        for _ in range(runs):
            r = subprocess.run(
                [sys.executable, str(ROOT / "benches/pymunk/puck_rooms.py"), str(n), "--seed", "1",
                 "--scene", str(scene_path), "--commands-out", str(cmds_path)],
                capture_output=True, text=True, check=True)
            line = [x for x in r.stdout.splitlines() if x.startswith("pymunk,")][-1]
            rates["pymunk"].append(float(line.split(",")[4]))
            # what a user writes: one space, the puck reset; and with the
            # puck's state kept by command prefix, as e3d keeps its own
            for mode in ("reuse", "cache"):
                r = subprocess.run(
                    [sys.executable, str(ROOT / "benches/pymunk/puck_rooms.py"), str(n), "--seed",
                     "1", "--scene", str(scene_path), "--mode", mode],
                    capture_output=True, text=True, check=True)
                line = [x for x in r.stdout.splitlines() if x.startswith("pymunk,")][-1]
                rates[f"pymunk {mode}"].append(float(line.split(",")[4]))
            cmds = scene.parse(cmds_path.read_text().split())
            w = scene.world()
            s = time.perf_counter()
            for c in cmds:
                w.execute(c)
            rates["World.execute"].append(n / (time.perf_counter() - s))
            # every step simulated: no prefix state kept
            w = scene.world(prefix_states=0)
            s = time.perf_counter()
            for c in cmds:
                w.execute(c)
            rates["every step"].append(n / (time.perf_counter() - s))
            # a batch of one command: a lone new command runs on the
            # world of one copy, as World.execute does
            w = scene.world()
            s = time.perf_counter()
            for i in range(n):
                w.execute_batch(cmds[i:i + 1])
            rates["batch of one"].append(n / (time.perf_counter() - s))
            try:
                from e3d.gym import E3dEnv
            except ImportError:
                continue
            env = E3dEnv(scene)
            env.reset(seed=0)
            s = time.perf_counter()
            for c in cmds:
                env.step(c)
            rates["E3dEnv.step"].append(n / (time.perf_counter() - s))
    for k, v in rates.items():
        if v:
            print(f"{k:<14} rollouts/s: median {statistics.median(v):.0f}, range {min(v):.0f}-{max(v):.0f} ({len(v)} runs)")
    e, p = statistics.median(rates["World.execute"]), statistics.median(rates["pymunk"])
    print(f"World.execute / pymunk: {e / p:.2f}x")
    f = statistics.median(rates["every step"])
    print(f"World.execute with every step simulated (prefix_states=0) / pymunk: {f / p:.2f}x")
    r, c = statistics.median(rates["pymunk reuse"]), statistics.median(rates["pymunk cache"])
    print(f"every step simulated / pymunk reuse: {f / r:.2f}x")
    print(f"World.execute (prefix states) / pymunk reuse with a prefix cache: {e / c:.2f}x")
    for name, ours, theirs in (("World.execute / pymunk", "World.execute", "pymunk"),
                               ("every step simulated / pymunk reuse", "every step", "pymunk reuse"),
                               ("World.execute / pymunk cache", "World.execute", "pymunk cache")):
        paired = [a / b for a, b in zip(rates[ours], rates[theirs])]
        print(f"{name} run by run: median {statistics.median(paired):.2f}x, "
              f"range {min(paired):.2f}x-{max(paired):.2f}x")


if __name__ == "__main__":
    main()
