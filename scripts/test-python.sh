#!/usr/bin/env bash
# The Python package's tests: builds the e3d CLI (the tests compare with
# it), creates a virtual environment (a new one in a temporary folder, or
# $E3D_VENV, created if missing and reused) with pytest, gymnasium, numpy,
# mypy, maturin and submitit (whose local executor runs the job-array
# recipe), and pyribs (e3d.qd's tests: without it they are skipped),
# builds the package's abi3 wheel with `maturin build
# --release` (cargo's target folder: $E3D_PY_TARGET, default
# target/python under the repository's root, beside the CLI's build and
# ignored by git like it), installs that wheel, checks the type stubs
# against the installed module (mypy's stubtest) and the source
# distribution (maturin sdist: what it holds, and that cargo resolves the
# e3d crate inside it), then runs python/tests against the installed
# wheel.
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
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
venv="${E3D_VENV:-$tmp/venv}"
if [[ ! -x "$venv/bin/python" ]]; then
  "$python" -m venv "$venv"
fi

start=$SECONDS
echo "== cargo build --release (the CLI the tests compare with)"
cargo build --release --quiet --bin e3d

echo "== pip install pytest gymnasium numpy mypy maturin submitit (into $venv)"
"$venv/bin/python" -m pip install --quiet --upgrade pip
"$venv/bin/python" -m pip install --quiet pytest gymnasium numpy mypy submitit 'maturin>=1.7,<2'
# pyribs (e3d.qd, the `qd` extra): where it cannot be installed, its tests are skipped
"$venv/bin/python" -m pip install --quiet ribs \
  || echo "test-python.sh: pyribs not installed: e3d.qd's pyribs tests will be skipped" >&2

pytarget="${E3D_PY_TARGET:-$root/target/python}"
echo "== maturin build --release (an abi3 wheel; cargo's target folder: $pytarget)"
(cd python && CARGO_TARGET_DIR="$pytarget" "$venv/bin/maturin" build --release \
  --interpreter "$venv/bin/python" --out "$tmp/wheels")
wheel=("$tmp"/wheels/e3d-*.whl)
if [[ ${#wheel[@]} -ne 1 || "${wheel[0]}" != *-abi3-* ]]; then
  echo "test-python.sh: expected one abi3 wheel, found: ${wheel[*]}" >&2
  exit 1
fi
echo "== pip install $(basename "${wheel[0]}")"
"$venv/bin/python" -m pip install --quiet --force-reinstall --no-deps "${wheel[0]}"
# the tests import the installed wheel, not ./python/e3d
(cd "$tmp" && "$venv/bin/python" -c 'import e3d, sys; f = e3d.__file__; assert "site-packages" in f, f; print("e3d", e3d.__version__, "installed from the wheel:", f)')

echo "== stubtest e3d (the stubs against the built module)"
(cd "$venv" && "$venv/bin/python" -m mypy.stubtest --concise e3d)

echo "== mypy --strict -p e3d (the installed package as a user's type checker reads it)"
(cd "$venv" && "$venv/bin/python" -m mypy --strict --no-error-summary -p e3d)

echo "== maturin sdist (the source distribution holds what its build needs)"
sdist="$tmp/sdist"
(cd python && "$venv/bin/maturin" sdist --out "$sdist" >/dev/null 2>&1) || {
  echo "test-python.sh: maturin sdist failed:" >&2
  (cd python && "$venv/bin/maturin" sdist --out "$sdist") >&2 || true
  exit 1
}
tar -xzf "$sdist"/e3d-*.tar.gz -C "$sdist"
"$venv/bin/python" - "$sdist"/e3d-*/ <<'PY'
import json, pathlib, subprocess, sys
top = pathlib.Path(sys.argv[1]).resolve()
need = ["pyproject.toml", "e3d/__init__.py", "e3d/_e3d.pyi", "e3d/py.typed", "e3d/gym.py",
        "python/Cargo.toml", "python/Cargo.lock", "python/src/lib.rs", "Cargo.toml",
        "src/lib.rs", "scenes/two_rooms.ron", "scenes/arm7x5.ron",
        # the patched Rapier ([patch.crates-io], vendor/README.md) and its diff
        "vendor/rapier2d/Cargo.toml", "vendor/rapier2d/src/lib.rs", "vendor/rapier2d.diff"]
missing = [n for n in need if not (top / n).is_file()]
# every file the crate includes at compile time (built-in scenes, docs)
import re
for rs in (top / "src").rglob("*.rs"):
    for inc in re.findall(r'include_(?:str|bytes)!\("([^"]+)"\)', rs.read_text()):
        if not (rs.parent / inc).is_file():
            missing.append(f"{inc} (included by {rs.relative_to(top)})")
assert not missing, f"the sdist lacks {missing}"
assert 'manifest-path = "python/Cargo.toml"' in (top / "pyproject.toml").read_text()
meta = json.loads(subprocess.run(
    ["cargo", "metadata", "--format-version", "1", "--manifest-path", str(top / "python/Cargo.toml")],
    check=True, capture_output=True, text=True).stdout)
lib = [p for p in meta["packages"] if p["name"] == "e3d"]
assert lib and pathlib.Path(lib[0]["manifest_path"]).resolve() == top / "Cargo.toml", lib
rapier = [p for p in meta["packages"] if p["name"] == "rapier2d"]
assert len(rapier) == 1 and pathlib.Path(rapier[0]["manifest_path"]).resolve() == \
    top / "vendor/rapier2d/Cargo.toml", f"rapier2d is not the vendored one: {rapier}"
print("sdist ok:", top.name, "with the e3d crate and the patched rapier2d inside")
PY

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
