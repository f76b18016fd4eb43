//! `e3d run`: sessions on a scene, of symbols or of values (here), or of
//! episodes ([`super::episodes`]).

use super::session::{
    finish_parts, print_header, print_metrics, recorders, track_run, write_run, Repro, RunArgs,
    TargetArg, TrialsCsv,
};
use super::{load_scene, CliError, CliResult};
use crate::cli::console::{errln, outln};
use e3d::learner::{Effort, LearnerSetup};
use e3d::report::run_scene::SceneRecord;
use e3d::session::{policy_effect_distribution, RepeatOptions, RunningMetrics, ValueSessionRecord};
use e3d::world::{ContinuousScene, ExecutionPlan, Executor, Workload};
use e3d::{run_sessions, Control, Metrics, Params, Scene, SessionConfig, Target};
use serde::Serialize;

/// What every `summary.json` of a run of symbols or values begins with.
#[derive(Serialize)]
struct Head<'a> {
    e3d_version: &'static str,
    scene: &'a str,
    /// The scene's file, content hash and effect grid (what `report` draws on).
    scene_record: SceneRecord,
    learner: &'static str,
    #[serde(flatten)]
    params: Params,
}

impl<'a> Head<'a> {
    fn new(a: &RunArgs, scene: &'a Scene, params: Params) -> Self {
        Head {
            e3d_version: env!("CARGO_PKG_VERSION"),
            scene: &scene.spec().name,
            scene_record: SceneRecord::new(scene, &a.scene),
            learner: a.learner.as_str(),
            params,
        }
    }
}

/// What `summary.json` holds: one session's figures inline, or a list of
/// several sessions'.
#[derive(Serialize)]
struct Summary<'a> {
    #[serde(flatten)]
    head: Head<'a>,
    #[serde(skip_serializing_if = "Option::is_none")]
    seed: Option<u64>,
    use_reward: bool,
    /// With `--target reachable`: the cells of the target's support.
    #[serde(skip_serializing_if = "Option::is_none")]
    target_reachable_cells: Option<usize>,
    #[serde(flatten)]
    single: Option<Single<'a>>,
    /// Per session (of several): its seed, metrics and effect counts.
    #[serde(skip_serializing_if = "Option::is_none")]
    sessions: Option<Vec<OneSession<'a>>>,
    /// How the outcomes were obtained (table, memo or live, and why).
    execution: &'a ExecutionPlan,
}

/// The figures of a run of one session.
#[derive(Serialize)]
struct Single<'a> {
    #[serde(flatten)]
    metrics: &'a Metrics,
    /// The exact effect distribution of the final policy (small command
    /// spaces only).
    policy_effect_distribution: Option<Vec<f64>>,
    effect_counts: Vec<f64>,
    /// On a noisy scene: the reproducibility of the final policy.
    #[serde(skip_serializing_if = "Option::is_none")]
    reproducibility: Option<Repro>,
}

/// A session's seed, metrics and effect counts (of several, or of values).
#[derive(Serialize)]
struct OneSession<'a> {
    seed: u64,
    #[serde(flatten)]
    metrics: &'a Metrics,
    effect_counts: Vec<f64>,
    /// Continuous commands: per slot, the mean and standard deviation of
    /// the final policy, in the slot's unit.
    #[serde(skip_serializing_if = "Option::is_none")]
    final_policy: Option<Vec<SlotPolicy>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    reproducibility: Option<Repro>,
}

pub fn run(a: RunArgs) -> CliResult {
    let threads = a.threads;
    threads.install(|| run_here(a))
}

/// [`run`] on the current thread pool.
fn run_here(a: RunArgs) -> CliResult {
    if let Some(dir) = &a.table_cache {
        super::output::check_cache_folder(dir, "--table-cache")?;
    }
    let params = a.params.params()?;
    super::session::note_unused_params(a.learner, &a.given_params);
    let scene = load_scene(&a.scene)?;
    if let Some(dir) = &a.out {
        super::output::prepare_out(dir, &["trials.csv", "summary.json"], a.force)?;
    }
    let seeds = seeds(&a)?;
    let name = &scene.spec().name;
    let reachable = a.target == TargetArg::Reachable;
    if let Some(continuous) = scene.as_continuous() {
        if reachable {
            return Err(only_trials(&format!(
                "scene `{name}` takes continuous commands"
            )));
        }
        run_values(&a, continuous, params, &seeds)
    } else if super::episodes::wanted(&a, &scene) {
        if reachable {
            return Err(only_trials("this run is of episodes"));
        }
        super::episodes::run(&a, &scene, params, &seeds)
    } else {
        run_symbols(&a, &scene, params, &seeds)
    }
}

