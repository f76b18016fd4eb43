//! What the scene tools share: a world's error as the CLI's, and the
//! cost model's estimates said before a long simulation, with its progress.

use crate::cli::console::errln;
use crate::cli::{progress, CliError};
use e3d::scene::{Scene, WorldSpec};
use e3d::Control;
use e3d::{OutcomeTable, WorldError};

pub(super) fn world_error(e: WorldError) -> CliError {
    match e {
        WorldError::BadCommand { .. } => CliError::input(e),
        _ => CliError::simulation(e),
    }
}

pub(super) fn seconds_text(t: f64) -> String {
    if t < 0.01 {
        format!("{:.2} ms", t * 1e3)
    } else if t < 1.0 {
        format!("{t:.2} s")
    } else if t < 120.0 {
        format!("{t:.0} s")
    } else if t < 7200.0 {
        format!("{:.0} min", t / 60.0)
    } else {
        format!("{:.1} h", t / 3600.0)
    }
}

/// Says on stderr how many commands of `scene` are about to be simulated
/// (`simulated`: fewer than all with a symmetry) and what that costs by
/// the cost model (`seconds`), then runs `work` with its progress shown
/// there (see [`progress::track`]).
pub(super) fn simulate_all<T>(
    scene: &Scene,
    simulated: u64,
    seconds: f64,
    work: impl FnOnce(&Control<'_>) -> T,
) -> T {
    let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
    let what = if simulated < n {
        format!("{simulated} of {n} commands (the others are mirror images)")
    } else {
        format!("{simulated} commands")
    };
    let label = format!("scene {}", scene.spec().name);
    let (steps, time) = (steps_text(scene), seconds_text(seconds));
    let threads = rayon::current_num_threads();
    errln!("{label}: simulating {what} on {threads} thread(s){steps}: about {time} by the cost model (calibrated on timed rollouts here)");
    progress::track_control(&label, "commands", simulated, work)
}

/// [`OutcomeTable::build_scene`], its cost and progress on stderr.
pub(super) fn build_table(scene: &Scene) -> Result<OutcomeTable, CliError> {
    let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
    let simulated = OutcomeTable::simulated_commands(scene).unwrap_or(n);
    simulate_all(scene, simulated, table_seconds(scene), |progress| {
        OutcomeTable::build_scene_with(scene, progress)
    })
    .map_err(world_error)
}

/// The plan of a run that only builds the table of `scene`, on the
/// current threads.
pub(super) fn table_plan(scene: &Scene) -> e3d::world::ExecutionPlan {
    let threads = rayon::current_num_threads();
    let work = e3d::world::Workload {
        trials: 0,
        sessions: 1,
        threads,
    };
    e3d::world::ExecutionPlan::choose(scene, &work, None, 0)
}

/// The cost model's seconds for building the whole table of `scene` on
/// the current threads (0 when no table is possible).
pub(super) fn table_seconds(scene: &Scene) -> f64 {
    plan_table_seconds(scene, &table_plan(scene))
}

/// [`table_seconds`] from `scene`'s [`table_plan`], calibrated on rollouts
/// run as the table runs them ([`table_copies`](e3d::world::table_copies)
/// to a world), not on the plan's `copies`: those are one session's, whose
/// single-copy world keeps prefix states and costs per command what a
/// table's world of many copies does not.
pub(super) fn plan_table_seconds(scene: &Scene, plan: &e3d::world::ExecutionPlan) -> f64 {
    let (threads, copies) = (
        rayon::current_num_threads(),
        e3d::world::table_copies(scene),
    );
    plan.table_seconds.unwrap_or(0.0) * calibration(scene, threads, copies)
}

/// The cost model's seconds for `n` rollouts of `scene`, one command per
/// world, on the current threads.
pub(super) fn live_seconds(scene: &Scene, n: u64) -> f64 {
    let threads = rayon::current_num_threads();
    n as f64 * e3d::world::rollout_seconds(scene) * calibration(scene, threads, 1) / threads as f64
}

/// The number of commands of `scene`, refused (`too many WHAT`) above
/// what a table holds.
pub(super) fn all_commands(scene: &Scene, what: &str) -> Result<u64, CliError> {
    let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
    if n > e3d::world::MAX_TABLE_COMMANDS {
        let (n, most) = (
            scene.command_space().num_commands_text(),
            e3d::world::MAX_TABLE_COMMANDS,
        );
        return Err(CliError::input(format!(
            "{n} commands: too many {what} (at most {most})"
        )));
    }
    Ok(n)
}

/// ` (120 steps each)` for a physics scene (nothing for a grid).
pub(super) fn steps_text(scene: &Scene) -> String {
    match &scene.spec().world {
        WorldSpec::Physics(p) => format!(
            " ({} steps each)",
            p.schedule.total_steps(p.dt, scene.spec().num_slots())
        ),
        WorldSpec::Grid(_) => String::new(),
    }
}

/// The cost model's estimate for `commands` rollouts of `scene` on
/// `threads` threads, run `copies` to a world, said on stderr (`LABEL: N
/// commands, S steps each, on T thread(s): about X by the cost model`)
/// when it reaches [`progress::LONG`]; whether it was said.
pub(in crate::cli) fn say_cost(
    label: &str,
    scene: &Scene,
    commands: u64,
    threads: usize,
    copies: usize,
) -> bool {
    let model =
        commands as f64 * e3d::world::batch_rollout_seconds(scene, copies) / threads.max(1) as f64;
    // one rollout is timed by doing it: no calibration for a command or two
    // that the model puts far below a second
    if commands <= 2 && model < 0.05 * progress::LONG {
        return false;
    }
    let secs = model * calibration(scene, threads, copies);
    if secs < progress::LONG {
        return false;
    }
    let (steps, time) = (steps_text(scene), seconds_text(secs));
    let timed = calibration_rollouts(scene);
    errln!("{label}: {commands} command(s){steps} on {threads} thread(s): about {time} (the cost model, calibrated on {timed} timed rollouts here)");
    true
}

/// The cost model's factor for this machine as loaded now, for commands
/// run `copies` to a world on `threads` threads
/// ([`e3d::world::calibration_on`]: rollouts of `scene` timed that way),
/// measured once per scene, threads and copies, and process.
pub(super) fn calibration(scene: &Scene, threads: usize, copies: usize) -> f64 {
    type Key = (String, usize, usize);
    static CACHE: std::sync::Mutex<Vec<(Key, f64)>> = std::sync::Mutex::new(Vec::new());
    let key = (scene.spec().name.clone(), threads, copies);
    let mut cache = crate::cli::locked(&CACHE);
    if let Some((_, f)) = cache.iter().find(|(k, _)| *k == key) {
        return *f;
    }
    let f = e3d::world::calibration_on(scene, threads, copies);
    cache.push((key, f));
    f
}

/// How many rollouts [`calibration`] timed ("no" for a grid, which is
/// not timed).
fn calibration_rollouts(scene: &Scene) -> String {
    match scene.spec().world {
        WorldSpec::Grid(_) => "no".into(),
        WorldSpec::Physics(_) => format!("at least {}", e3d::world::CALIBRATION_ROLLOUTS),
    }
}
