"""`World.execute_batch` of new commands, by batch size, on puck_rooms:
the milliseconds one batch takes (each batch's commands new to the world:
every one simulated). Shows what a batch smaller than the worlds' 32
copies per thread costs (the copies without a command are switched off).

    python python/examples/bench_batch_sizes.py [SIZES...]
    RAYON_NUM_THREADS=1 python python/examples/bench_batch_sizes.py 64

For each size (default 64 52 32 16): 5 repetitions of 20 batches, each on
a new World; prints the fastest and the median repetition's mean time per
batch. With two threads a batch splits into two pieces, one world each.
"""

import statistics
import sys
import time

import numpy as np

import e3d


def main():
    sizes = [int(a) for a in sys.argv[1:]] or [64, 52, 32, 16]
    scene = e3d.Scene.builtin("puck_rooms")
    rng = np.random.default_rng(0)
    order = rng.permutation(scene.num_commands)
    cmds = np.array([[(i >> (2 * k)) & 3 for k in range(7)] for i in order], dtype=np.uint8)
    for size in sizes:
        times = []
        for rep in range(5):
            w = scene.world()
            s = time.perf_counter()
            for k in range(20):
                start = (rep * 20 + k) * 64
                w.execute_batch(cmds[start:start + size])
            times.append((time.perf_counter() - s) / 20)
        print(f"batch of {size}: {1e3 * min(times):.2f} ms (fastest), "
              f"{1e3 * statistics.median(times):.2f} ms (median)")


if __name__ == "__main__":
    main()
