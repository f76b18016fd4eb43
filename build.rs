//! Computes `E3D_PHYSICS_FINGERPRINT`: a hash of the code that decides
//! what a command does (the physics and grid worlds, the physics scene
//! checks and shorthands, effect binning) and of the Rapier and parry
//! versions in Cargo.lock. It is part of every outcome table's key and
//! of a sweep folder's identity (`e3d::sweep::VERSION`), so that a
//! table or a journal written by a build with other physics is never
//! reused. Whitespace does not count; anything else (comments included)
//! does, which errs on the side of recomputing.

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

/// Whether `rel` (a path under src/) is physics code: anything named
/// `physics*` (files or folders) under src/world or src/scene, the grid
/// world, the shorthands and the effect binning.
fn is_physics(rel: &str) -> bool {
    let rel = rel.replace('\\', "/");
    ((rel.starts_with("world/") || rel.starts_with("scene/")) && rel.contains("physics"))
        || rel == "world/grid.rs"
        || rel.starts_with("scene/shorthand")
        || rel == "effect.rs"
}

fn main() {
    let src = Path::new("src");
    let mut files = Vec::new();
    rust_files(src, &mut files);
    // hashes of the contents, sorted: moving code between files that
    // keep the same text does not matter, any change of text does
    let mut parts: Vec<u64> = files
        .iter()
        .filter(|p| {
            p.strip_prefix(src)
                .is_ok_and(|r| is_physics(&r.to_string_lossy()))
        })
        .filter_map(|p| std::fs::read(p).ok())
        .map(|b| {
            fnv1a64(
                b.into_iter().filter(|c| !c.is_ascii_whitespace()),
                0xcbf29ce484222325,
            )
        })
        .collect();
    parts.sort_unstable();
    // the engine's versions, as Cargo.lock pins them
    if let Ok(lock) = std::fs::read_to_string("Cargo.lock") {
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
    println!("cargo:rustc-env=E3D_PHYSICS_FINGERPRINT={:08x}", h >> 32);
    println!("cargo:rerun-if-changed=src/world");
    println!("cargo:rerun-if-changed=src/scene");
    println!("cargo:rerun-if-changed=src/effect.rs");
    println!("cargo:rerun-if-changed=Cargo.lock");
    println!("cargo:rerun-if-changed=build.rs");
}
