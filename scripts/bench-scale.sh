#!/usr/bin/env bash
# The end-to-end speed targets of research-scale command spaces, measured
# in one run (docs/benchmarks.md#research-scale-command-spaces):
#
#   1. e3d run puck_rooms --trials 5000 (no cache) against e3d scene table
#      puck_rooms, same cores;
#   2. a sweep of 100 sessions x 5000 trials on puck_rooms14 (no table
#      possible), 1 and 2 threads: session-trials/s per core, speed-up;
#   3. e3d scene exec puck_rooms - on 3000 distinct commands: rollouts/s;
#   4. pymunk's single-rollout rate on the same 3000 commands, if a Python
#      with pymunk is given as PYTHON (see benches/pymunk/README.md);
#   5. arm7x5, e3d run --trials 5000 --table-cache DIR with the table on
#      disk (built first by e3d scene table);
#   6. e3d run two_rooms --trials 100000000, peak memory without and with
#      --out (set BIG=0 to skip: it writes a 2 GB trials.csv).
#
# Usage: scripts/bench-scale.sh [TRIALS_PER_SESSION]   (default 5000)
# Environment: PYTHON (a python3 with pymunk), BIG=0, E3D (a binary).
set -euo pipefail
cd "$(dirname "$0")/.."
TRIALS="${1:-5000}"
if [ -z "${E3D:-}" ]; then
    cargo build --release --quiet
    E3D=target/release/e3d
fi
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
secs() { # seconds of a command, its output discarded
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>&1
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc -l
}
ratio() { echo "scale=3; $1 / $2" | bc -l; }

echo "# 1. e3d run puck_rooms --trials 5000 against e3d scene table puck_rooms"
table=$(secs "$E3D" scene table puck_rooms)
run=$(secs "$E3D" run puck_rooms --trials 5000)
echo "scene table: ${table} s, run: ${run} s, ratio $(ratio "$run" "$table") (target <= 1.1)"

echo "# 2. sweep 100 x $TRIALS on puck_rooms14"
cat > "$TMP/sweep.ron" <<EOF
Sweep(scenes: ["puck_rooms14"], learners: [e3d], use_reward: [false], params: (),
      sessions: 100, trials: $TRIALS, seed: 1)
EOF
for t in 1 2; do
    s=$(secs "$E3D" sweep "$TMP/sweep.ron" --out "$TMP/sweep-$t" --threads "$t")
    rate=$(echo "100 * $TRIALS / $s" | bc -l)
    printf "threads %d: %.1f s, %.0f session-trials/s (%.0f per core)\n" "$t" "$s" "$rate" \
        "$(echo "$rate / $t" | bc -l)"
    eval "sweep_$t=$s"
done
cmp "$TMP/sweep-1/results.csv" "$TMP/sweep-2/results.csv" && echo "results.csv identical on 1 and 2 threads"
echo "speed-up on 2 threads: $(ratio "$sweep_1" "$sweep_2") (target >= 1.8)"

echo "# 3. e3d scene exec puck_rooms - on 3000 distinct commands (and 4. pymunk on the same)"
if [ -n "${PYTHON:-}" ]; then
    # pymunk's reader wants the walls written out in full
    "$E3D" scene check --expanded puck_rooms > "$TMP/puck_rooms.ron"
    pm=$("$PYTHON" benches/pymunk/puck_rooms.py 3000 --scene "$TMP/puck_rooms.ron" --commands-out "$TMP/cmds.txt" 2>/dev/null \
        | awk -F, '/^pymunk,/ {print $5}')
else
    python3 scripts/random-commands.py ESWN 7 3000 1 > "$TMP/cmds.txt"
fi
exec_s=$(secs sh -c "'$E3D' scene exec puck_rooms - < '$TMP/cmds.txt'")
exec_rate=$(echo "3000 / $exec_s" | bc -l)
printf "scene exec: %.2f s, %.0f rollouts/s\n" "$exec_s" "$exec_rate"
if [ -n "${PYTHON:-}" ]; then
    printf "pymunk: %.0f rollouts/s; scene exec / pymunk: %.2f (target >= 2)\n" "$pm" \
        "$(echo "$exec_rate / $pm" | bc -l)"
    per_core=$(echo "100 * $TRIALS / $sweep_1" | bc -l)
    printf "sweep per core / (pymunk x 540/960): %.2f (target >= 3)\n" \
        "$(echo "$per_core / ($pm * 540 / 960)" | bc -l)"
fi

echo "# 5. arm7x5 with its table on disk"
"$E3D" scene table arm7x5 --cache "$TMP/cache" >/dev/null 2>&1
cached=$(secs "$E3D" run arm7x5 --trials 5000 --table-cache "$TMP/cache")
echo "e3d run arm7x5 --trials 5000 --table-cache: ${cached} s (target < 0.1)"

if [ "${BIG:-1}" != 0 ]; then
    echo "# 6. two_rooms, 100 million trials"
    /usr/bin/time -f "without --out: %e s, peak %M KB" "$E3D" run two_rooms --trials 100000000 >/dev/null
    /usr/bin/time -f "with --out: %e s, peak %M KB" "$E3D" run two_rooms --trials 100000000 \
        --out "$TMP/big" >/dev/null
    ls -l "$TMP/big/trials.csv" | awk '{print "trials.csv: " $5 " bytes"}'
fi
