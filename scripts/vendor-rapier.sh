#!/usr/bin/env bash
# Rebuilds vendor/rapier2d/ (the patched Rapier that Cargo.toml's
# [patch.crates-io] points at) from rapier2d's crates.io source plus
# vendor/rapier2d.diff (see vendor/README.md).
#
#   scripts/vendor-rapier.sh          rebuild vendor/rapier2d/
#   scripts/vendor-rapier.sh --check  rebuild it in a temporary folder and
#                                     fail if vendor/rapier2d/ differs
#   scripts/vendor-rapier.sh --diff   after editing vendor/rapier2d/: write
#                                     vendor/rapier2d.diff anew from it
#
# The crates.io source is fetched with cargo into a throw-away project (the
# repository's own manifests patch rapier2d away, so they cannot fetch it).
# It fails, saying so, if the diff does not apply cleanly, e.g. after a
# version bump: then port the diff or drop it (vendor/README.md).
set -euo pipefail

VERSION=0.36.1
root=$(cd "$(dirname "$0")/.." && pwd)
diff_file="$root/vendor/rapier2d.diff"
dest="$root/vendor/rapier2d"
mode=build
case "${1:-}" in
    --check) mode=check ;;
    --diff) mode=diff ;;
    "") ;;
    *) echo "usage: $0 [--check | --diff]" >&2; exit 2 ;;
esac

[ "$mode" = diff ] || [ -f "$diff_file" ] || { echo "error: $diff_file is missing" >&2; exit 1; }
command -v patch >/dev/null || { echo "error: \`patch\` is needed (apt-get install patch)" >&2; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# 1. the crates.io source of rapier2d $VERSION, through cargo's own cache
mkdir -p "$tmp/fetch/src"
cat > "$tmp/fetch/Cargo.toml" <<TOML
[package]
name = "fetch-rapier2d"
version = "0.0.0"
edition = "2021"
publish = false

[dependencies]
rapier2d = "=$VERSION"
TOML
: > "$tmp/fetch/src/lib.rs"
(cd "$tmp/fetch" && cargo fetch --quiet)
cargo_home=${CARGO_HOME:-$HOME/.cargo}
src=$(ls -d "$cargo_home"/registry/src/*/rapier2d-"$VERSION" 2>/dev/null | head -n 1)
[ -n "$src" ] && [ -f "$src/Cargo.toml" ] || {
    echo "error: cargo fetched no rapier2d-$VERSION under $cargo_home/registry/src" >&2
    exit 1
}

# 2. what cargo needs to build it: the manifest, the readme it names, the
# sources (not its tests, lock file or VCS notes)
out="$tmp/rapier2d"
mkdir -p "$out"
cp "$src/Cargo.toml" "$src/README.md" "$out/"
cp -R "$src/src" "$out/src"

if [ "$mode" = diff ]; then
    # the change as a unified diff against the crates.io source, paths a/
    # and b/ from the crate's root, no time stamps
    mkdir -p "$tmp/d"
    mv "$out" "$tmp/d/a"
    cp -R "$dest" "$tmp/d/b"
    (cd "$tmp/d" && diff -ruN a b || true) \
        | sed -E 's/^((\+\+\+|---) [^\t]*)\t.*$/\1/' > "$diff_file"
    echo "vendor/rapier2d.diff: $(grep -c '^diff ' "$diff_file") file(s) changed"
    exit 0
fi

# 3. the patch; a diff that does not apply exactly is an error
if ! (cd "$out" && patch -p1 --forward --batch --fuzz=0 --no-backup-if-mismatch \
        --reject-file=- < "$diff_file" > "$tmp/patch.log" 2>&1); then
    cat "$tmp/patch.log" >&2
    echo "error: vendor/rapier2d.diff does not apply to rapier2d $VERSION's crates.io source" >&2
    exit 1
fi

if [ "$mode" = check ]; then
    if diff -r "$out" "$dest" > "$tmp/check.log"; then
        echo "vendor/rapier2d is rapier2d $VERSION + vendor/rapier2d.diff"
    else
        cat "$tmp/check.log" >&2
        echo "error: vendor/rapier2d differs from rapier2d $VERSION + vendor/rapier2d.diff (run $0)" >&2
        exit 1
    fi
else
    rm -rf "$dest"
    cp -R "$out" "$dest"
    echo "vendor/rapier2d: rapier2d $VERSION from crates.io + vendor/rapier2d.diff"
fi
