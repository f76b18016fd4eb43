//! What the test binaries share: the `e3d` program built with them, and
//! temporary paths of their own.
//!
//! A test binary takes it in with `#[path = "../common/mod.rs"] mod common;`
//! (from `tests/NAME/main.rs`) or `mod common;` (from `tests/NAME.rs`).

// each binary uses a part of it
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The `e3d` program, as a command to give arguments, environment and
/// pipes to.
pub fn e3d_command() -> Command {
    Command::new(env!("CARGO_BIN_EXE_e3d"))
}

/// `e3d ARGS`, run to its end: exit status, standard output and error.
pub fn e3d(args: &[&str]) -> Output {
    e3d_command().args(args).output().unwrap()
}

/// `out`, which must be a success; else the test fails with e3d's exit
/// status and standard error.
pub fn ok(out: Output) -> Output {
    assert!(
        out.status.success(),
        "e3d failed: {}\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The standard output of `e3d ARGS`, which must succeed.
pub fn stdout_of(args: &[&str]) -> String {
    String::from_utf8(ok(e3d(args)).stdout).unwrap()
}

/// `e3d-NAME-PID` in the system's temporary folder: a path unique to this
/// test process and `name` (each test, or each helper shared by tests,
/// gives its own name). Nothing is created or removed.
pub fn temp_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("e3d-{name}-{}", std::process::id()))
}

/// [`temp_path`], with what a former run left there removed.
pub fn fresh_path(name: &str) -> PathBuf {
    let path = temp_path(name);
    remove(&path);
    path
}

fn remove(path: &Path) {
    let _ = std::fs::remove_dir_all(path);
    let _ = std::fs::remove_file(path);
}

/// An empty folder of its own for one test ([`fresh_path`], created),
/// removed when dropped unless the test failed (then it is kept to look
/// into).
pub struct TempDir(PathBuf);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            remove(&self.0);
        }
    }
}

/// A [`TempDir`] named `e3d-NAME-PID`.
pub fn temp_dir(name: &str) -> TempDir {
    let dir = fresh_path(name);
    std::fs::create_dir_all(&dir).unwrap();
    TempDir(dir)
}

/// A puck that takes continuous commands: puck_rooms's rooms and puck,
/// 3 slots of a 1.6 N*s impulse in any heading. Its copies in one world are
/// exact, so its sessions step together in lockstep.
pub const PUCK_HEADINGS: &str = r#"Scene(
    name: "puck_headings",
    world: Physics(
        gravity: (0.0, 0.0),
        dt: 0.016666666666666666,
        walls: [
            (name: "wall", room: ((0.0, 0.0), (6.0, 3.0)), placement: Outside,
             thickness: 0.1, friction: 0.0, restitution: 0.5),
            (name: "inner", points: [(3.0, 0.0), (3.0, 3.0)], doors: [((3.0, 1.0), (3.0, 2.0))],
             names: ["inner_low", "inner_high"], thickness: 0.1, friction: 0.0, restitution: 0.5),
        ],
        bodies: [
            (name: "puck", shape: Ball(radius: 0.2), mass: 1.0, position: (0.5, 2.5),
             linear_damping: 1.5, friction: 0.0, restitution: 0.5, lock_rotation: true),
        ],
        schedule: Sequential(phase: 0.5, settle: 1.0),
        effect: (body: "puck", grid: (rows: 3, cols: 6, min: (0.0, 0.0), max: (6.0, 3.0))),
    ),
    command: Continuous([
        (name: "h1", range: (-3.14159, 3.14159), action: Heading(body: "puck", impulse: 1.6)),
        (name: "h2", range: (-3.14159, 3.14159), action: Heading(body: "puck", impulse: 1.6)),
        (name: "h3", range: (-3.14159, 3.14159), action: Heading(body: "puck", impulse: 1.6)),
    ]),
)
"#;
