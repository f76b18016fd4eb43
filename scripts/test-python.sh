#!/usr/bin/env bash
# The Python package's tests: builds the e3d CLI (the tests compare with
# it), installs ./python with pip into a virtual environment (a new one in
# a temporary folder, or $E3D_VENV, created if missing and reused), with
# pytest, gymnasium and numpy, then runs python/tests.
#
#   scripts/test-python.sh                 # cold: a fresh venv, a fresh build
#   E3D_VENV=/tmp/e3d-venv scripts/test-python.sh   # keeps the venv for next time
#
# Prints pytest's summary; exits non-zero if anything fails, and also when
# pytest collects no test (its exit code 5).
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"

python="${PYTHON:-python3}"
if [[ -n "${E3D_VENV:-}" ]]; then
  venv="$E3D_VENV"
else
  tmp="$(mktemp -d)"
  trap 'rm -rf "$tmp"' EXIT
  venv="$tmp/venv"
fi
if [[ ! -x "$venv/bin/python" ]]; then
  "$python" -m venv "$venv"
fi

start=$SECONDS
echo "== cargo build --release (the CLI the tests compare with)"
cargo build --release --quiet --bin e3d

echo "== pip install ./python pytest gymnasium numpy (into $venv)"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet ./python pytest gymnasium numpy
"$venv/bin/python" -c 'import e3d; print("e3d", e3d.__version__, "installed")'

echo "== pytest python/tests"
set +e
E3D_BIN="$root/target/release/e3d" "$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests
status=$?
set -e
echo "== test-python.sh: $((SECONDS - start)) s"
if [[ $status -eq 5 ]]; then
  echo "test-python.sh: pytest collected no test" >&2
  exit 1
fi
exit $status
