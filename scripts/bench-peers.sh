#!/usr/bin/env bash
# e3d against its strongest peers, in one run (docs/benchmarks.md, "Peers"):
#
#   arm7        every command (3^7 = 2187), open loop: e3d `scene exec` as
#               shipped (mirror symmetry) and without the symmetry, against
#               MuJoCo's native multi-threaded `mujoco.rollout`
#               (benches/peers/arm7_mujoco.py) at dt 1/60 and 1/240, 1 and 2
#               threads each, and
#               Box2D v3 through pyb2d3 (benches/peers/arm7_box2d.py, a
#               Python loop, on N_ARM random commands);
#   puck_rooms  N random distinct commands: e3d `scene exec` against pymunk
#               (benches/pymunk/puck_rooms.py) and Box2D v3 through pyb2d3
#               (benches/peers/puck_rooms_box2d.py), one rollout at a time.
#
# Every e3d figure is a whole process (start-up, parsing, CSV output
# included), the best of REPEAT runs alternating with MuJoCo's; the peers'
# figures are their own timings of the rollouts (best of REPEAT for MuJoCo,
# one run of N for pymunk and Box2D).
# With ACCURACY=1 it also runs the converged references (Rapier at dt/4
# with 8 solver iterations, MuJoCo at dt/8; about 4 CPU-minutes) and prints
# the share of commands landing in the converged Rapier run's cell.
#
#   python3 -m venv /tmp/peers && /tmp/peers/bin/pip install mujoco pymunk pyb2d3 numpy
#   cargo build --release
#   PYTHON=/tmp/peers/bin/python scripts/bench-peers.sh
#
# Options (environment): PYTHON (default python3), E3D (default
# target/release/e3d), N (puck commands, default 3000), REPEAT (default 3),
# N_ARM (Box2D arm commands, default 300), ACCURACY (0 or 1), OUT (a folder for the CSVs; default a temporary one).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}
E3D=${E3D:-target/release/e3d}
N=${N:-3000}
N_ARM=${N_ARM:-300}
REPEAT=${REPEAT:-3}
ACCURACY=${ACCURACY:-0}
OUT=${OUT:-$(mktemp -d)}
mkdir -p "$OUT"

[ -x "$E3D" ] || { echo "no $E3D: run cargo build --release first" >&2; exit 1; }
"$PYTHON" -c "import mujoco, pymunk, numpy" || {
    echo "$PYTHON lacks mujoco, pymunk or numpy (see the header of this script)" >&2
    exit 1
}
HAVE_B2D=1
"$PYTHON" -c "import pyb2d3" 2>/dev/null || HAVE_B2D=0

now() { date +%s.%N; }
# rate_once COMMANDS THREADS SCENE: commands/s of one whole run of
# `e3d scene exec SCENE -` on the file COMMANDS (its CSV left in $OUT/e3d.csv)
rate_once() {
    local cmds=$1 threads=$2 scene=$3 s e n
    n=$(wc -l < "$cmds")
    s=$(now)
    RAYON_NUM_THREADS=$threads "$E3D" scene exec "$scene" - < "$cmds" > "$OUT/e3d.csv" 2> /dev/null
    e=$(now)
    "$PYTHON" -c "print(f'{$n / ($e - $s):.1f}')"
}
max() { "$PYTHON" -c "print(max($1, $2))"; }
ratio() { "$PYTHON" -c "print(f'{$1 / $2:.2f}')"; }

echo "# $(date -u +%FT%TZ), load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "# $("$E3D" --version), $("$PYTHON" -c 'import mujoco, pymunk; print("mujoco", mujoco.__version__, "pymunk", pymunk.version)')"

