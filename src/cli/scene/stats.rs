//! `e3d scene stats`: what happens when every command of a physics scene
//! runs.

use super::simulate::{simulate_all, world_error};
use crate::cli::console::outln;
use crate::cli::{CliError, CliResult};
use e3d::scene::Scene;
use e3d::world::RunStats;

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
    let ([contacts, fixed, limits], max_speed, max_spin) = figures(&all);
    let cells = per_cell(&all, scene.num_effects());
    let (name, k, threads) = (&scene.spec().name, all.len(), rayon::current_num_threads());
    let rate = k as f64 / secs;
    outln!(
        "scene {name}: {k} commands in {secs:.2} s ({rate:.0} rollouts/s on {threads} thread(s))"
    );
    outln!("reached cells: {} of {}", reached(&cells), cells.len());
    outln!("commands bringing two moving bodies into contact: {contacts}");
    outln!("commands bringing a moving body into contact with a fixed body or wall: {fixed}");
    outln!("commands pressing a joint against a limit (within 0.01 rad): {limits}");
    let cap = physics.spec().max_speed;
    let cap_spin = std::f64::consts::FRAC_PI_4 / physics.spec().dt;
    outln!(
        "top linear speed {max_speed:.3} m/s (max_speed {cap} m/s); top angular speed {max_spin:.2} rad/s (Rapier's cap: {cap_spin:.2} rad/s)"
    );
    Ok(())
}

/// `e3d scene stats` with start contexts: per context (a drawn one from
/// its seed-0 draw, as `scene exec`), every command run from its start and
/// what it did; then the union of the contexts' reached effects.
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
    let all: Vec<Vec<RunStats>> = simulate_all(scene, total, secs, |progress| {
        (starts.iter())
            .map(|from| inspect_all(physics, &space, n, Some(from), progress))
            .collect::<Result<_, _>>()
    })
    .map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    let (name, m, rate) = (&scene.spec().name, contexts.len(), total as f64 / secs);
    outln!("scene {name}: {n} commands from each of {m} start contexts in {secs:.2} s ({rate:.0} rollouts/s on {threads} thread(s))");
    let mut union = vec![0u64; scene.num_effects()];
    for (ctx, runs) in contexts.iter().zip(&all) {
        let cells = per_cell(runs, scene.num_effects());
        union.iter_mut().zip(&cells).for_each(|(u, c)| *u += c);
        let ([contacts, fixed, limits], max_speed, _) = figures(runs);
        let drawn = if ctx.drawn {
            " (drawn: its seed-0 start)"
        } else {
            ""
        };
        let (k, h) = (reached(&cells), entropy(&cells));
        outln!(
            "context {}{drawn}: reached cells {k} of {}, normalised entropy of the terminal cells {h:.3}; contacts {contacts}, with fixed bodies or walls {fixed}, at a limit {limits}, top speed {max_speed:.3} m/s",
            ctx.name,
            cells.len()
        );
        outln!("  commands per cell: {}", counts_text(&cells));
    }
    let (k, all, h) = (reached(&union), union.len(), entropy(&union));
    outln!("all contexts: reached cells {k} of {all} (the union), normalised entropy {h:.3}");
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
) -> Result<Vec<RunStats>, e3d::WorldError> {
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

/// Of `runs`, the commands (`K (P%)`) that brought two moving bodies into
/// contact, a moving body into contact with a fixed one or a wall, a joint
/// against a limit; the top linear and angular speeds.
fn figures(runs: &[RunStats]) -> ([String; 3], f64, f64) {
    let share = |f: fn(&RunStats) -> u64| {
        let k = runs.iter().filter(|s| f(s) > 0).count();
        format!("{k} ({:.1}%)", 100.0 * k as f64 / runs.len() as f64)
    };
    let top = |f: fn(&RunStats) -> f64| runs.iter().map(f).fold(0.0, f64::max);
    let counts: [fn(&RunStats) -> u64; 3] = [
        |s| s.contact_steps,
        |s| s.fixed_contact_steps,
        |s| s.limit_steps,
    ];
    (counts.map(share), top(|s| s.max_speed), top(|s| s.max_spin))
}

/// The commands of `runs` per effect cell (of `effects`).
fn per_cell(runs: &[RunStats], effects: usize) -> Vec<u64> {
    let mut cells = vec![0u64; effects];
    for s in runs {
        cells[s.outcome.effect] += 1;
    }
    cells
}

/// The cells of `counts` reached at least once.
fn reached(counts: &[u64]) -> usize {
    counts.iter().filter(|&&c| c > 0).count()
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
