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
pub const PUCK_HEADINGS: &str = include_str!("../scenes/puck_headings.ron");

/// The normalised entropy of the terminal cells per start context (of
/// `contexts`) after 5000 one-command episodes of contextual E3D (task 1)
/// on the world `world()` makes: first observing its start context, then
/// blind to it.
pub fn seen_and_blind_entropy<W: e3d::World + ?Sized>(
    space: &e3d::command::CommandSpace,
    num_effects: usize,
    contexts: usize,
    seed: u64,
    mut world: impl FnMut() -> Box<W>,
) -> Vec<Vec<f64>> {
    use e3d::episode::{run_episodes, EpisodeConfig, Observe};
    use e3d::learner::ContextTargets;
    use e3d::{LearnerKind, Params, Target};
    [Observe::StartContext, Observe::Blind]
        .into_iter()
        .map(|observe| {
            let mut w = world();
            let cfg = EpisodeConfig {
                episodes: 5000,
                commands: 1,
                seed,
                use_reward: false,
                observe,
            };
            let mut l = LearnerKind::E3d
                .make_contextual(
                    &Params::TASK1,
                    space,
                    num_effects,
                    cfg.num_contexts(&*w),
                    &ContextTargets::Shared(Target::Uniform),
                )
                .unwrap();
            run_episodes(&mut *w, &mut l, &cfg, &e3d::session::Control::default())
                .unwrap()
                .entropy_per_start(contexts)
        })
        .collect()
}

/// Sessions of continuous commands, `learners[i]` with `configs[i]`, run
/// the way `exec` plans them ([`e3d::run_sessions`]): their records, each
/// with its learner's final policy.
pub fn value_sessions<L: e3d::ContinuousLearner + Send>(
    exec: &e3d::Executor<'_>,
    configs: &[e3d::SessionConfig],
    mut learners: Vec<L>,
) -> Vec<e3d::session::ValueSessionRecord> {
    let scene = exec.continuous().expect("a continuous scene");
    let slots = scene.values().num_slots();
    let effects = scene.scene().num_effects();
    let mut records: Vec<e3d::session::ValueSessionRecord> = configs
        .iter()
        .map(|c| e3d::session::ValueSessionRecord::new(slots, effects, c.trials))
        .collect();
    let status = e3d::run_sessions(
        exec,
        &mut learners,
        configs,
        &mut records,
        &e3d::Control::default(),
    );
    for ((s, r), l) in status.into_iter().zip(&mut records).zip(&learners) {
        s.unwrap();
        r.set_policy(l);
    }
    records
}

/// `scenes/two_rooms_contexts.ron` with its two start contexts replaced by
/// `contexts` (a RON list's items).
pub fn grid_with_contexts(contexts: &str) -> String {
    let text = std::fs::read_to_string("scenes/two_rooms_contexts.ron").unwrap();
    let old = r#"contexts: [(name: "room_a", cell: (0, 0)), (name: "room_b", cell: (2, 5))],"#;
    assert!(text.contains(old));
    text.replace(old, &format!("contexts: [{contexts}],"))
}
