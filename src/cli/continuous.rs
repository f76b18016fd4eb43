//! `e3d run` on a scene of continuous commands: live physics, the
//! sessions in lockstep groups of [`e3d::Executor::for_values`], the groups
//! in parallel on every core.

use super::run::{configs, track_run, Head};
use super::session::{print_header, print_metrics, write_run, RunArgs};
use super::{CliError, CliResult};
use crate::cli::console::errln;
use e3d::learner::LearnerSetup;
use e3d::session::ValueSessionRecord;
use e3d::world::ContinuousScene;
use e3d::{run_sessions, Metrics, Params, Target};
use serde::Serialize;

/// What `summary.json` holds for a run of continuous commands.
#[derive(Serialize)]
struct Summary<'a> {
    #[serde(flatten)]
    head: Head<'a>,
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
    let setup = LearnerSetup::new(a.learner).params(params);
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
    let work = e3d::world::Workload {
        trials: a.trials.saturating_mul(sessions as u64),
        sessions,
        threads,
    };
    let exec = e3d::Executor::for_values(scene, &work).map_err(CliError::input)?;
    errln!(
        "outcomes: live: continuous commands, {} trials x {sessions} session(s) x {steps} steps, on {threads} thread(s){}",
        a.trials,
        match exec.plan().copies {
            1 => String::new(),
            k => format!(", in lockstep up to {k} sessions per world"),
        }
    );
    let status = track_run(a, scene, "trials", sessions, |control| {
        run_sessions(&exec, &mut learners, &configs, &mut records, control)
    });
    for ((st, rec), learner) in status.into_iter().zip(&mut records).zip(&learners) {
        st.map_err(CliError::simulation)?;
        rec.set_policy(learner);
    }
    let metrics: Vec<Metrics> = records
        .iter()
        .map(|r| r.metrics(&Target::Uniform))
        .collect();
    print_header(a, name, " (continuous)", &params, seeds);
    print_metrics(&metrics, seeds, num_effects);
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
    let summary = Summary {
        head: Head::new(a, scene, params),
        use_reward: !a.no_reward,
        execution: "live",
        sessions: (records.iter().zip(&metrics).zip(seeds))
            .map(|((r, m), &seed)| OneSession {
                seed,
                metrics: m,
                effect_counts: r.effect_counts(0..r.trials()),
                final_policy: (r.final_policy.iter())
                    .map(|&(mean, sd)| SlotPolicy { mean, sd })
                    .collect(),
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
