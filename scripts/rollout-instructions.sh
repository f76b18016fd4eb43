#!/usr/bin/env bash
# Instructions per simulated command of a physics scene, from valgrind's
# callgrind: `e3d scene exec SCENE -` on one thread over the first 30 and the
# first 10 of a fixed random sample of its commands (scripts/random-commands.py,
# seed 0); the difference divided by 20 (start-up and parsing cancel).
# Stable from run to run, unlike timings on a shared machine.
# With --one-copy, the commands run one `World::execute` each on a world
# of one copy keeping no prefix state (examples/one_copy.rs, built first
# with `cargo build --release --example one_copy`), as Python's
# `World.execute` runs them with every step simulated.
#
#   scripts/rollout-instructions.sh [--one-copy] SCENE ALPHABET SLOTS
#   scripts/rollout-instructions.sh scenes/arm7.ron -0+ 7
#   scripts/rollout-instructions.sh --one-copy puck_rooms ESWN 7
#
# A scene with a symmetry reflects some commands instead of simulating
# them: give a copy without its `symmetry` line to count simulations.
# E3D (default target/release/e3d) picks the binary, e.g. to compare builds.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
one_copy=
if [ "${1:-}" = --one-copy ]; then
    one_copy=$here/../target/release/examples/one_copy
    shift
    [ -x "$one_copy" ] || { echo "no $one_copy: run cargo build --release --example one_copy first" >&2; exit 1; }
fi
[ $# -eq 3 ] || { sed -n '2,18p' "$0" >&2; exit 2; }
scene=$1 alphabet=$2 slots=$3
E3D=${E3D:-$here/../target/release/e3d}
[ -n "$one_copy" ] || [ -x "$E3D" ] || { echo "no $E3D: run cargo build --release first" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 "$here/random-commands.py" "$alphabet" "$slots" 30 0 > "$tmp/30.txt"
head -n 10 "$tmp/30.txt" > "$tmp/10.txt"
count() {
    local run=("$E3D" scene exec "$scene" -)
    [ -z "$one_copy" ] || run=("$one_copy" "$scene")
    RAYON_NUM_THREADS=1 valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.$1" \
        "${run[@]}" < "$tmp/$1.txt" > "$tmp/out.$1" 2> "$tmp/log.$1"
    grep -E "Collected" "$tmp/log.$1" | awk '{print $NF}' | tr -d ,
}
a=$(count 10)
b=$(count 30)
awk -v a="$a" -v b="$b" -v s="$scene" \
    'BEGIN { printf "%s: %.2f M instructions per command (%d for 10 commands, %d for 30)\n", s, (b - a) / 20 / 1e6, a, b }'
