#!/bin/bash
# A real Slurm test of the documented job-array script (docs/cluster.md):
#
#  1. installs slurm-wlm and munge with apt-get if they are missing;
#  2. starts a single-node cluster on localhost (munged, slurmctld, slurmd)
#     from scripts/slurm/slurm.conf.in, with unprivileged ports, state and
#     spool under $E3D_SLURM_DIR (default /tmp/e3d-slurm), or reuses the
#     daemons a previous run of this script left there;
#  3. submits scripts/slurm/sweep-array.sh for scripts/slurm/test-sweep.ron
#     as a 3-task array with `sbatch --wait`, merges the shards with
#     `e3d merge`, runs the same sweep in one process, and compares the
#     final files byte for byte;
#  4. stops the daemons it started (not those it reused or found).
#
# Usage: scripts/slurm/test-cluster.sh        (from anywhere; as root, or with sudo)
#        scripts/slurm/test-cluster.sh stop   (stop a cluster kept with KEEP_CLUSTER=1)
# Environment: E3D (an e3d binary; default: the release build of `cargo test
# --release`, made or refreshed with `cargo test --release --no-run`, which
# reuses its artefacts), E3D_SLURM_DIR, E3D_SLURM_PORT
# (first of two ports, default 16817), KEEP_CLUSTER=1 (leave the daemons
# running for the next run).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
DIR="${E3D_SLURM_DIR:-/tmp/e3d-slurm}"
PORT="${E3D_SLURM_PORT:-16817}"
SHARDS=3
START=$(date +%s)
log() { echo "test-cluster: $*" >&2; }
die() { log "FAILED: $*"; exit 1; }

