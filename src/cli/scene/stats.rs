//! `e3d scene stats`: what happens when every command of a physics scene
//! runs.

use super::simulate::{simulate_all, world_error};
use crate::cli::console::outln;
use crate::cli::{CliError, CliResult};
use e3d::scene::Scene;

pub(super) fn stats(scene: &Scene) -> CliResult {
    let Some(physics) = scene.as_physics() else {
        return Err(CliError::input(
            "`e3d scene stats` is for physics scenes; this is a grid scene",
        ));
    };
    let space = scene.command_space();
    let n = super::simulate::all_commands(scene, "to execute them all")?;
    let contexts = e3d::world::start_contexts(scene);
    if !contexts.is_empty() {
        return context_stats(scene, physics, &contexts, n);
    }
    let start = std::time::Instant::now();
    let secs = super::simulate::live_seconds(scene, n);
    let all = simulate_all(scene, n, secs, |progress| {
        inspect_all(physics, &space, n, None, progress)
    })
    .map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    let count = |f: &dyn Fn(&e3d::world::RunStats) -> bool| all.iter().filter(|s| f(s)).count();
    let pct = |k: usize| 100.0 * k as f64 / all.len() as f64;
    let contacts = count(&|s| s.contact_steps > 0);
    let fixed = count(&|s| s.fixed_contact_steps > 0);
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
        "commands bringing a moving body into contact with a fixed body or wall: {fixed} ({:.1}%)",
        pct(fixed)
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

/// `e3d scene stats` on a physics scene with start contexts: per context
/// (a drawn one from its seed-0 draw, as `scene exec`), every command run
/// from its start, with its contacts, limits and speeds, the effects it
/// reaches and how evenly (the normalised entropy of the terminal
/// effects); then the union of the contexts' reached effects.
fn context_stats(
    scene: &Scene,
    physics: e3d::world::PhysicsScene<'_>,
    contexts: &[e3d::world::StartContext],
    n: u64,
) -> CliResult {
    let space = scene.command_space();
    let probe = scene.build();
    let starts: Vec<e3d::world::WorldState> = (0..contexts.len())
        .map(|k| e3d::world::seed0_start(&probe, k))
        .collect::<Result<_, _>>()
        .map_err(world_error)?;
    let threads = rayon::current_num_threads();
    let total = n * contexts.len() as u64;
    let secs = super::simulate::live_seconds(scene, total);
    let start = std::time::Instant::now();
    let all: Vec<Vec<e3d::world::RunStats>> = simulate_all(scene, total, secs, |progress| {
        (starts.iter())
            .map(|from| inspect_all(physics, &space, n, Some(from), progress))
            .collect::<Result<_, _>>()
    })
    .map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    outln!(
        "scene {}: {} commands from each of {} start contexts in {:.2} s ({:.0} rollouts/s on {threads} thread(s))",
        scene.spec().name,
        n,
        contexts.len(),
        secs,
        total as f64 / secs,
    );
    let mut union = vec![0u64; scene.num_effects()];
    for (ctx, runs) in contexts.iter().zip(&all) {
        let mut cells = vec![0u64; scene.num_effects()];
        for s in runs {
            cells[s.outcome.effect] += 1;
            union[s.outcome.effect] += 1;
        }
        let pct = |k: usize| 100.0 * k as f64 / runs.len() as f64;
        let contacts = runs.iter().filter(|s| s.contact_steps > 0).count();
        let fixed = runs.iter().filter(|s| s.fixed_contact_steps > 0).count();
        let limits = runs.iter().filter(|s| s.limit_steps > 0).count();
        let max_speed = runs.iter().map(|s| s.max_speed).fold(0.0, f64::max);
        outln!(
            "context {}{}: reached cells {} of {}, normalised entropy of the terminal cells {:.3}; contacts {contacts} ({:.1}%), with fixed bodies or walls {fixed} ({:.1}%), at a limit {limits} ({:.1}%), top speed {max_speed:.3} m/s",
            ctx.name,
            if ctx.drawn { " (drawn: its seed-0 start)" } else { "" },
            cells.iter().filter(|&&c| c > 0).count(),
            cells.len(),
            entropy(&cells),
            pct(contacts),
            pct(fixed),
            pct(limits)
        );
        outln!("  commands per cell: {}", counts_text(&cells));
    }
    outln!(
        "all contexts: reached cells {} of {} (the union), normalised entropy {:.3}",
        union.iter().filter(|&&c| c > 0).count(),
        union.len(),
        entropy(&union)
    );
    Ok(())
}

/// The figures of the `n` commands of `physics` each run once (from
/// `from` if given), in parallel, each counted to `control`.
fn inspect_all(
    physics: e3d::world::PhysicsScene<'_>,
    space: &e3d::command::CommandSpace,
    n: u64,
    from: Option<&e3d::world::WorldState>,
    control: &e3d::Control<'_>,
) -> Result<Vec<e3d::world::RunStats>, e3d::WorldError> {
    use rayon::prelude::*;
    (0..n)
        .into_par_iter()
        .map_init(
            || physics.world(1),
            |w, i| {
                let c = space.command_at(i);
                let stats = match from {
                    Some(from) => w.from_start(from, |w| w.inspect(&c)).and_then(|r| r),
                    None => w.inspect(&c),
                };
                (control.progress)(1);
                stats
            },
        )
        .collect()
}

/// Counts as `cell:count` pairs of the non-zero ones, space-separated.
fn counts_text(cells: &[u64]) -> String {
    let pairs: Vec<String> = cells
        .iter()
        .enumerate()
        .filter(|(_, &c)| c > 0)
        .map(|(i, c)| format!("{i}:{c}"))
        .collect();
    pairs.join(" ")
}

/// The normalised entropy of `counts` over all their cells.
fn entropy(counts: &[u64]) -> f64 {
    let w: Vec<f64> = counts.iter().map(|&c| c as f64).collect();
    e3d::effect::normalized_entropy_over(&w, w.len())
}
