//! `e3d run`: one session on a scene.

use super::output::{prepare_out, write_file};
use super::session::{join_trials, print_header, print_metrics, RunArgs, TargetArg, TrialsCsv};
use super::{load_scene, CliError, CliResult};
use crate::cli::console::{errln, outln};
use e3d::command::CommandSpace;
use e3d::learner::LearnerSetup;
use e3d::report::run_scene::SceneRecord;
use e3d::session::{policy_effect_distribution, RunningMetrics};
use e3d::world::ExecutionPlan;
use e3d::world::{Executor, Workload, WorldError};
use e3d::{run_sessions, Control, Metrics, Params, Scene, SessionConfig, Target};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What `summary.json` holds (one session).
#[derive(Serialize)]
struct Summary<'a> {
    e3d_version: &'static str,
    scene: &'a str,
    /// The scene's file, content hash and effect grid (what `report` draws on).
    scene_record: SceneRecord,
    learner: &'static str,
    #[serde(flatten)]
    params: Params,
    seed: u64,
    use_reward: bool,
    /// With `--target reachable`: the cells of the target's support.
    #[serde(skip_serializing_if = "Option::is_none")]
    target_reachable_cells: Option<usize>,
    #[serde(flatten)]
    metrics: &'a Metrics,
    /// The exact effect distribution of the final policy (small command
    /// spaces only).
    policy_effect_distribution: Option<Vec<f64>>,
    effect_counts: Vec<f64>,
    /// How the outcomes were obtained (table, memo or live, and why).
    execution: &'a ExecutionPlan,
}

/// What `summary.json` holds with `--sessions N` (N > 1).
#[derive(Serialize)]
struct SessionsSummary<'a> {
    e3d_version: &'static str,
    scene: &'a str,
    scene_record: SceneRecord,
    learner: &'static str,
    #[serde(flatten)]
    params: Params,
    use_reward: bool,
    /// With `--target reachable`: the cells of the target's support.
    #[serde(skip_serializing_if = "Option::is_none")]
    target_reachable_cells: Option<usize>,
    /// Per session: its seed, metrics and effect counts.
    sessions: Vec<OneSession<'a>>,
    execution: &'a ExecutionPlan,
}

