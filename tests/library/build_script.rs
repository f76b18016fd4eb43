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
    let text = std::fs::read_to_string(root().join("build.rs")).unwrap();
    let watched: Vec<&str> = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("println!(\"cargo:rerun-if-changed="))
        .map(|l| l.trim_end_matches("\");"))
        .collect();
    // the script's own lines, as cargo reads them: each a literal path
    assert_eq!(
        watched.len(),
        text.matches("rerun-if-changed=").count(),
        "a watched path that is not written literally: {watched:?}"
    );
    for p in &watched {
        assert!(!p.contains('{'), "not a literal path: {p}");
        assert!(
            root().join(p).exists(),
            "build.rs watches {p}, which does not exist"
        );
    }
    // every physics folder and file, Cargo.lock and the script itself
    let physics = build_rs::PHYSICS_DIRS
        .iter()
        .map(|d| format!("src/{}", d.trim_end_matches('/')))
        .chain(build_rs::PHYSICS_FILES.iter().map(|f| format!("src/{f}")));
    for must in physics.chain(["Cargo.lock".into(), "build.rs".into()]) {
        assert!(
            watched.contains(&must.as_str()),
            "{must} not watched: {watched:?}"
        );
    }
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
        // (the MJCF export reads parry2d's mass properties to write them
        // out: it decides no outcome)
        let physics = !rel.starts_with("scene/mjcf")
            && (text.contains("rapier2d")
                || text.contains("parry2d")
                || text.contains("pub struct Binning")
                || text.contains("pub struct EffectGrid")
                || text.contains("pub struct GridWorld"));
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