# ---- arm7 ----
"$PYTHON" -c "
import itertools
print('\n'.join(''.join(p) for p in itertools.product('-0+', repeat=7)))" > "$OUT/arm7_cmds.txt"
# arm7 without its symmetry line: Rapier's own outcome of every command
grep -v '^ *symmetry: FlipY,' scenes/arm7.ron > "$OUT/arm7_nosym.ron"
# the peers and e3d alternate, REPEAT rounds, so that they share the
# machine's load; each figure is the best of its rounds
mj1=0 mj2=0 m41=0 m42=0 a1=0 a2=0 n1=0 n2=0
for _ in $(seq "$REPEAT"); do
    "$PYTHON" benches/peers/arm7_mujoco.py --threads 1,2 --repeat 1 \
        --outcomes-out "$OUT/arm7_mujoco.csv" > "$OUT/mujoco.txt"
    mj1=$(max "$mj1" "$(grep '^mujoco,arm7,1,' "$OUT/mujoco.txt" | cut -d, -f6)")
    mj2=$(max "$mj2" "$(grep '^mujoco,arm7,2,' "$OUT/mujoco.txt" | cut -d, -f6)")
    # MuJoCo at dt 1/240: as accurate as e3d at 1/60 (docs/benchmarks.md)
    "$PYTHON" benches/peers/arm7_mujoco.py --threads 1,2 --repeat 1 --dt-divisor 4 \
        --outcomes-out "$OUT/arm7_mujoco4.csv" > "$OUT/mujoco4.txt"
    m41=$(max "$m41" "$(grep '^mujoco,arm7,1,' "$OUT/mujoco4.txt" | cut -d, -f6)")
    m42=$(max "$m42" "$(grep '^mujoco,arm7,2,' "$OUT/mujoco4.txt" | cut -d, -f6)")
    a1=$(max "$a1" "$(rate_once "$OUT/arm7_cmds.txt" 1 arm7)")
    n1=$(max "$n1" "$(rate_once "$OUT/arm7_cmds.txt" 1 "$OUT/arm7_nosym.ron")")
    a2=$(max "$a2" "$(rate_once "$OUT/arm7_cmds.txt" 2 arm7)")
    n2=$(max "$n2" "$(rate_once "$OUT/arm7_cmds.txt" 2 "$OUT/arm7_nosym.ron")")
    cp "$OUT/e3d.csv" "$OUT/arm7_nosym.csv"
done
b2arm=n/a
if [ "$HAVE_B2D" = 1 ]; then
    b2arm=$("$PYTHON" benches/peers/arm7_box2d.py "$N_ARM" --outcomes-out "$OUT/arm7_box2d.csv" | cut -d, -f5)
fi
echo
echo "| arm7, 2187 commands | 1 thread (commands/s) | 2 threads | vs MuJoCo, 1 thread | 2 threads |"
echo "|---|---|---|---|---|"
echo "| MuJoCo \`mujoco.rollout\`, dt 1/60 | $mj1 | $mj2 | 1 | 1 |"
echo "| MuJoCo \`mujoco.rollout\`, dt 1/240 (4 steps a frame) | $m41 | $m42 | $(ratio "$m41" "$mj1") | $(ratio "$m42" "$mj2") |"
echo "| e3d \`scene exec arm7 -\` (mirror symmetry: 1094 simulated) | $a1 | $a2 | $(ratio "$a1" "$mj1") | $(ratio "$a2" "$mj2") |"
echo "| e3d, every command simulated (no symmetry) | $n1 | $n2 | $(ratio "$n1" "$mj1") | $(ratio "$n2" "$mj2") |"
if [ "$b2arm" != n/a ]; then
    echo "| Box2D v3 (pyb2d3, Python loop, $N_ARM commands, 8 substeps a frame) | $b2arm | | $(ratio "$b2arm" "$mj1") | |"
fi
echo "e3d against MuJoCo at dt 1/240: $(ratio "$a1" "$m41")x (1 thread), $(ratio "$a2" "$m42")x (2 threads) as shipped; $(ratio "$n1" "$m41")x, $(ratio "$n2" "$m42")x without the symmetry"
echo "e3d on 2 threads against 1: $(ratio "$a2" "$a1")x as shipped, $(ratio "$n2" "$n1")x without the symmetry"

