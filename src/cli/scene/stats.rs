//! `e3d scene stats`: what happens when every command of a physics scene
//! runs.

use super::simulate::{simulate_all, world_error};
use crate::cli::console::outln;
use crate::cli::{CliError, CliResult};
use e3d::scene::Scene;

pub(super) fn stats(scene: &Scene) -> CliResult {
    use rayon::prelude::*;
    let Some(physics) = scene.as_physics() else {
        return Err(CliError::input(
            "`e3d scene stats` is for physics scenes; this is a grid scene",
        ));
    };
    let space = scene.command_space();
    let n = space.num_commands().unwrap_or(u64::MAX);
    if n > e3d::world::MAX_TABLE_COMMANDS {
        return Err(CliError::input(format!(
            "{} commands: too many to execute them all (at most {})",
            space.num_commands_text(),
            e3d::world::MAX_TABLE_COMMANDS
        )));
    }
    let start = std::time::Instant::now();
    let threads = rayon::current_num_threads();
    let secs = n as f64
        * e3d::world::rollout_seconds(scene)
        * super::simulate::calibration(scene, threads, 1)
        / threads as f64;
    let all: Vec<e3d::world::RunStats> = simulate_all(scene, n, secs, |progress| {
        (0..n)
            .into_par_iter()
            .map_init(
                || physics.world(1),
                |w, i| {
                    let stats = w.inspect(&space.command_at(i));
                    progress(1);
                    stats
                },
            )
            .collect::<Result<_, _>>()
    })
    .map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    let count = |f: &dyn Fn(&e3d::world::RunStats) -> bool| all.iter().filter(|s| f(s)).count();
    let pct = |k: usize| 100.0 * k as f64 / all.len() as f64;
    let contacts = count(&|s| s.contact_steps > 0);
    let limits = count(&|s| s.limit_steps > 0);
    let max_speed = all.iter().map(|s| s.max_speed).fold(0.0, f64::max);
    let max_spin = all.iter().map(|s| s.max_spin).fold(0.0, f64::max);
    let mut cells = vec![0u64; scene.num_effects()];
    for s in &all {
        cells[s.outcome.effect] += 1;
    }
    outln!(
        "scene {}: {} commands in {:.2} s ({:.0} rollouts/s on {} thread(s))",
        scene.spec().name,
        all.len(),
        secs,
        all.len() as f64 / secs,
        rayon::current_num_threads()
    );
    outln!(
        "reached cells: {} of {}",
        cells.iter().filter(|&&c| c > 0).count(),
        cells.len()
    );
    outln!(
        "commands bringing two moving bodies into contact: {contacts} ({:.1}%)",
        pct(contacts)
    );
    outln!(
        "commands pressing a joint against a limit (within 0.01 rad): {limits} ({:.1}%)",
        pct(limits)
    );
    outln!(
        "top linear speed {max_speed:.3} m/s (max_speed {} m/s); top angular speed {max_spin:.2} rad/s (Rapier's cap: {:.2} rad/s)",
        physics.spec().max_speed,
        std::f64::consts::FRAC_PI_4 / physics.spec().dt
    );
    Ok(())
}