/// `--target reachable` refused: `what` the run is instead.
fn only_trials(what: &str) -> CliError {
    CliError::input(format!(
        "--target reachable: {what}; it takes a scene of symbol commands run trial by trial (its outcome table lists the reachable cells)"
    ))
}

/// `e3d run` on a scene of symbols, trial by trial: the outcomes from
/// the executor's plan (a table, a memo or live worlds).
fn run_symbols(a: &RunArgs, scene: &Scene, params: Params, seeds: &[u64]) -> CliResult {
    let name = &scene.spec().name;
    let sessions = seeds.len();
    let space = scene.command_space();
    let num_effects = scene.num_effects();
    let setup = LearnerSetup::new(a.learner).params(params).effort_of(scene);
    setup
        .symbols(&space, num_effects)
        .map_err(CliError::input)?;
    let work = Workload {
        trials: a.trials.saturating_mul(a.sessions),
        sessions,
        threads: rayon::current_num_threads(),
    };
    let exec = executor(a, scene, &work)?;
    let table = exec.table();
    // p*: uniform over every cell, or over the cells the table reaches
    let target = match (a.target, table) {
        (TargetArg::All, _) => Target::Uniform,
        (TargetArg::Reachable, Some(t)) => t.reachable_target(),
        (TargetArg::Reachable, None) => {
            return Err(only_trials(&format!(
                "scene `{name}` has no outcome table here ({})",
                exec.plan()
            )))
        }
    };
    let setup = setup.target(target.clone());
    let mut learners = seeds
        .iter()
        .map(|_| setup.symbols(&space, num_effects).map_err(CliError::input))
        .collect::<Result<Vec<_>, _>>()?;
    let effort = Effort::of_scene(scene);
    let tally = || RunningMetrics::new(num_effects).with_effort(effort.clone());
    let mut recorders = recorders(a.out.as_deref(), sessions, tally, |part, i| TrialsCsv {
        part,
        space: space.clone(),
        session: (sessions > 1).then_some(i),
        trial: 0,
    })?;
    let configs = configs(a, seeds);
    let status = track_run(a, scene, "trials", sessions, |control| {
        run_sessions(&exec, &mut learners, &configs, &mut recorders, control)
    });
    if let Some(line) = exec.finish() {
        errln!("outcomes: {line}");
    }
    let parts = recorders.iter_mut().map(|r| r.1.take().map(|c| c.part));
    let files = finish_parts(status, parts)?;
    // with a table, the reachable cells are known (when fewer than all):
    // the metrics then hold the entropy over them too
    let reachable = table
        .map(|t| t.reachable_effects())
        .filter(|&r| r < num_effects);
    let metrics: Vec<Metrics> = recorders
        .iter()
        .map(|r| match reachable {
            Some(k) => r.0.metrics_over_reachable(&target, k),
            None => r.0.metrics(&target),
        })
        .collect();
    let exact = match (table, sessions) {
        (Some(t), 1) => policy_effect_distribution(t, &*learners[0]),
        _ => None,
    };

    print_header(a, name, "", &params, seeds);
    let support = (a.target == TargetArg::Reachable)
        .then(|| table.map(|t| t.reachable_effects()))
        .flatten();
    if let Some(cells) = support {
        outln!("target: uniform over the {cells} reachable cells (of {num_effects})");
    }
    print_metrics(&metrics, seeds, num_effects);
    if let Some(d) = &exact {
        let h = e3d::effect::entropy(d) / (d.len() as f64).ln();
        outln!("exact effect distribution of the final policy: normalised entropy {h:.4}");
    }
    let repro = reproducibility(a, scene, &exec, &mut learners, seeds)?;
    let mut repro = repro.into_iter().flatten();
    let Some(dir) = &a.out else {
        return Ok(());
    };
    let mut counts = recorders.iter().map(|r| r.0.effect_counts());
    let single = sessions == 1;
    let summary = Summary {
        head: Head::new(a, scene, params),
        seed: single.then_some(a.seed),
        use_reward: !a.no_reward,
        target_reachable_cells: support,
        single: single.then(|| Single {
            metrics: &metrics[0],
            policy_effect_distribution: exact,
            effect_counts: counts.next().unwrap_or_default(),
            reproducibility: repro.next(),
        }),
        sessions: (!single).then(|| {
            let each = metrics.iter().zip(counts).zip(seeds);
            each.map(|((m, effect_counts), &seed)| OneSession {
                seed,
                metrics: m,
                effect_counts,
                final_policy: None,
                reproducibility: repro.next(),
            })
            .collect()
        }),
        execution: exec.plan(),
    };
    let header = if single {
        "trial,command,effect,reward"
    } else {
        "session,trial,command,effect,reward"
    };
    write_run(dir, header, &files, |_| Ok(()), &summary)
}

