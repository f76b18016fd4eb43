//! `e3d run` on a scene of continuous commands: live physics, the
//! sessions in lockstep groups of [`e3d::Executor::for_values`], the groups
//! in parallel on every core.

use super::output::write_file;
use super::session::{join_trials, print_header, print_metrics, RunArgs};
use super::{CliError, CliResult};
use crate::cli::console::{errln, outln};
use e3d::learner::LearnerSetup;
use e3d::session::ValueSessionRecord;
use e3d::world::ContinuousScene;
use e3d::{run_sessions, Control, Metrics, Params, Scene, SessionConfig, Target};
use serde::Serialize;

/// What `summary.json` holds for a run of continuous commands.
#[derive(Serialize)]
struct Summary<'a> {
    e3d_version: &'static str,
    scene: &'a str,
    /// The scene's file, content hash and effect grid (what `report` draws on).
    scene_record: e3d::report::run_scene::SceneRecord,
    learner: &'static str,
    #[serde(flatten)]
    params: Params,
    use_reward: bool,
    /// Always `"live"`: continuous commands have no table or memo.
    execution: &'static str,
    /// Per session: its seed, metrics, effect counts and final policy.
    sessions: Vec<OneSession<'a>>,
}

#[derive(Serialize)]
struct OneSession<'a> {
    seed: u64,
    #[serde(flatten)]
    metrics: &'a Metrics,
    effect_counts: Vec<f64>,
    /// Per slot: the mean and standard deviation of the final policy, in
    /// the slot's unit.
    final_policy: Vec<SlotPolicy>,
}

#[derive(Serialize)]
struct SlotPolicy {
    mean: f64,
    sd: f64,
}

/// Runs `a`'s sessions of continuous commands on `scene`.
pub fn run(a: &RunArgs, continuous: ContinuousScene, params: Params, seeds: &[u64]) -> CliResult {
    let scene = continuous.scene();
    if a.table_cache.is_some() {
        return Err(CliError::input(format!(
            "--table-cache: scene `{}` takes continuous commands, which have no outcome table (every trial is simulated)",
            scene.spec().name
        )));
    }
    if matches!(a.memo.outcomes.0, Some(s) if s != e3d::world::Strategy::Live) {
        return Err(CliError::input(format!(
            "--outcomes: scene `{}` takes continuous commands, which run live only (no table, no memo)",
            scene.spec().name
        )));
    }
    let space = continuous.values();
    let num_effects = scene.num_effects();
    let target = Target::Uniform;
    let setup = LearnerSetup::new(a.learner).params(params);
    let make = || setup.values(space, num_effects).map_err(CliError::input);
    let configs: Vec<SessionConfig> = seeds
        .iter()
        .map(|&seed| SessionConfig {
            trials: a.trials as usize,
            seed,
            use_reward: !a.no_reward,
        })
        .collect();
    let mut learners = configs
        .iter()
        .map(|_| make())
        .collect::<Result<Vec<_>, CliError>>()?;
    let mut records: Vec<ValueSessionRecord> = configs
        .iter()
        .map(|c| ValueSessionRecord::new(space.num_slots(), num_effects, c.trials))
        .collect();
    let num_sessions = seeds.len();
    let steps = scene.spec().steps_per_command().unwrap_or(0) as u64;
    let threads = rayon::current_num_threads();
    let work = e3d::world::Workload {
        trials: a.trials.saturating_mul(num_sessions as u64),
        sessions: num_sessions,
        threads,
    };
    let exec = e3d::Executor::for_values(scene, &work).map_err(CliError::input)?;
    errln!(
        "outcomes: live: continuous commands, {} trials x {num_sessions} session(s) x {steps} steps, on {threads} thread(s){}",
        a.trials,
        match exec.plan().copies {
            1 => String::new(),
            k => format!(", in lockstep up to {k} sessions per world"),
        }
    );
    let label = format!("run {}", scene.spec().name);
    let total = a.trials.saturating_mul(num_sessions as u64);
    let status = super::progress::track(&label, "trials", total, |p| {
        let add = |k: u64| p.add(k);
        let control = Control::default().with_progress(&add);
        run_sessions(&exec, &mut learners, &configs, &mut records, &control)
    });
    for ((st, rec), learner) in status.into_iter().zip(&mut records).zip(&learners) {
        st.map_err(CliError::simulation)?;
        rec.set_policy(learner);
    }
    let metrics: Vec<Metrics> = records.iter().map(|r| r.metrics(&target)).collect();
    print_header(a, &scene.spec().name, " (continuous)", &params, seeds);
    print_metrics(&metrics, seeds, num_effects);
    if let Some(dir) = &a.out {
        write_out(dir, a, scene, params, seeds, &records, &metrics, space)?;
    }
    Ok(())
}

/// Writes DIR/trials.csv (whole or absent) and DIR/summary.json.
#[allow(clippy::too_many_arguments)]
fn write_out(
    dir: &std::path::Path,
    a: &RunArgs,
    scene: &Scene,
    params: Params,
    seeds: &[u64],
    records: &[ValueSessionRecord],
    metrics: &[Metrics],
    space: &e3d::command::ValueSpace,
) -> CliResult {
    let several = records.len() > 1;
    let csv = dir.join("trials.csv");
    let (part, file) = e3d::io::create_temp_beside(&csv)
        .map_err(|e| CliError::output(format!("{}: cannot write: {e}", csv.display())))?;
    let written = (|| -> std::io::Result<()> {
        let mut out = std::io::BufWriter::new(file);
        for (i, r) in records.iter().enumerate() {
            r.write_trials_csv(space, several.then_some(i), false, &mut out)?;
        }
        std::io::Write::flush(&mut out)
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_file(&part);
        return Err(CliError::output(format!(
            "{}: cannot write: {e}",
            csv.display()
        )));
    }
    let header = if several {
        "session,trial,values,effect,reward,x,y"
    } else {
        "trial,values,effect,reward,x,y"
    };
    join_trials(&csv, header, &[part])?;
    let summary = Summary {
        e3d_version: env!("CARGO_PKG_VERSION"),
        scene: &scene.spec().name,
        scene_record: e3d::report::run_scene::SceneRecord::new(scene, &a.scene),
        learner: a.learner.as_str(),
        params,
        use_reward: !a.no_reward,
        execution: "live",
        sessions: records
            .iter()
            .zip(metrics)
            .zip(seeds)
            .map(|((r, m), &seed)| OneSession {
                seed,
                metrics: m,
                effect_counts: r.effect_counts(0..r.trials()),
                final_policy: r
                    .final_policy
                    .iter()
                    .map(|&(mean, sd)| SlotPolicy { mean, sd })
                    .collect(),
            })
            .collect(),
    };
    let mut json = serde_json::to_vec_pretty(&summary).map_err(CliError::output)?;
    json.push(b'\n');
    write_file(&dir.join("summary.json"), &json)?;
    outln!(
        "wrote {} and {}",
        csv.display(),
        dir.join("summary.json").display()
    );
    Ok(())
}
