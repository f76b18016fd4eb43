#!/usr/bin/env python3
"""The cross-check table of docs/physics.md: every shipped physics scene
run in e3d and in MuJoCo on the same random commands (`e3d.crosscheck`),
printed as a Markdown table. Needs the e3d wheel and `mujoco`
(`pip install 'e3d[mujoco]'`).

    python3 scripts/mjcf-crosscheck.py [COMMANDS] [SEED]     # default 200 0
"""

import sys

import numpy as np

import e3d


def cell(d: np.ndarray) -> str:
    if len(d) == 0:
        return "—"
    return f"{np.median(d):.2g} / {np.quantile(d, 0.9):.2g} ({len(d)})"


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 200
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 0
    print("| scene | cells agree | no contact: median / p90 (commands) | contact: median / p90 (commands) |")
    print("|---|---|---|---|")
    for name in e3d.Scene.builtins():
        if e3d.Scene.builtin(name).kind != "physics":
            continue
        out = e3d.crosscheck(name, commands=n, seed=seed)
        d, c = out["distance"], out["contact"]
        print(f"| {name} | {100 * out['agree'].mean():.1f}% | {cell(d[~c])} | {cell(d[c])} |", flush=True)


if __name__ == "__main__":
    main()
