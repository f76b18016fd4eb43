#!/usr/bin/env bash
# Instructions per E3D trial on two_rooms, from valgrind's callgrind: the
# difference between tight loops of 100k and 600k trials (set-up cancels),
# divided by 500k. Stable from run to run, unlike timings on a shared VM.
#   scripts/trial-instructions.sh [concrete|dyn]
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-concrete}"
cargo build --release --example trial_loop >&2
bin=target/release/examples/trial_loop
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
count() {
  valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.$1" "$bin" "$1" "$mode" >/dev/null 2>"$tmp/log.$1"
  grep -E "Collected" "$tmp/log.$1" | awk '{print $NF}' | tr -d ,
}
a="$(count 100000)"
b="$(count 600000)"
awk -v a="$a" -v b="$b" -v m="$mode" 'BEGIN { printf "%s: %.1f instructions per trial\n", m, (b - a) / 500000 }'
