//! The build script: what it tells cargo to watch exists (a missing path
//! makes cargo rerun it, and recompile the crate, at every build), and
//! every file that decides what a command does is part of the physics
//! fingerprint.

#[allow(dead_code)]
#[path = "../../build.rs"]
mod build_rs;

use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn every_watched_path_exists() {
    let watched = build_rs::watched(root());
    for must in ["src/world/physics", "src/effect", "Cargo.lock", "build.rs"] {
        assert!(
            watched.iter().any(|w| w == must),
            "{must} not watched: {watched:?}"
        );
    }
    // the script's own output, as cargo reads it
    for p in &watched {
        assert!(
            root().join(p).exists(),
            "build.rs watches {p}, which does not exist"
        );
    }
    // and nothing else in build.rs names a path to watch
    let text = std::fs::read_to_string(root().join("build.rs")).unwrap();
    assert_eq!(
        text.matches("rerun-if-changed=").count(),
        1,
        "one rerun-if-changed line, fed by watched()"
    );
}

#[test]
fn physics_code_is_in_the_fingerprint() {
    let src = root().join("src");
    let hashed: Vec<PathBuf> = build_rs::physics_files(root());
    let mut all = Vec::new();
    sources(&src, &mut all);
    let mut outside = Vec::new();
    for p in &all {
        let text = std::fs::read_to_string(p).unwrap();
        let rel = p.strip_prefix(&src).unwrap().to_path_buf();
        // the engine's code, and the effect binning
        let physics = text.contains("rapier2d")
            || text.contains("parry2d")
            || text.contains("pub struct Binning")
            || text.contains("pub struct EffectGrid")
            || text.contains("pub struct GridWorld");
        if physics && !hashed.contains(&rel) {
            outside.push(rel);
        }
    }
    assert!(
        outside.is_empty(),
        "physics files outside the fingerprint: {outside:?}"
    );
    for must in [
        "effect/binning.rs",
        "effect/mod.rs",
        "world/grid.rs",
        "world/physics/step.rs",
    ] {
        assert!(hashed.contains(&PathBuf::from(must)), "{must} not hashed");
    }
}

#[test]
fn the_compiled_fingerprint_is_the_sources() {
    assert_eq!(
        e3d::sweep::PHYSICS_FINGERPRINT,
        build_rs::fingerprint(root()),
        "the crate was built from other physics sources than these"
    );
}