alive() { [ -f "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }
stop_pidfile() {
    if alive "$1"; then
        local pid; pid="$(cat "$1")"
        log "stopping $(basename "$1" .pid) (pid $pid)"
        kill "$pid" 2>/dev/null || true
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
    fi
    rm -f "$1"
}
if [ "${1:-}" = stop ]; then
    for pf in "$DIR/slurmd.pid" "$DIR/slurmctld.pid" "$DIR/munge/munged.pid"; do stop_pidfile "$pf"; done
    exit 0
fi

SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi

# 1. packages
if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
    || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    log "installing slurm-wlm and munge"
    $SUDO apt-get update -q
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q slurm-wlm munge
fi

# 2. e3d
if [ -z "${E3D:-}" ]; then
    # `cargo test --release --no-run` builds the binary of the test suite:
    # nothing to rebuild after it
    log "building e3d (cargo test --release --no-run)"
    (cd "$ROOT" && cargo test --release --quiet --no-run 2>/dev/null)
    E3D="$ROOT/target/release/e3d"
fi
E3D="$(realpath "$E3D")"
[ -x "$E3D" ] || die "no e3d binary at $E3D"

# 3. the cluster
mkdir -p "$DIR/munge" "$DIR/state" "$DIR/spool" "$DIR/runs"
HOST="$(hostname -s)"
CPUS="$(nproc)"
USER_NAME="$(id -un)"
export SLURM_CONF="$DIR/slurm.conf"
sed -e "s|@HOST@|$HOST|g" -e "s|@DIR@|$DIR|g" -e "s|@CPUS@|$CPUS|g" \
    -e "s|@USER@|$USER_NAME|g" -e "s|@CTLD_PORT@|$PORT|g" \
    -e "s|@SLURMD_PORT@|$((PORT + 1))|g" \
    "$ROOT/scripts/slurm/slurm.conf.in" > "$SLURM_CONF.new"
mv "$SLURM_CONF.new" "$SLURM_CONF"

STARTED=()   # pid files of the daemons this run started
cleanup() {
    local status=$?
    if [ "${KEEP_CLUSTER:-0}" != 1 ]; then
        # stop in reverse order, each by the pid it wrote
        for ((i = ${#STARTED[@]} - 1; i >= 0; i--)); do stop_pidfile "${STARTED[$i]}"; done
    elif [ ${#STARTED[@]} -gt 0 ]; then
        log "KEEP_CLUSTER=1: leaving the daemons running; stop them with $0 stop"
    fi
    exit $status
}
trap cleanup EXIT

MUNGE_SOCKET="$DIR/munge/munge.socket"
if alive "$DIR/munge/munged.pid" && munge -S "$MUNGE_SOCKET" -n </dev/null | unmunge -S "$MUNGE_SOCKET" >/dev/null 2>&1; then
    log "reusing munged (pid $(cat "$DIR/munge/munged.pid"))"
else
    KEY=/etc/munge/munge.key
    if [ ! -r "$KEY" ]; then
        KEY="$DIR/munge/munge.key"
        [ -f "$KEY" ] || { dd if=/dev/urandom of="$KEY" bs=1 count=1024 2>/dev/null; chmod 600 "$KEY"; }
    fi
    # munged refuses a key or folders that others can write; ours are private
    chmod 700 "$DIR/munge"
    rm -f "$MUNGE_SOCKET" "$MUNGE_SOCKET.lock"
    log "starting munged"
    munged --force --socket="$MUNGE_SOCKET" --key-file="$KEY" \
        --pid-file="$DIR/munge/munged.pid" --log-file="$DIR/munge/munged.log" \
        --seed-file="$DIR/munge/munged.seed"
    STARTED+=("$DIR/munge/munged.pid")
    for _ in $(seq 50); do alive "$DIR/munge/munged.pid" && [ -S "$MUNGE_SOCKET" ] && break; sleep 0.1; done
    munge -S "$MUNGE_SOCKET" -n </dev/null | unmunge -S "$MUNGE_SOCKET" >/dev/null \
        || die "munged does not answer; see $DIR/munge/munged.log"
fi

if alive "$DIR/slurmctld.pid"; then
    log "reusing slurmctld (pid $(cat "$DIR/slurmctld.pid"))"
else
    log "starting slurmctld"
    slurmctld -c -f "$SLURM_CONF"   # -c: a clean state, no old jobs
    STARTED+=("$DIR/slurmctld.pid")
fi
if alive "$DIR/slurmd.pid"; then
    log "reusing slurmd (pid $(cat "$DIR/slurmd.pid"))"
else
    log "starting slurmd"
    slurmd -f "$SLURM_CONF" -N "$HOST"
    STARTED+=("$DIR/slurmd.pid")
fi
# wait for the node to be idle
for i in $(seq 120); do
    STATE="$(sinfo -h -N -o %t 2>/dev/null | head -1 || true)"
    case "$STATE" in idle|mix|alloc) break ;; esac
    if [ "$STATE" = "drain" ] || [ "$STATE" = "down" ] || [ "$STATE" = "down*" ] || [ "$STATE" = "drng" ]; then
        scontrol update NodeName="$HOST" State=RESUME 2>/dev/null || true
    fi
    [ "$i" = 120 ] && die "the node never became idle (state '$STATE'); see $DIR/slurmctld.log and $DIR/slurmd.log"
    sleep 0.5
done
log "cluster up: node $HOST, $CPUS CPUs, SLURM_CONF=$SLURM_CONF"

# 4. the sweep: 3 shards through the job-array script, then merged
RUN="$DIR/runs/$(date +%Y%m%d-%H%M%S)-$$"
mkdir -p "$RUN"
SWEEP="$ROOT/scripts/slurm/test-sweep.ron"
log "sbatch --wait --array=1-$SHARDS scripts/slurm/sweep-array.sh"
(cd "$RUN" && sbatch --wait --array=1-$SHARDS --cpus-per-task=1 \
    --export=ALL,SWEEP="$SWEEP",OUT="$RUN/shards",N=$SHARDS,E3D="$E3D" \
    "$ROOT/scripts/slurm/sweep-array.sh") \
    || { cat "$RUN"/e3d-sweep-*.log >&2 2>/dev/null || true; die "the job array failed"; }
"$E3D" merge "$RUN"/shards/shard-* --out "$RUN/merged"
"$E3D" sweep "$SWEEP" --out "$RUN/one" 2>/dev/null >/dev/null
for f in results.csv summary.csv sweep.ron version.txt; do
    cmp "$RUN/one/$f" "$RUN/merged/$f" || die "$f differs between $RUN/one and $RUN/merged"
done
ROWS=$(($(wc -l < "$RUN/merged/results.csv") - 1))
for k in $(seq $SHARDS); do
    [ -s "$RUN/shards/shard-$k/results.csv" ] || die "shard $k wrote no results"
done
log "OK: $SHARDS Slurm array tasks, merged, $ROWS sessions, byte-identical to the one-process run ($(( $(date +%s) - START )) s)"
