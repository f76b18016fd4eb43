"""E3dVectorEnv (one execute_batch a step) against gymnasium's
SyncVectorEnv over E3dEnv, at 64 environments on puck_rooms, the same
random actions (action_space.seed(0)) for both, new environments (empty
outcome memos) each run.

    python python/examples/bench_vector_env.py [STEPS] [RUNS]

Prints the environment steps per second (vector steps x 64) of each, and
their ratio; also SyncVectorEnv over environments whose worlds keep no
prefix state (`Scene.world(prefix_states=0)`: every step simulated), the
single-environment path as it was before prefix states.

The three are timed one after the other within each run, so that each
run's ratio compares them under the same load: on a shared machine the
paired ratios (median and range printed) vary less than the ratio of the
medians.
"""

import statistics
import sys
import time

from gymnasium.vector import AutoresetMode, SyncVectorEnv

from e3d.gym import E3dEnv, E3dVectorEnv

N = 64


def rate(env, actions):
    env.reset(seed=0)
    s = time.perf_counter()
    for a in actions:
        env.step(a)
    return len(actions) * N / (time.perf_counter() - s)


def plain_env():
    """An E3dEnv whose world simulates every step of every command."""
    env = E3dEnv("puck_rooms")
    env.world = env.scene.world(prefix_states=0)
    return env


def main():
    steps = int(sys.argv[1]) if len(sys.argv) > 1 else 40
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    probe = E3dVectorEnv("puck_rooms", N)
    probe.action_space.seed(0)
    actions = [probe.action_space.sample() for _ in range(steps)]
    vec, sync, plain = [], [], []
    for _ in range(runs):
        vec.append(rate(E3dVectorEnv("puck_rooms", N), actions))
        sync.append(rate(SyncVectorEnv([lambda: E3dEnv("puck_rooms") for _ in range(N)],
                                       autoreset_mode=AutoresetMode.SAME_STEP), actions))
        plain.append(rate(SyncVectorEnv([plain_env for _ in range(N)],
                                        autoreset_mode=AutoresetMode.SAME_STEP), actions))
    v, s, p = statistics.median(vec), statistics.median(sync), statistics.median(plain)
    paired = [a / b for a, b in zip(vec, sync)]
    print(f"E3dVectorEnv  steps/s: median {v:.0f}, range {min(vec):.0f}-{max(vec):.0f} ({runs} runs)")
    print(f"SyncVectorEnv steps/s: median {s:.0f}, range {min(sync):.0f}-{max(sync):.0f} ({runs} runs)")
    print(f"SyncVectorEnv, every step simulated: median {p:.0f}, range {min(plain):.0f}-{max(plain):.0f}")
    print(f"ratio: {v / s:.1f}x (against every step simulated: {v / p:.1f}x)")
    print(f"ratio run by run: median {statistics.median(paired):.1f}x, "
          f"range {min(paired):.1f}x-{max(paired):.1f}x")


if __name__ == "__main__":
    main()
