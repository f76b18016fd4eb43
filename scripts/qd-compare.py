#!/usr/bin/env python3
"""The quality-diversity comparison of docs/quality-diversity.md: on arm7
and three_rooms, at equal numbers of rollouts, e3d's learners (run by
e3d.run_sessions) and pyribs' own MAP-Elites (e3d.qd.map_elites), each
session's archive scored by QD-score and coverage as pyribs computes them
(e3d.qd.Scoring), mean and 95% t-interval over the seeds, and each
method's difference from pyribs' MAP-Elites with its 95% (Welch)
interval. Needs e3d and pyribs (pip install ribs) in the interpreter.

    python3 scripts/qd-compare.py --svg docs/figures/qd-compare.svg   # the docs' table and figure
    python3 scripts/qd-compare.py --seeds 10       # a quick look
    python3 scripts/qd-compare.py --learners e3d,uniform

Prints a Markdown table; --svg also draws it (each method's mean and 95%
interval, QD-score and coverage, per scene). The sessions of a scene share one table cache
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
#: default parameters ("map_elites": e3d's own MAP-Elites, elites by effort)
LEARNERS = ["e3d", "goal_babbling", "uniform", "map_elites"]

#: the quality of each scene's elites: by effort where commands differ in
#: it (Scene.effort_varies: arm7's sum of |torque|), else by reward
#: (three_rooms: every command is 9 impulses of 2.4 N*s; 1 in the far
#: corner's cell)
def quality(scene):
    return "effort" if e3d.Scene.resolve(scene).effort_varies else "reward"

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
    ap.add_argument("--svg", default=None, help="also draw the table into this SVG file")
    args = ap.parse_args()
    cache = args.table_cache or tempfile.mkdtemp(prefix="qd-compare-")
    seeds = list(range(args.seeds))
    print(f"{args.trials} rollouts per session, {args.seeds} seeds (0..{args.seeds - 1}); "
          f"pyribs MAP-Elites: GaussianEmitter, sigma {args.sigma} of a slot's width, "
          f"batches of {args.batch}, the first drawn uniformly\n")
    print("| scene (quality) | method | QD-score | coverage | QD-score − MAP-Elites' | "
          "coverage − MAP-Elites' |")
    print("|---|---|---|---|---|---|")
    drawn = []
    for name in args.scenes.split(","):
        scoring = qd.Scoring(name, quality(name))
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
            drawn.append((f"{name} ({scoring.quality})", method, interval(q), interval(c)))
    if args.svg:
        with open(args.svg, "w") as f:
            f.write(svg(drawn, args.trials, args.seeds))


def svg(rows, trials, seeds):
    """Per scene, two panels (QD-score, coverage): each method's mean as a
    dot with its 95% interval as a bar, on an axis spanning the intervals."""
    scenes = list(dict.fromkeys(r[0] for r in rows))
    methods = list(dict.fromkeys(r[1] for r in rows))
    colours = ["#1f77b4", "#2ca02c", "#7f7f7f", "#d62728", "#9467bd", "#ff7f0e"]
    pw, ph, left, top, gap_x, gap_y = 300, 30 * len(methods) + 20, 130, 50, 60, 60
    width = left + 2 * pw + gap_x + 20
    height = top + len(scenes) * (ph + gap_y) + 10
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
           f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="12">',
           '<rect width="100%" height="100%" fill="white"/>',
           f'<text x="{left}" y="20" font-size="13" font-weight="bold">QD-score and coverage at '
           f'{trials} rollouts: mean and 95% interval over {seeds} seeds (axes not from 0)</text>']
    for si, scene in enumerate(scenes):
        y0 = top + si * (ph + gap_y)
        mine = [r for r in rows if r[0] == scene]
        for pi, (title, k) in enumerate([("QD-score", 2), ("coverage", 3)]):
            x0 = left + pi * (pw + gap_x)
            lo = min(r[k][0] - r[k][1] for r in mine)
            hi = max(r[k][0] + r[k][1] for r in mine)
            pad = 0.08 * (hi - lo) or 0.5
            lo, hi = lo - pad, hi + pad
            scale = pw / (hi - lo)
            out.append(f'<text x="{x0}" y="{y0 - 8}" font-weight="bold">{scene}: {title}</text>')
            out.append(f'<line x1="{x0}" y1="{y0 + ph}" x2="{x0 + pw}" y2="{y0 + ph}" stroke="black"/>')
            for t in range(5):
                v = lo + (hi - lo) * t / 4
                x = x0 + (v - lo) * scale
                out.append(f'<line x1="{x:.1f}" y1="{y0}" x2="{x:.1f}" y2="{y0 + ph}" stroke="#ddd"/>'
                           f'<text x="{x:.1f}" y="{y0 + ph + 14}" text-anchor="middle">{v:.3g}</text>')
            for mi, method in enumerate(methods):
                row = next((r for r in mine if r[1] == method), None)
                if row is None:
                    continue
                m, h = row[k]
                y = y0 + 15 + mi * 30
                c = colours[mi % len(colours)]
                if pi == 0:
                    out.append(f'<text x="{left - 8}" y="{y + 4}" text-anchor="end">{method}</text>')
                at = lambda v: x0 + (v - lo) * scale  # noqa: E731
                out.append(f'<line x1="{at(m - h):.1f}" y1="{y}" x2="{at(m + h):.1f}" '
                           f'y2="{y}" stroke="{c}" stroke-width="3"/>'
                           f'<circle cx="{at(m):.1f}" cy="{y}" r="4" fill="{c}">'
                           f'<title>{method}: {m:.3f} ± {h:.3f}</title></circle>')
    out.append("</svg>")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    main()