#[derive(Serialize)]
struct OneSession<'a> {
    seed: u64,
    #[serde(flatten)]
    metrics: &'a Metrics,
    effect_counts: Vec<f64>,
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
        prepare_out(dir, &["trials.csv", "summary.json"], a.force)?;
    }
    let seeds = seeds(&a)?;
    let only_trials = |what: &str| {
        CliError::input(format!(
            "--target reachable: {what}; it takes a scene of symbol commands run trial by trial (its outcome table lists the reachable cells)"
        ))
    };
    if let Some(continuous) = scene.as_continuous() {
        if a.target == TargetArg::Reachable {
            return Err(only_trials(&format!(
                "scene `{}` takes continuous commands",
                scene.spec().name
            )));
        }
        return super::continuous::run(&a, continuous, params, &seeds);
    }
    if super::episodes::wanted(&a, &scene) {
        if a.target == TargetArg::Reachable {
            return Err(only_trials("this run is of episodes"));
        }
        return super::episodes::run(&a, &scene, params, &seeds);
    }
    let sessions = a.sessions as usize;
    let space = scene.command_space();
    let num_effects = scene.num_effects();
    let cfg = |seed: u64| SessionConfig {
        trials: a.trials as usize,
        seed,
        use_reward: !a.no_reward,
    };
    let setup = LearnerSetup::new(a.learner).params(params);
    let make = || setup.symbols(&space, num_effects).map_err(CliError::input);
    make()?;
    let work = Workload {
        trials: a.trials.saturating_mul(a.sessions),
        sessions,
        threads: rayon::current_num_threads(),
    };
    let exec = executor(&a, &scene, &work)?;
    // p*: uniform over every cell, or over the cells the table reaches
    let target = match a.target {
        TargetArg::All => Target::Uniform,
        TargetArg::Reachable => match exec.table() {
            Some(t) => t.reachable_target(),
            None => {
                return Err(only_trials(&format!(
                    "scene `{}` has no outcome table here ({})",
                    scene.spec().name,
                    exec.plan()
                )))
            }
        },
    };
    let setup = setup.target(target.clone());
    let make = || setup.symbols(&space, num_effects).map_err(CliError::input);
    let mut learners = (0..sessions)
        .map(|_| make())
        .collect::<Result<Vec<_>, _>>()?;
    let mut recorders = recorders(&a, &space, num_effects)?;
    // a bar on a terminal, a line every few seconds otherwise
    let label = format!("run {}", scene.spec().name);
    let configs: Vec<SessionConfig> = seeds.iter().map(|&s| cfg(s)).collect();
    let status = super::progress::track(&label, "trials", work.trials, |p| {
        let add = |t| p.add(t);
        let control = Control::default().with_progress(&add);
        run_sessions(&exec, &mut learners, &configs, &mut recorders, &control)
    });
    if let Some(line) = exec.finish() {
        errln!("outcomes: {line}");
    }
    let files = finish_files(status, &mut recorders)?;
    let metrics = session_metrics(&exec, &recorders, &target, num_effects);
    let exact = match (exec.table(), sessions) {
        (Some(t), 1) => policy_effect_distribution(t, &*learners[0]),
        _ => None,
    };

    print_header(&a, &scene.spec().name, "", &params, &seeds);
    let support = (a.target == TargetArg::Reachable)
        .then(|| exec.table().map(|t| t.reachable_effects()))
        .flatten();
    if let Some(cells) = support {
        outln!("target: uniform over the {cells} reachable cells (of {num_effects})");
    }
    print_metrics(&metrics, &seeds, num_effects);
    if let Some(d) = &exact {
        let h = e3d::effect::entropy(d) / (d.len() as f64).ln();
        outln!("exact effect distribution of the final policy: normalised entropy {h:.4}");
    }

    if let Some(dir) = &a.out {
        let done = Finished {
            seeds: &seeds,
            metrics: &metrics,
            counts: recorders.iter().map(|r| r.0.effect_counts()).collect(),
            exact,
            plan: exec.plan(),
            support,
        };
        write_out(dir, &a, &scene, params, done, &files)?;
    }
    Ok(())
}

/// The executor of `scene` for `work`: an outcome table built first
/// shows its own progress (off a terminal, a line every few seconds); its
/// plan is told.
fn executor<'s>(a: &RunArgs, scene: &'s Scene, work: &Workload) -> Result<Executor<'s>, CliError> {
    let options = a.memo.options(a.table_cache.as_deref());
    let exec = super::progress::track(
        &format!("table {}", scene.spec().name),
        "commands",
        0,
        |p| {
            let (add, total) = (|k| p.add(k), |n| p.set_total(n));
            let control = Control {
                progress: &add,
                total: &total,
                ..Control::default()
            };
            Executor::with_control(scene, work, &options, &control)
        },
    )
    .map_err(CliError::simulation)?;
    errln!("outcomes: {}", exec.plan());
    Ok(exec)
}

/// Per session, its metrics and (with `--out`) its trials file.
fn recorders(
    a: &RunArgs,
    space: &CommandSpace,
    num_effects: usize,
) -> Result<Vec<(RunningMetrics, Option<TrialsCsv>)>, CliError> {
    let sessions = a.sessions as usize;
    let csv_path = a.out.as_ref().map(|d| d.join("trials.csv"));
    let csv = |i: usize| -> Result<Option<TrialsCsv>, CliError> {
        csv_path
            .as_ref()
            .map(|p| TrialsCsv::create(p, space, (sessions > 1).then_some(i)))
            .transpose()
    };
    (0..sessions)
        .map(|i| Ok((RunningMetrics::new(num_effects), csv(i)?)))
        .collect()
}

