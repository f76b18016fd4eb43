#!/usr/bin/env python3
"""Compares the cost lines of `e3d scene check --samples N` and `e3d scene
reward-cell` (the time they announce before they start) with the time
they report having taken, on every shipped scene; exits 1 when an
estimate is off by more than 2x either way.

Usage: scripts/check-estimates.py [E3D_BINARY] [SCENE ...]
(default: target/release/e3d, every shipped scene). Wall-clock figures:
run it on a quiet machine; docs/benchmarks.md records its output.
"""
import re
import subprocess
import sys

SCENES = {
    # scene: samples for `scene check` (about a second or more of work),
    # and whether `scene reward-cell` (every command) is cheap enough here
    "two_rooms": (2000, True),
    "puck_rooms": (600, True),
    "arm7": (300, True),
    "pendulum3": (125, True),
    "maze3": (300, True),
    "puck_rooms14": (200, False),
    "arm7x5": (200, False),
    "three_rooms": (600, False),
    "arm4_gravity": (81, True),
    "arm7_continuous": (200, False),
    "arm_push": (150, True),
    "swimmer": (150, True),
    "cart_pole": (243, True),
}

UNITS = {"ms": 1e-3, "s": 1.0, "min": 60.0, "h": 3600.0}


def seconds(number, unit):
    return float(number) * UNITS[unit]


def run(args):
    p = subprocess.run(args, capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


def main():
    args = sys.argv[1:]
    binary = args.pop(0) if args and "/" in args[0] else "target/release/e3d"
    names = args or list(SCENES)
    worst = 1.0
    bad = []
    print(f"{'scene':<16} {'tool':<22} {'estimate':>10} {'taken':>10} {'taken/estimate':>15}")
    for name in names:
        samples, full = SCENES[name]
        rc, out = run([binary, "scene", "check", name, "--samples", str(samples)])
        est = re.search(r"command\(s\) \(\d+ steps each\) on \d+ thread\(s\): about ([\d.]+) (ms|s|min|h)", out)
        took = re.search(r"^reach.*?\((?:seed \d+, )?([\d.]+) s\)", out, re.M)
        rows = []
        if rc == 0 and est and took:
            rows.append((f"check --samples {samples}", seconds(*est.groups()), float(took.group(1))))
        elif rc == 0 and took:
            # the tools announce a cost only from 1 s on
            print(f"{name:<16} {'check --samples ' + str(samples):<22} {'(none)':>10} {float(took.group(1)):>9.3g}s {'under 1 s':>15}")
        else:
            bad.append(f"{name}: scene check failed (exit {rc})")
        if full:
            rc, out = run([binary, "scene", "reward-cell", name])
            est = re.search(r"simulating \d+ (?:of \d+ )?commands.*? on \d+ thread\(s\).*?: about ([\d.]+) (ms|s|min|h)", out)
            took = re.search(r"executed \d+ commands in ([\d.]+) s", out)
            if rc == 0 and est and took:
                rows.append(("reward-cell", seconds(*est.groups()), float(took.group(1))))
            elif rc == 0 and took:
                print(f"{name:<16} {'reward-cell':<22} {'(none)':>10} {float(took.group(1)):>9.3g}s {'under 1 s':>15}")
            else:
                bad.append(f"{name}: scene reward-cell failed (exit {rc})")
        for tool, e, t in rows:
            # below 0.1 s both are noise (a time slice of a shared machine,
            # thread start, rounding)
            ratio = t / e if e > 0 else float("inf")
            flag = ""
            if max(e, t) >= 0.1 and not (0.5 <= ratio <= 2.0):
                flag = "  <- off by more than 2x"
                bad.append(f"{name} {tool}: estimate {e:.3g} s, taken {t:.3g} s")
            if max(e, t) >= 0.1:
                worst = max(worst, ratio, 1 / ratio)
            print(f"{name:<16} {tool:<22} {e:>9.3g}s {t:>9.3g}s {ratio:>15.2f}{flag}")
    print(f"worst factor (tools taking 0.1 s or more): {worst:.2f}")
    if bad:
        print("\n".join(bad), file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
