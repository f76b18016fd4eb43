#!/usr/bin/env python3
"""The reproducibility measurement of docs/analysis.md ("Reproducibility
under noise"): runs scenes/sweeps/reproducibility.ron (puck_rooms with 5%
action noise, E3D and the uniform policy, 100 sessions each), then draws
docs/figures/reproducibility.svg from its summary.csv and prints the table.

    python3 scripts/reproducibility.py [--e3d target/release/e3d] [--runs DIR]

The sweep is resumed when DIR holds part of it (`e3d sweep --resume`).
Standard library only.
"""

import argparse
import csv
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SWEEP = os.path.join(ROOT, "scenes", "sweeps", "reproducibility.ron")
FIGURE = os.path.join(ROOT, "docs", "figures", "reproducibility.svg")
METRICS = [
    ("reproducibility", "reproducibility of the final policy"),
    ("normalized_entropy", "normalised entropy of the effects"),
    ("coverage", "coverage of the 18 cells"),
]


def cells(summary):
    """The rows of summary.csv: (label, {metric: (mean, low, high)})."""
    with open(summary, newline="") as f:
        rows = list(csv.DictReader(f))
    out = []
    for r in rows:
        name = "E3D" if r["learner"] == "e3d" else "uniform policy"
        task = "task 2 (reward)" if r["use_reward"] == "true" else "task 1"
        values = {
            m: tuple(float(r[f"{m}_{k}"]) for k in ("mean", "ci_low", "ci_high"))
            for m, _ in METRICS
        }
        out.append((f"{name}, {task}", int(r["sessions"]), values))
    return out


def svg(rows):
    """Horizontal bars with their 95% intervals, one panel per metric."""
    bar, gap, left, width, panel_gap = 22, 8, 230, 260, 40
    height_of = len(rows) * (bar + gap)
    w = left + len(METRICS) * (width + panel_gap)
    h = height_of + 70
    s = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" '
        f'font-family="sans-serif" font-size="12">',
        f'<rect width="{w}" height="{h}" fill="white"/>',
    ]
    colours = {"E3D": "#3465a4", "uniform policy": "#888a85"}
    for i, (label, _, _) in enumerate(rows):
        y = 40 + i * (bar + gap) + bar / 2 + 4
        s.append(f'<text x="{left - 8}" y="{y}" text-anchor="end">{label}</text>')
    for p, (metric, title) in enumerate(METRICS):
        x0 = left + p * (width + panel_gap)
        s.append(f'<text x="{x0}" y="20" font-weight="bold">{title}</text>')
        for t in range(0, 11, 2):
            x = x0 + width * t / 10
            s.append(f'<line x1="{x}" y1="34" x2="{x}" y2="{40 + height_of}" stroke="#ddd"/>')
            s.append(f'<text x="{x}" y="{56 + height_of}" text-anchor="middle">{t / 10:g}</text>')
        for i, (label, _, values) in enumerate(rows):
            mean, low, high = values[metric]
            y = 40 + i * (bar + gap)
            colour = colours[label.split(",")[0]]
            s.append(
                f'<rect x="{x0}" y="{y}" width="{width * mean:.1f}" height="{bar}" fill="{colour}"/>'
            )
            mid = y + bar / 2
            lo, hi = x0 + width * low, x0 + width * min(high, 1.0)
            s.append(f'<line x1="{lo:.1f}" y1="{mid}" x2="{hi:.1f}" y2="{mid}" stroke="black"/>')
            for x in (lo, hi):
                s.append(
                    f'<line x1="{x:.1f}" y1="{mid - 5}" x2="{x:.1f}" y2="{mid + 5}" stroke="black"/>'
                )
    s.append("</svg>")
    return "\n".join(s) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--e3d", default=os.path.join(ROOT, "target", "release", "e3d"))
    ap.add_argument("--runs", default=os.path.join(ROOT, "runs", "reproducibility"))
    ap.add_argument("--out", default=FIGURE, help="the SVG file to write")
    a = ap.parse_args()
    cmd = [a.e3d, "sweep", SWEEP, "--out", a.runs]
    if os.path.exists(os.path.join(a.runs, "journal.txt")):
        cmd.append("--resume")
    if subprocess.call(cmd) != 0:
        sys.exit("the sweep failed")
    rows = cells(os.path.join(a.runs, "summary.csv"))
    with open(a.out, "w") as f:
        f.write(svg(rows))
    print("| cell | sessions | reproducibility | normalised entropy | coverage |")
    print("|---|---|---|---|---|")
    for label, n, v in rows:
        shown = [f"{v[m][0]:.3f} [{v[m][1]:.3f}, {v[m][2]:.3f}]" for m, _ in METRICS]
        print(f"| {label} | {n} | " + " | ".join(shown) + " |")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
