"""Quickstart: execute commands, run sessions, and reproduce the paper's
Figure 2 numbers (task 1 on two_rooms: the uniform policy against E3D).

    python python/examples/quickstart.py        # from the repository's root

`e3d reproduce` runs 10 sessions of 5000 trials per learner, session i
seeded with 0 + i, without the reward (task 1), with the paper's task 1
parameters (alpha 0.3, beta 1, lambda 0.03, eta 0.01: run_session's
defaults); the normalised entropy is H / log(18) of the terminal cells over
all trials, given as mean +- sd (sample sd) [min, max] over the sessions.
This script does the same through the Python package and prints its
numbers beside those of docs/figures/summary.md.
"""

import statistics
import time

import numpy as np

import e3d

# docs/figures/summary.md (`e3d reproduce`, seed 0): normalised entropy
PUBLISHED = {
    "uniform": "0.801 +- 0.002 [0.797, 0.805]",
    "e3d": "0.983 +- 0.008 [0.964, 0.993]",
}


def describe(xs):
    return f"{statistics.mean(xs):.3f} +- {statistics.stdev(xs):.3f} [{min(xs):.3f}, {max(xs):.3f}]"


def main():
    scene = e3d.Scene.builtin("two_rooms")
    print(scene, "| commands:", scene.num_commands, "| alphabets:", scene.alphabets)

    # one command, then a batch (numpy in, numpy out)
    world = scene.world()
    print("SEEEEES ->", world.execute("SEEEEES"))  # the rewarded corner of room B
    cmds = scene.parse(["EESSEES", "SEEEEES", "NNNNNNN"])
    out = world.execute_batch(cmds)
    print("effects", out.effect, "rewards", out.reward, "x", out.x, "y", out.y)

    # Figure 2: 10 sessions x 5000 trials per learner, seeds 0..9, no reward
    start = time.perf_counter()
    print("\nFigure 2 (task 1, two_rooms): normalised entropy over 5000 trials, 10 sessions")
    print(f"{'learner':<10} {'this script':<32} {'docs/figures/summary.md'}")
    for learner in ["uniform", "e3d"]:
        # the 10 sessions at once (seeds 0..9, as `e3d run --sessions 10 --seed 0`);
        # each is the run_session of its seed
        batch = e3d.run_sessions(scene, learner=learner, trials=5000, sessions=10, seed=0,
                                 use_reward=False)
        h = batch.metrics["normalized_entropy"].tolist()
        print(f"{learner:<10} {describe(h):<32} {PUBLISHED[learner]}")
    print(f"({time.perf_counter() - start:.2f} s for the 20 sessions)")

    # task 2 on the physics puck, one session: E3D finds the sparse reward
    rec = e3d.run_session("puck_rooms", learner="e3d", trials=5000, seed=0, beta=100.0)
    m = rec.metrics
    print(
        f"\npuck_rooms, E3D beta 100: cumulative reward {m['cumulative_reward']:.0f},"
        f" first reward at trial {m['first_reward_trial']},"
        f" {np.unique(rec.effects).size} distinct effects"
    )

    # the whole motion of the first rewarded command: the puck's path, step by step
    first = int(np.argmax(rec.rewards > 0))
    motion = e3d.Scene.builtin("puck_rooms").world().trace(rec.commands[first])
    b = motion.bodies.index("puck")
    print(
        f"its command {motion.command}: {len(motion)} frames over {motion.time[-1]:.2f} s,"
        f" {motion.bodies[b]} from ({motion.x[0, b]:.2f}, {motion.y[0, b]:.2f})"
        f" to ({motion.x[-1, b]:.2f}, {motion.y[-1, b]:.2f})"
    )


if __name__ == "__main__":
    main()
