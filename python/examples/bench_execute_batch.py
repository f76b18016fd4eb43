"""execute_batch from Python against `e3d scene exec puck_rooms -` on the
same 3000 distinct commands (those of docs/benchmarks.md: Python's
random.seed(1), 3000 sampled from every command of ESWN^7).

    python python/examples/bench_execute_batch.py [RUNS] [E3D_BIN]

Runs alternate between the two. The CLI is timed as a whole process
(start-up, reading, printing); Python times the `execute_batch` call on
a new World each run (a World keeps its outcomes: a second call would only
look them up), separately the same call with the strings parsed too, and
the call with a progress callback (a batch of more than 256 commands runs
on a thread of its own either way, the caller checking for Ctrl-C every
50 ms).
"""

import itertools
import random
import statistics
import subprocess
import sys
import tempfile
import time

import e3d


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 7
    cli = sys.argv[2] if len(sys.argv) > 2 else "target/release/e3d"
    cmds = ["".join(p) for p in itertools.product("ESWN", repeat=7)]
    random.seed(1)
    sample = random.sample(cmds, 3000)
    text = "\n".join(sample) + "\n"
    scene = e3d.Scene.builtin("puck_rooms")
    array = scene.parse(sample)
    with tempfile.TemporaryFile("w+") as f:
        f.write(text)
        rates = {"cli": [], "py": [], "py+parse": [], "py+progress": []}
        calls = []
        rows = None
        for _ in range(runs):
            f.seek(0)
            s = time.perf_counter()
            r = subprocess.run([cli, "scene", "exec", "puck_rooms", "-"], stdin=f,
                               capture_output=True, text=True, check=True)
            rates["cli"].append(3000 / (time.perf_counter() - s))
            rows = r.stdout.splitlines()[1:]
            w = scene.world()
            s = time.perf_counter()
            out = w.execute_batch(array)
            rates["py"].append(3000 / (time.perf_counter() - s))
            w = scene.world()
            s = time.perf_counter()
            w.execute_batch(scene.parse(sample))
            rates["py+parse"].append(3000 / (time.perf_counter() - s))
            w = scene.world()
            s = time.perf_counter()
            w.execute_batch(array, progress=lambda done, total: calls.append(done))
            rates["py+progress"].append(3000 / (time.perf_counter() - s))
    same = [int(line.split(",")[1]) for line in rows] == out.effect.tolist()
    for k, v in rates.items():
        print(f"{k:<12} rollouts/s: median {statistics.median(v):.0f}, range {min(v):.0f}-{max(v):.0f} ({runs} runs)")
    print("effects equal to the CLI's:", same, f"| progress calls: {len(calls) / runs:.1f} a batch")


if __name__ == "__main__":
    main()
