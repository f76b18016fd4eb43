//! `e3d bench`: what a scene costs.

use super::load_scene;
use super::{CliError, CliResult};
use crate::cli::console::outln;
use clap::Args;
use e3d::learner::LearnerSetup;
use e3d::world::PhysicsScene;
use e3d::{run_session, LearnerKind, OutcomeTable, Scene, SessionConfig, World};
use std::time::{Duration, Instant};

/// Arguments of `e3d bench`.
#[derive(Args, Debug)]
pub struct BenchArgs {
    /// Scene files or built-in scene names (default: two_rooms).
    #[arg(default_value = e3d::scene::DEFAULT_SCENE)]
    pub scenes: Vec<String>,
    /// Seconds to spend on each measurement (in 5 slices: `rate` is their
    /// median, `best` the fastest).
    #[arg(long, default_value_t = 2.0)]
    pub seconds: f64,
}

/// The number of slices a measurement's budget is cut into.
const SLICES: usize = 5;

/// A rate measured in [`SLICES`] slices of the budget: their median (what
/// the scene typically costs) and their best (what it costs when nothing
/// else holds the machine; on a shared machine the two can differ by a
/// third).
#[derive(Debug, Clone, Copy)]
struct Rate {
    median: f64,
    best: f64,
}

impl Rate {
    /// A single measurement: both figures are it.
    fn once(r: f64) -> Rate {
        Rate { median: r, best: r }
    }

    /// `f` of both figures.
    fn map(self, f: impl Fn(f64) -> f64) -> Rate {
        Rate {
            median: f(self.median),
            best: f(self.best),
        }
    }
}

/// Repeats `f` (which returns how many units it did) for `budget`, in
/// [`SLICES`] slices of at least one call each; returns units per second.
fn rate(budget: Duration, mut f: impl FnMut() -> usize) -> Rate {
    let slice = budget / SLICES as u32;
    let mut rates: Vec<f64> = (0..SLICES)
        .map(|_| {
            let start = Instant::now();
            let mut n = 0usize;
            loop {
                n += f();
                if start.elapsed() >= slice {
                    break;
                }
            }
            n as f64 / start.elapsed().as_secs_f64()
        })
        .collect();
    rates.sort_by(f64::total_cmp);
    Rate {
        median: rates[SLICES / 2],
        best: rates[SLICES - 1],
    }
}

/// Prints one line of the output: `scene`'s `measure`, per second.
fn line(scene: &Scene, measure: &str, r: Rate) {
    let name = &scene.spec().name;
    outln!("{name},{measure},{:.1},{:.1},1/s", r.median, r.best);
}

pub fn run(a: BenchArgs) -> CliResult {
    if !(a.seconds > 0.0 && a.seconds <= 3600.0) {
        return Err(CliError::input(format!(
            "--seconds {}: expected a number in (0, 3600]",
            a.seconds
        )));
    }
    let budget = Duration::from_secs_f64(a.seconds);
    outln!("scene,measure,rate,best,unit");
    for name in &a.scenes {
        let scene = load_scene(name)?;
        let mut world = scene.build();
        // every step simulated: a physics world of symbols keeps no prefix
        // states here (its commands run in index order, sharing prefixes)
        let plain = (!scene.spec().is_continuous()).then(|| scene.physics_world());
        if let Some(mut plain) = plain.flatten() {
            plain.set_prefix_states(0);
            bench_rollouts(&scene, &mut plain, budget)?;
            bench_prefixes(&scene, budget)?;
        } else {
            bench_rollouts(&scene, &mut *world, budget)?;
        }
        if let Some(physics) = scene.as_physics() {
            bench_copies(&scene, &physics, budget);
        }
        bench_trials(&scene, &mut *world, budget)?;
    }
    Ok(())
}

/// Rollouts per second of `world` executing one command at a time, the
/// command of each rollout the index `next()` gives; a failure ends the
/// measure with its error.
fn execute_rate(
    world: &mut dyn World,
    budget: Duration,
    mut next: impl FnMut() -> u64,
) -> Result<Rate, CliError> {
    let space = world.command_space().clone();
    let mut cmd = space.first();
    let mut failure = None;
    let rollouts = rate(budget, || {
        for _ in 0..16 {
            space.write_command_at(next(), &mut cmd);
            if let Err(e) = world.execute(&cmd) {
                failure.get_or_insert(e);
            }
        }
        16
    });
    match failure {
        Some(e) => Err(CliError::simulation(e)),
        None => Ok(rollouts),
    }
}

