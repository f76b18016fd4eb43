//! Computes `E3D_PHYSICS_FINGERPRINT`: a hash of the code that decides
//! what a command does (the physics and grid worlds, the physics scene
//! checks and shorthands, effect binning), of the Rapier and parry
//! versions in Cargo.lock and of the patch applied to the vendored Rapier,
//! if any. It is part of every outcome table's key and of a sweep folder's
//! identity (`e3d::sweep::VERSION`), so that a table or a journal written
//! by a build with other physics is never reused. Whitespace does not
//! count; anything else (comments included) does, which errs on the side
//! of recomputing.
//!
//! Cargo reruns this script only when a path it was told to watch
//! changed, and treats a watched path that does not exist as changed at
//! every build: `main` names each watched path literally, and
//! `tests/library/build_script.rs` checks that each exists and that every
//! physics folder and file is among them.

use std::path::{Path, PathBuf};

fn fnv1a64(bytes: impl IntoIterator<Item = u8>, mut h: u64) -> u64 {
    for b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

/// Every `.rs` file under `dir`, recursively.
fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The folders (under src/) whose every file is physics code, and the
/// single files beside them that are too.
pub const PHYSICS_DIRS: [&str; 4] = [
    "world/physics/",
    "scene/physics/",
    "scene/shorthand/",
    "effect/",
];
pub const PHYSICS_FILES: [&str; 3] = ["world/grid.rs", "scene/enclosure.rs", "scene/overlap.rs"];

/// The patch applied to the vendored Rapier, if the build uses one.
const RAPIER_PATCH: &str = "vendor/rapier2d.diff";

/// Whether `rel` (a path under src/, `/`-separated) is physics code: the
/// physics and grid worlds, the physics scene checks, the shorthands, the
/// effect binning, and the scene checks that call parry.
fn is_physics(rel: &str) -> bool {
    let rel = rel.replace('\\', "/");
    PHYSICS_DIRS.iter().any(|d| rel.starts_with(d)) || PHYSICS_FILES.contains(&rel.as_str())
}

/// The physics files under `root/src`, as paths relative to `root/src`.
pub fn physics_files(root: &Path) -> Vec<PathBuf> {
    let src = root.join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut rel: Vec<PathBuf> = files
        .iter()
        .filter_map(|p| p.strip_prefix(&src).ok())
        .filter(|r| is_physics(&r.to_string_lossy()))
        .map(Path::to_path_buf)
        .collect();
    rel.sort();
    rel
}

/// The fingerprint of the sources under `root`.
pub fn fingerprint(root: &Path) -> String {
    // hashes of the contents, sorted: moving code between files that
    // keep the same text does not matter, any change of text does
    let mut parts: Vec<u64> = physics_files(root)
        .iter()
        .filter_map(|r| std::fs::read(root.join("src").join(r)).ok())
        .chain(std::fs::read(root.join(RAPIER_PATCH)).ok())
        .map(|b| {
            fnv1a64(
                b.into_iter().filter(|c| !c.is_ascii_whitespace()),
                0xcbf29ce484222325,
            )
        })
        .collect();
    parts.sort_unstable();
    // the engine's versions, as Cargo.lock pins them
    if let Ok(lock) = std::fs::read_to_string(root.join("Cargo.lock")) {
        let mut name = "";
        for line in lock.lines() {
            if let Some(n) = line.strip_prefix("name = ") {
                name = n;
            } else if let Some(v) = line.strip_prefix("version = ") {
                if matches!(
                    name,
                    "\"rapier2d\"" | "\"parry2d\"" | "\"nalgebra\"" | "\"glam\""
                ) {
                    parts.push(fnv1a64(
                        format!("{name}{v}").into_bytes(),
                        0xcbf29ce484222325,
                    ));
                }
            }
        }
    }
    let h = parts
        .iter()
        .fold(0xcbf29ce484222325, |h, p| fnv1a64(p.to_le_bytes(), h));
    format!("{:08x}", h >> 32)
}

#[allow(dead_code)] // the tests include this file for its functions, not for main
fn main() {
    let root = Path::new(".");
    println!(
        "cargo:rustc-env=E3D_PHYSICS_FINGERPRINT={}",
        fingerprint(root)
    );
    // every path literally, each one that exists (a missing one reruns
    // this script and recompiles the crate at every build)
    println!("cargo:rerun-if-changed=src/world/physics");
    println!("cargo:rerun-if-changed=src/scene/physics");
    println!("cargo:rerun-if-changed=src/scene/shorthand");
    println!("cargo:rerun-if-changed=src/effect");
    println!("cargo:rerun-if-changed=src/world/grid.rs");
    println!("cargo:rerun-if-changed=src/scene/enclosure.rs");
    println!("cargo:rerun-if-changed=src/scene/overlap.rs");
    println!("cargo:rerun-if-changed=vendor/rapier2d.diff");
    println!("cargo:rerun-if-changed=Cargo.lock");
    println!("cargo:rerun-if-changed=build.rs");
}
