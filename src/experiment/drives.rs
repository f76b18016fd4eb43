//! The comparison of every drive on the canonical scenes (what `e3d
//! compare` runs): the sweep `scenes/sweeps/drives.ron`, sized and told the
//! reachable cells of its scenes. [`report::drives`](crate::report::drives)
//! summarises and draws its results.

use crate::sweep::{Sweep, SweepError, SweepSpec};
use crate::world::{ExecOptions, Executor, Strategy, Workload, MAX_TABLE_COMMANDS};

/// The sweep file of the comparison, as shipped.
pub const DRIVES_SWEEP: &str = include_str!("../../scenes/sweeps/drives.ron");

/// The comparison's sweep with `sessions` per cell and `trials` per
/// session, on `scenes` (built-in names; empty: the shipped four), of
/// `learners` (names; empty: the shipped eight; `qlearning_moves` runs
/// each trial as an episode of the scene's moves one by one, on scenes
/// whose command is `Repeat`).
pub fn drives_sweep(
    sessions: usize,
    trials: usize,
    scenes: &[&str],
    learners: &[&str],
) -> Result<Sweep, SweepError> {
    let mut spec = SweepSpec::parse(DRIVES_SWEEP, "drives.ron (built in)")?;
    spec.sessions = sessions;
    spec.trials = trials;
    if !scenes.is_empty() {
        spec.scenes = scenes.iter().map(|s| s.to_string()).collect();
    }
    if !learners.is_empty() {
        spec.learners = learners.iter().map(|s| s.to_string()).collect();
    }
    Sweep::new(spec)
}

/// `sweep`, told the reachable cells of each of its scenes
/// ([`Sweep::with_reachable_effects`]) from the scene's outcome table
/// (built on the current rayon pool, or read from `cache`, a table
/// folder), for scenes of at most [`MAX_TABLE_COMMANDS`] commands; the
/// others keep every cell as the reference of coverage.
pub fn with_reachable_cells(
    sweep: Sweep,
    cache: Option<&std::path::Path>,
) -> Result<Sweep, SweepError> {
    let options = ExecOptions {
        cache: cache.map(std::path::Path::to_path_buf),
        force: Some(Strategy::Table),
        ..ExecOptions::default()
    };
    let work = Workload {
        trials: 1,
        sessions: 1,
        threads: rayon::current_num_threads(),
    };
    let mut reachable = Vec::new();
    for s in sweep.scenes() {
        let small = |n| n <= MAX_TABLE_COMMANDS;
        let k = match s.scene() {
            Some(scene) if scene.command_space().num_commands().is_some_and(small) => {
                let exec = Executor::new(scene, &work, &options)
                    .map_err(|e| SweepError::Other(format!("scene `{}`: {e}", s.name())))?;
                exec.table().map(|t| t.reachable_effects())
            }
            _ => None,
        };
        reachable.push(k);
    }
    Ok(sweep.with_reachable_effects(reachable))
}