/// Rollouts (and steps) per second: every command in index order,
/// cycling (no table).
fn bench_rollouts(scene: &Scene, world: &mut dyn World, budget: Duration) -> CliResult {
    let n_commands = world.command_space().num_commands().unwrap_or(u64::MAX);
    let mut i = 0u64;
    let rollouts = execute_rate(world, budget, || {
        i += 1;
        (i - 1) % n_commands
    })?;
    line(scene, "rollouts", rollouts);
    if let Some(steps) = scene.spec().steps_per_command() {
        line(scene, "steps", rollouts.map(|r| r * steps as f64));
    }
    Ok(())
}

/// Rollouts per second of random commands (seed 0, uniform) on a world of
/// one copy that keeps prefix states, as `execute` runs them (see
/// [`PhysicsWorld::set_prefix_states`](e3d::world::PhysicsWorld::set_prefix_states));
/// nothing on a scene whose schedule shares no prefix.
fn bench_prefixes(scene: &Scene, budget: Duration) -> CliResult {
    let Some(mut world) = scene.physics_world() else {
        return Ok(());
    };
    let depth = world.prefix_depth();
    if depth == 0 {
        return Ok(());
    }
    let n_commands = scene.command_space().num_commands().unwrap_or(u64::MAX);
    let mut rng = <e3d::rng::SessionRng as rand::SeedableRng>::seed_from_u64(0);
    let rollouts = execute_rate(&mut world, budget, || {
        rand::RngExt::random_range(&mut rng, 0..n_commands)
    })?;
    let measure = format!("rollouts (random commands; prefix states of up to {depth} slots kept)");
    line(scene, &measure, rollouts);
    Ok(())
}

/// Rollouts per second of many commands at once in one Rapier world (one
/// thread).
fn bench_copies(scene: &Scene, physics: &PhysicsScene, budget: Duration) {
    let space = scene.command_space();
    let n_commands = space.num_commands().unwrap_or(u64::MAX);
    let copies = e3d::world::TABLE_COPIES;
    let mut multi = physics.world(copies);
    let mut cmds = vec![space.first(); copies];
    let mut out = Vec::with_capacity(copies);
    let mut i = 0u64;
    let r = rate(budget, || {
        for c in cmds.iter_mut() {
            space.write_command_at(i % n_commands, c);
            i += 1;
        }
        out.clear();
        multi.execute_batch(&cmds, &mut out);
        copies
    });
    let exact = if physics.spec().copies_are_exact() {
        "bit-identical"
    } else {
        "not bit-identical: tables use one copy"
    };
    let measure = format!("rollouts ({copies} copies per world; {exact})");
    line(scene, &measure, r);
}

/// E3D trials per second: on the scene's outcome table (and the table's
/// build) when one is worthwhile, else 200 simulated trials.
fn bench_trials(scene: &Scene, world: &mut dyn World, budget: Duration) -> CliResult {
    let space = world.command_space().clone();
    let n_commands = space.num_commands().unwrap_or(u64::MAX);
    let n_effects = world.num_effects();
    let make = || {
        LearnerSetup::new(LearnerKind::E3d)
            .symbols(&space, n_effects)
            .map_err(CliError::input)
    };
    let trials = 5000;
    let cfg = |trials, seed| SessionConfig {
        trials,
        seed,
        use_reward: true,
    };
    if !OutcomeTable::worthwhile(scene, &*world, trials as u64) {
        let t0 = Instant::now();
        let mut l = make()?;
        run_session(world, &mut l, &cfg(200, 1)).map_err(CliError::simulation)?;
        let r = Rate::once(200.0 / t0.elapsed().as_secs_f64());
        line(scene, "e3d trials (simulated)", r);
        return Ok(());
    }
    let t0 = Instant::now();
    let table = OutcomeTable::build_scene(scene).map_err(CliError::simulation)?;
    let secs = t0.elapsed().as_secs_f64();
    let simulated = OutcomeTable::simulated_commands(scene).unwrap_or(n_commands);
    let (threads, name, k) = (
        rayon::current_num_threads(),
        &scene.spec().name,
        table.len(),
    );
    outln!("{name},outcome table build ({k} commands; {simulated} simulated; {threads} thread(s)),{secs:.3},{secs:.3},s");
    let measure = format!("outcome table commands ({threads} thread(s))");
    line(scene, &measure, Rate::once(table.len() as f64 / secs));
    let mut seed = 0;
    let mut err = None;
    let r = rate(budget, || {
        seed += 1;
        let mut l = make().expect("valid parameters");
        if let Err(e) = run_session(&mut &table, &mut l, &cfg(trials, seed)) {
            err.get_or_insert(e);
        }
        trials
    });
    if let Some(e) = err {
        return Err(CliError::simulation(e));
    }
    line(scene, "e3d trials (outcome table)", r);
    let Rate { median, best } = r.map(|r| 1e9 / r);
    outln!("{name},e3d trial (outcome table),{median:.1},{best:.1},ns");
    Ok(())
}
