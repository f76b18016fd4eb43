#!/usr/bin/env python3
"""The quality-diversity comparison of docs/quality-diversity.md: on arm7
and three_rooms, at equal numbers of rollouts, e3d's learners (run by
e3d.run_sessions) and pyribs' own MAP-Elites (e3d.qd.map_elites), each
session's archive scored by QD-score and coverage as pyribs computes them
(e3d.qd.Scoring), mean and 95% t-interval over the seeds, and each
method's difference from pyribs' MAP-Elites with its 95% (Welch)
interval. Needs e3d and pyribs (pip install ribs) in the interpreter.

    python3 scripts/qd-compare.py                  # the docs' table: 1000 rollouts, 100 seeds
    python3 scripts/qd-compare.py --seeds 10       # a quick look
    python3 scripts/qd-compare.py --learners e3d,goal_babbling,uniform,map_elites

Prints a Markdown table. The sessions of a scene share one table cache
(--table-cache, default a temporary folder): a command is simulated once
whichever session proposes it.
"""

import argparse
import math
import sys
import tempfile

import numpy as np
from scipy import stats

import e3d
from e3d import qd

#: e3d's built-in learners compared, each run by e3d.run_sessions with its
#: default parameters (e3d's own MAP-Elites, "map_elites", is not in the
#: docs' table yet: add it with --learners).
LEARNERS = ["e3d", "goal_babbling", "uniform"]

#: the quality of each scene's elites: arm7's commands differ in effort
#: (the sum of |torque|), three_rooms' do not (9 impulses of 2.4 N*s), so
#: its elites are scored by reward (1 in the far corner's cell)
QUALITY = {"arm7": "effort", "three_rooms": "reward"}

RIBS = "pyribs MAP-Elites"


def interval(x):
    """Mean and half-width of its 95% t-interval."""
    x = np.asarray(x, dtype=float)
    n = len(x)
    half = stats.t.ppf(0.975, n - 1) * x.std(ddof=1) / math.sqrt(n) if n > 1 else math.nan
    return x.mean(), half


def difference(a, b):
    """Mean of a - mean of b and the half-width of its 95% Welch interval."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    va, vb = a.var(ddof=1) / len(a), b.var(ddof=1) / len(b)
    se = math.sqrt(va + vb)
    if se == 0:
        return a.mean() - b.mean(), 0.0
    df = (va + vb) ** 2 / (va ** 2 / (len(a) - 1) + vb ** 2 / (len(b) - 1))
    return a.mean() - b.mean(), stats.t.ppf(0.975, df) * se


def fmt(mean_half, digits):
    m, h = mean_half
    return f"{m:.{digits}f} ± {h:.{digits}f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default="arm7,three_rooms")
    ap.add_argument("--learners", default=",".join(LEARNERS),
                    help="e3d's learners (run_sessions names), comma-separated")
    ap.add_argument("--trials", type=int, default=1000, help="rollouts per session")
    ap.add_argument("--seeds", type=int, default=100, help="sessions per method: seeds 0..N-1")
    ap.add_argument("--sigma", type=float, default=0.15,
                    help="pyribs' mutation: the Gaussian's sd over each slot's width")
    ap.add_argument("--batch", type=int, default=50, help="pyribs' batch size")
    ap.add_argument("--table-cache", default=None)
    args = ap.parse_args()
    cache = args.table_cache or tempfile.mkdtemp(prefix="qd-compare-")
    seeds = list(range(args.seeds))
    print(f"{args.trials} rollouts per session, {args.seeds} seeds (0..{args.seeds - 1}); "
          f"pyribs MAP-Elites: GaussianEmitter, sigma {args.sigma} of a slot's width, "
          f"batches of {args.batch}, the first drawn uniformly\n")
    print("| scene (quality) | method | QD-score | coverage | QD-score − MAP-Elites' | "
          "coverage − MAP-Elites' |")
    print("|---|---|---|---|---|---|")
    for name in args.scenes.split(","):
        scoring = qd.Scoring(name, QUALITY.get(name, "reward"))
        scores = {}
        for learner in args.learners.split(","):
            batch = e3d.run_sessions(name, learner, trials=args.trials, seeds=seeds,
                                     table_cache=cache)
            el = [scoring.elites(batch.commands[i], batch.effects[i]) for i in range(len(seeds))]
            scores[learner] = el
            print(f"{name} {learner}: done", file=sys.stderr)
        scores[RIBS] = [qd.elites_of(qd.map_elites(name, args.trials, seed, scoring=scoring,
                                                   sigma=args.sigma, batch_size=args.batch), scoring)
                        for seed in seeds]
        print(f"{name} {RIBS}: done", file=sys.stderr)
        ref_q = [scoring.qd_score(e) for e in scores[RIBS]]
        ref_c = [scoring.coverage(e) for e in scores[RIBS]]
        for method, el in scores.items():
            q = [scoring.qd_score(e) for e in el]
            c = [scoring.coverage(e) for e in el]
            dq = "" if method == RIBS else fmt(difference(q, ref_q), 2)
            dc = "" if method == RIBS else fmt(difference(c, ref_c), 3)
            print(f"| {name} ({scoring.quality}) | {method} | {fmt(interval(q), 2)} | "
                  f"{fmt(interval(c), 3)} | {dq} | {dc} |")


if __name__ == "__main__":
    main()