/// What `summary.json` holds for a run of continuous commands.
#[derive(Serialize)]
struct ValuesSummary<'a> {
    #[serde(flatten)]
    head: Head<'a>,
    use_reward: bool,
    /// Always `"live"`: continuous commands have no table or memo.
    execution: &'static str,
    /// Per session: its seed, metrics, effect counts and final policy.
    sessions: Vec<OneSession<'a>>,
}

#[derive(Serialize)]
struct SlotPolicy {
    mean: f64,
    sd: f64,
}

/// `e3d run` on a scene of continuous commands: live physics, the
/// sessions in lockstep groups of [`Executor::for_values`], the groups in
/// parallel on every core.
fn run_values(
    a: &RunArgs,
    continuous: ContinuousScene,
    params: Params,
    seeds: &[u64],
) -> CliResult {
    let scene = continuous.scene();
    let name = &scene.spec().name;
    if a.table_cache.is_some() {
        return Err(CliError::input(format!(
            "--table-cache: scene `{name}` takes continuous commands, which have no outcome table (every trial is simulated)"
        )));
    }
    if matches!(a.memo.outcomes.0, Some(s) if s != e3d::world::Strategy::Live) {
        return Err(CliError::input(format!(
            "--outcomes: scene `{name}` takes continuous commands, which run live only (no table, no memo)"
        )));
    }
    let space = continuous.values();
    let num_effects = scene.num_effects();
    let setup = (LearnerSetup::new(a.learner).params(params)).effort_of(scene);
    let configs = configs(a, seeds);
    let mut learners = configs
        .iter()
        .map(|_| setup.values(space, num_effects).map_err(CliError::input))
        .collect::<Result<Vec<_>, CliError>>()?;
    let mut records: Vec<ValueSessionRecord> = configs
        .iter()
        .map(|c| ValueSessionRecord::new(space.num_slots(), num_effects, c.trials))
        .collect();
    let sessions = seeds.len();
    let steps = scene.spec().steps_per_command().unwrap_or(0);
    let threads = rayon::current_num_threads();
    let work = Workload {
        trials: a.trials.saturating_mul(sessions as u64),
        sessions,
        threads,
    };
    let exec = Executor::for_values(scene, &work).map_err(CliError::input)?;
    let lockstep = match exec.plan().copies {
        1 => String::new(),
        k => format!(", in lockstep up to {k} sessions per world"),
    };
    let trials = a.trials;
    errln!("outcomes: live: continuous commands, {trials} trials x {sessions} session(s) x {steps} steps, on {threads} thread(s){lockstep}");
    let status = track_run(a, scene, "trials", sessions, |control| {
        run_sessions(&exec, &mut learners, &configs, &mut records, control)
    });
    for ((st, rec), learner) in status.into_iter().zip(&mut records).zip(&learners) {
        st.map_err(CliError::simulation)?;
        rec.set_policy(learner);
    }
    let effort = Effort::of_scene(scene);
    let metrics: Vec<Metrics> = records
        .iter()
        .map(|r| Metrics {
            qd_score: r.qd_score(&effort),
            ..r.metrics(&Target::Uniform)
        })
        .collect();
    print_header(a, name, " (continuous)", &params, seeds);
    print_metrics(&metrics, seeds, num_effects);
    let repro = reproducibility(a, scene, &exec, &mut learners, seeds)?;
    let mut repro = repro.into_iter().flatten();
    let Some(dir) = &a.out else {
        return Ok(());
    };
    let several = sessions > 1;
    let rows = |out: &mut _| {
        for (i, r) in records.iter().enumerate() {
            r.write_trials_csv(space, several.then_some(i), false, &mut *out)?;
        }
        Ok(())
    };
    let summary = ValuesSummary {
        head: Head::new(a, scene, params),
        use_reward: !a.no_reward,
        execution: "live",
        sessions: (records.iter().zip(&metrics).zip(seeds))
            .map(|((r, m), &seed)| OneSession {
                seed,
                metrics: m,
                effect_counts: r.effect_counts(0..r.trials()),
                final_policy: Some(
                    (r.final_policy.iter())
                        .map(|&(mean, sd)| SlotPolicy { mean, sd })
                        .collect(),
                ),
                reproducibility: repro.next(),
            })
            .collect(),
    };
    let header = if several {
        "session,trial,values,effect,reward,x,y"
    } else {
        "trial,values,effect,reward,x,y"
    };
    write_run(dir, header, &[], rows, &summary)
}