if [ "$ACCURACY" = 1 ]; then
    # converged references: Rapier at dt 1/240 with 8 solver iterations,
    # MuJoCo at dt 1/480
    sed -e 's|dt: 0.016666666666666666,|dt: 0.004166666666666667, solver_iterations: 8,|' \
        "$OUT/arm7_nosym.ron" > "$OUT/arm7_ref.ron"
    "$E3D" scene exec "$OUT/arm7_ref.ron" - < "$OUT/arm7_cmds.txt" > "$OUT/arm7_ref.csv" 2> /dev/null
    "$PYTHON" benches/peers/arm7_mujoco.py --threads 2 --repeat 1 --dt-divisor 8 \
        --outcomes-out "$OUT/arm7_mujoco_ref.csv" > /dev/null
    "$PYTHON" - "$OUT" << 'EOF'
import csv, sys
out = sys.argv[1]
def cells(f):
    return {r[0]: r[1] for r in csv.reader(open(f"{out}/{f}")) if r[0] != "command"}
ref = cells("arm7_ref.csv")
mjref = cells("arm7_mujoco_ref.csv")
print("\n| arm7 run | in the converged Rapier run's cell | in the converged MuJoCo run's cell |")
print("|---|---|---|")
import os
for name, f in [("e3d, dt 1/60, 4 iterations (Rapier's own outcome of each command)", "arm7_nosym.csv"),
                ("MuJoCo, dt 1/60", "arm7_mujoco.csv"),
                ("MuJoCo, dt 1/240", "arm7_mujoco4.csv"),
                ("MuJoCo, dt 1/480 (converged)", "arm7_mujoco_ref.csv"),
                ("Box2D v3, 8 substeps a frame", "arm7_box2d.csv")]:
    if not os.path.exists(f"{out}/{f}"):
        continue
    c = cells(f)
    a = sum(c[k] == ref[k] for k in c)
    b = sum(c[k] == mjref[k] for k in c)
    print(f"| {name} | {a} of {len(c)} ({100 * a / len(c):.1f}%) | {b} of {len(c)} ({100 * b / len(c):.1f}%) |")
EOF
fi

# ---- puck_rooms ----
# the peers' parser reads walls written out in full
"$E3D" scene check --expanded puck_rooms > "$OUT/puck_rooms.ron"
pm=$("$PYTHON" benches/pymunk/puck_rooms.py "$N" --scene "$OUT/puck_rooms.ron" \
    --commands-out "$OUT/puck_cmds.txt" | grep '^pymunk,' | cut -d, -f5)
b2=n/a
if [ "$HAVE_B2D" = 1 ]; then
    b2=$("$PYTHON" benches/peers/puck_rooms_box2d.py "$N" --scene "$OUT/puck_rooms.ron" | cut -d, -f5)
fi
p1=0 p2=0
for _ in $(seq "$REPEAT"); do
    p1=$(max "$p1" "$(rate_once "$OUT/puck_cmds.txt" 1 puck_rooms)")
    p2=$(max "$p2" "$(rate_once "$OUT/puck_cmds.txt" 2 puck_rooms)")
done
echo
echo "| puck_rooms, $N distinct commands | rollouts/s | vs pymunk |"
echo "|---|---|---|"
echo "| pymunk, one rollout at a time | $pm | 1 |"
if [ "$b2" != n/a ]; then
    echo "| Box2D v3 (pyb2d3), one rollout at a time | $b2 | $(ratio "$b2" "$pm") |"
fi
echo "| e3d \`scene exec puck_rooms -\`, 1 thread | $p1 | $(ratio "$p1" "$pm") |"
echo "| e3d \`scene exec puck_rooms -\`, 2 threads | $p2 | $(ratio "$p2" "$pm") |"
echo
echo "# load average at end: $(cut -d' ' -f1-3 /proc/loadavg); CSVs in $OUT"