/// The trials files of the sessions, finished; the first failing
/// session (its `status`) fails the run, naming its command.
fn finish_files(
    status: Vec<Result<(), WorldError>>,
    recorders: &mut [(RunningMetrics, Option<TrialsCsv>)],
) -> Result<Vec<PathBuf>, CliError> {
    let mut files = Vec::new();
    for (st, (_, csv)) in status.into_iter().zip(recorders.iter_mut()) {
        st.map_err(CliError::simulation)?;
        if let Some(c) = csv.take() {
            files.push(c.finish()?);
        }
    }
    Ok(files)
}

/// Each session's metrics; with a table, the reachable cells are known
/// (when fewer than all): the metrics then hold the entropy over them
/// too.
fn session_metrics(
    exec: &Executor,
    recorders: &[(RunningMetrics, Option<TrialsCsv>)],
    target: &Target,
    num_effects: usize,
) -> Vec<Metrics> {
    let reachable = exec
        .table()
        .map(|t| t.reachable_effects())
        .filter(|&r| r < num_effects);
    recorders
        .iter()
        .map(|r| match reachable {
            Some(k) => r.0.metrics_over_reachable(target, k),
            None => r.0.metrics(target),
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

/// What the sessions of a run ended with, for `summary.json`.
struct Finished<'a> {
    seeds: &'a [u64],
    metrics: &'a [Metrics],
    /// Per session, its effect counts.
    counts: Vec<Vec<f64>>,
    /// The final policy's exact effect distribution (one session on a table).
    exact: Option<Vec<f64>>,
    plan: &'a ExecutionPlan,
    /// The cells of the target's support with `--target reachable`.
    support: Option<usize>,
}

/// Writes DIR/trials.csv (the sessions' streamed `files` joined) and
/// DIR/summary.json.
fn write_out(
    dir: &Path,
    a: &RunArgs,
    scene: &Scene,
    params: Params,
    done: Finished<'_>,
    files: &[PathBuf],
) -> CliResult {
    let sessions = done.seeds.len();
    let mut json = if sessions == 1 {
        serde_json::to_vec_pretty(&Summary {
            e3d_version: env!("CARGO_PKG_VERSION"),
            scene: &scene.spec().name,
            scene_record: SceneRecord::new(scene, &a.scene),
            learner: a.learner.as_str(),
            params,
            seed: a.seed,
            use_reward: !a.no_reward,
            target_reachable_cells: done.support,
            metrics: &done.metrics[0],
            policy_effect_distribution: done.exact,
            effect_counts: done.counts.into_iter().next().unwrap_or_default(),
            execution: done.plan,
        })
    } else {
        serde_json::to_vec_pretty(&SessionsSummary {
            e3d_version: env!("CARGO_PKG_VERSION"),
            scene: &scene.spec().name,
            scene_record: SceneRecord::new(scene, &a.scene),
            learner: a.learner.as_str(),
            params,
            use_reward: !a.no_reward,
            target_reachable_cells: done.support,
            sessions: done
                .metrics
                .iter()
                .zip(done.counts)
                .zip(done.seeds)
                .map(|((m, effect_counts), &seed)| OneSession {
                    seed,
                    metrics: m,
                    effect_counts,
                })
                .collect(),
            execution: done.plan,
        })
    }
    .map_err(CliError::output)?;
    json.push(b'\n');
    let header = if sessions > 1 {
        "session,trial,command,effect,reward"
    } else {
        "trial,command,effect,reward"
    };
    join_trials(&dir.join("trials.csv"), header, files)?;
    write_file(&dir.join("summary.json"), &json)?;
    outln!(
        "wrote {} and {}",
        dir.join("trials.csv").display(),
        dir.join("summary.json").display()
    );
    Ok(())
}