/// On a noisy scene with `--repeat R` (R > 0): per session, the
/// reproducibility of its final policy ([`e3d::session::reproducibility`],
/// seeded by the session's seed), the sessions in parallel; else nothing
/// (an empty list, so that the summary of a noise-free run is unchanged).
/// Each session's figure is printed.
fn reproducibility<C, L>(
    a: &RunArgs,
    scene: &Scene,
    exec: &Executor<'_>,
    learners: &mut [L],
    seeds: &[u64],
) -> Result<Vec<Option<Repro>>, CliError>
where
    C: Clone,
    L: e3d::session::Learns<C> + Send,
    for<'e> Executor<'e>: e3d::session::Worlds<C>,
{
    use e3d::session::Worlds;
    use rayon::prelude::*;
    let noisy = matches!(&scene.spec().world, e3d::scene::WorldSpec::Physics(p) if p.active_noise().is_some());
    if !noisy || a.repeat == 0 {
        return Ok(Vec::new());
    }
    let options = RepeatOptions {
        runs: a.repeat as usize,
        ..RepeatOptions::default()
    };
    let width = exec.plan().copies;
    let repro: Vec<Option<Repro>> = (learners.par_iter_mut().zip(seeds))
        .map(|(l, &seed)| {
            let mut world = exec.world_for(width).map_err(CliError::simulation)?;
            let r = e3d::session::reproducibility(&mut *world, &*l, options, seed)
                .map_err(CliError::simulation)?;
            Ok(r.map(|r| Repro::of(r, options)))
        })
        .collect::<Result<_, CliError>>()?;
    super::session::print_repro(&repro, seeds, "commands");
    Ok(repro)
}

/// The executor of `scene` for `work`: an outcome table built first
/// shows its own progress (off a terminal, a line every few seconds); its
/// plan is told.
fn executor<'s>(a: &RunArgs, scene: &'s Scene, work: &Workload) -> Result<Executor<'s>, CliError> {
    let options = a.memo.options(a.table_cache.as_deref());
    let label = format!("table {}", scene.spec().name);
    let exec = super::progress::track(&label, "commands", 0, |p| {
        let (add, total) = (|k| p.add(k), |n| p.set_total(n));
        let control = Control {
            progress: &add,
            total: &total,
            ..Control::default()
        };
        Executor::with_control(scene, work, &options, &control)
    })
    .map_err(CliError::simulation)?;
    errln!("outcomes: {}", exec.plan());
    Ok(exec)
}

/// A session's configuration per seed.
fn configs(a: &RunArgs, seeds: &[u64]) -> Vec<SessionConfig> {
    (seeds.iter())
        .map(|&seed| SessionConfig {
            trials: a.trials as usize,
            seed,
            use_reward: !a.no_reward,
        })
        .collect()
}

/// The sessions' seeds: `--seed`, `--seed + 1`, ..., one per session.
fn seeds(a: &RunArgs) -> Result<Vec<u64>, CliError> {
    (0..a.sessions)
        .map(|i| a.seed.checked_add(i))
        .collect::<Option<_>>()
        .ok_or_else(|| {
            CliError::input(format!(
                "--seed {} with --sessions {}: the seeds seed..seed+N-1 pass 2^64 - 1",
                a.seed, a.sessions
            ))
        })
}
