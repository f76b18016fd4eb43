//! Accuracy as a choice: what a physics scene's solver iterations
//! (`solver_iterations`, Rapier's substeps) cost, and how often the
//! terminal point lands in the cell of the converged run.

use super::{ContinuousWorld, World, WorldError};
use crate::scene::{Scene, WorldSpec};
use crate::SessionRng;
use rand::{RngExt, SeedableRng};
use std::time::Instant;

/// The solver iterations a run compares with its converged one, besides
/// the scene's own: from coarse to fine.
pub const ACCURACY_SETTINGS: [usize; 5] = [1, 2, 3, 4, 8];

/// The converged run, against which the other settings are measured: the
/// scene's `dt` divided by [`CONVERGED_DT_DIVISOR`], with this many
/// solver iterations (docs/benchmarks.md, "arm7: levers against a
/// converged run").
pub const CONVERGED_ITERATIONS: usize = 8;

/// The converged run's step is the scene's `dt` divided by this.
pub const CONVERGED_DT_DIVISOR: f64 = 4.0;

/// One setting of [`accuracy`]: its solver iterations, the share of the
/// sampled commands whose terminal point lands in the converged run's
/// cell, and what a command costs at it.
#[derive(Debug, Clone, PartialEq)]
pub struct AccuracyRow {
    /// Solver iterations per step.
    pub iterations: usize,
    /// Whether this is the scene's own setting (`solver_iterations`, or
    /// Rapier's default 4).
    pub scene: bool,
    /// The share of the sampled commands in the converged run's cell, in
    /// `[0, 1]`.
    pub in_converged_cell: f64,
    /// Seconds a command, measured on one thread (wall-clock: it varies
    /// with the machine's load; the ratios between settings are what to
    /// read).
    pub seconds_per_command: f64,
}

/// Runs `samples` seeded random commands of the physics scene `scene`
/// (symbols or values) at each of [`ACCURACY_SETTINGS`] and the scene's
/// own solver iterations, and in the converged run ([`CONVERGED_ITERATIONS`]
/// at the scene's `dt` / [`CONVERGED_DT_DIVISOR`]): per setting,
/// how often the terminal point lands in the converged run's cell and
/// what a command costs, on one thread. The rows go from coarse to fine.
/// A grid scene has no solver: an error.
///
/// ```
/// use e3d::world::accuracy;
/// use e3d::Scene;
/// let scene = Scene::builtin("arm7").unwrap();
/// let rows = accuracy(&scene, 20, 0).unwrap();
/// let own = rows.iter().find(|r| r.scene).unwrap();
/// assert_eq!(own.iterations, 4);
/// assert!(rows.iter().all(|r| (0.0..=1.0).contains(&r.in_converged_cell)));
/// ```
pub fn accuracy(scene: &Scene, samples: u64, seed: u64) -> Result<Vec<AccuracyRow>, WorldError> {
    let WorldSpec::Physics(p) = &scene.spec().world else {
        return Err(WorldError::Other(format!(
            "scene `{}` is a grid: it has no solver iterations",
            scene.spec().name
        )));
    };
    let own = p.solver_iterations.unwrap_or(4);
    let mut settings: Vec<usize> = ACCURACY_SETTINGS.to_vec();
    settings.push(own);
    settings.sort_unstable();
    settings.dedup();
    let (converged, _) = effects_at(
        scene,
        CONVERGED_ITERATIONS,
        CONVERGED_DT_DIVISOR,
        samples,
        seed,
    )?;
    settings
        .into_iter()
        .map(|n| {
            let (effects, seconds) = effects_at(scene, n, 1.0, samples, seed)?;
            let same = effects
                .iter()
                .zip(&converged)
                .filter(|(a, b)| a == b)
                .count();
            Ok(AccuracyRow {
                iterations: n,
                scene: n == own,
                in_converged_cell: same as f64 / samples.max(1) as f64,
                seconds_per_command: seconds / samples.max(1) as f64,
            })
        })
        .collect()
}

/// The effects of `samples` seeded random commands of `scene` at
/// `iterations` solver iterations and `dt / divisor`, and the seconds
/// they took.
fn effects_at(
    scene: &Scene,
    iterations: usize,
    divisor: f64,
    samples: u64,
    seed: u64,
) -> Result<(Vec<usize>, f64), WorldError> {
    let mut spec = scene.to_spec();
    if let WorldSpec::Physics(p) = &mut spec.world {
        p.solver_iterations = Some(iterations);
        p.dt /= divisor;
    }
    let scene = spec
        .validate()
        .map_err(|e| WorldError::Other(e.to_string()))?;
    let mut rng = SessionRng::seed_from_u64(seed);
    let mut effects = Vec::with_capacity(samples as usize);
    let start = Instant::now();
    if let Some(continuous) = scene.as_continuous() {
        let mut world = continuous.world(1);
        let ranges: Vec<(f64, f64)> = continuous.values().ranges().to_vec();
        for _ in 0..samples {
            let values: Vec<f64> = ranges
                .iter()
                .map(|&(lo, hi)| rng.random_range(lo..=hi))
                .collect();
            effects.push(world.execute_values(&values)?.effect);
        }
    } else {
        let mut world = scene.build();
        let sizes: Vec<usize> = scene.command_space().sizes().collect();
        for _ in 0..samples {
            effects.push(world.execute(&super::reach::draw(&sizes, &mut rng))?.effect);
        }
    }
    Ok((effects, start.elapsed().as_secs_f64()))
}
