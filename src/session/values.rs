//! Sessions of continuous commands: the trial loop with values in place
//! of symbols, and what it records.

use super::metrics::{discovery_trials, Metrics, LAST};
use super::SessionConfig;
use crate::command::ValueSpace;
use crate::effect::Target;
use crate::learner::ContinuousLearner;
use crate::rng::SessionRng;
use crate::world::{ContinuousWorld, Executor, Outcome, WorldError};
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use std::io::{self, Write};

/// What a session of continuous commands recorded, trial by trial (the
/// twin of [`SessionRecord`](super::SessionRecord), with values in place of symbols).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValueSessionRecord {
    /// The number of slots of each command.
    pub num_slots: usize,
    /// The number of effects of the world.
    pub num_effects: usize,
    /// The commands, `num_slots` values per trial, one after another.
    pub values: Vec<f64>,
    /// The effect of each trial.
    pub effects: Vec<usize>,
    /// The reward the learner received at each trial.
    pub rewards: Vec<f64>,
    /// The terminal point `(x, y)` of each trial.
    pub points: Vec<[f64; 2]>,
    /// Per slot, the mean and standard deviation of the learner's policy
    /// at the end ([`ContinuousLearner::slot_gaussian`]).
    pub final_policy: Vec<(f64, f64)>,
}

impl ValueSessionRecord {
    /// A record of no trials yet, with room for `trials`.
    fn empty(num_slots: usize, num_effects: usize, trials: usize) -> ValueSessionRecord {
        ValueSessionRecord {
            num_slots,
            num_effects,
            values: Vec::with_capacity(trials.saturating_mul(num_slots)),
            effects: Vec::with_capacity(trials),
            rewards: Vec::with_capacity(trials),
            points: Vec::with_capacity(trials),
            final_policy: Vec::new(),
        }
    }

    /// Records one trial: its values and outcome.
    fn push(&mut self, values: &[f64], outcome: &Outcome) {
        self.values.extend_from_slice(values);
        self.effects.push(outcome.effect);
        self.rewards.push(outcome.reward);
        self.points.push(outcome.point);
    }

    /// The number of trials.
    pub fn trials(&self) -> usize {
        self.effects.len()
    }

    /// The values of trial `t` (0-based).
    pub fn values_of(&self, t: usize) -> &[f64] {
        &self.values[t * self.num_slots..(t + 1) * self.num_slots]
    }

    /// How many trials in `range` ended in each effect.
    pub fn effect_counts(&self, range: std::ops::Range<usize>) -> Vec<f64> {
        let mut counts = vec![0.0; self.num_effects];
        for &e in &self.effects[range] {
            counts[e] += 1.0;
        }
        counts
    }

    /// The session's metrics against the target `p*` (as
    /// [`SessionRecord::metrics`](super::SessionRecord::metrics)).
    pub fn metrics(&self, target: &Target) -> Metrics {
        let t = self.trials();
        Metrics::from_counts(
            &self.effect_counts(0..t),
            &self.effect_counts(t.saturating_sub(LAST)..t),
            self.rewards.iter().fold(0.0, |a, r| a + r),
            self.rewards.iter().position(|&r| r > 0.0).map(|i| i + 1),
            &discovery_trials(&self.effects, self.num_effects),
            t,
            target,
            None,
        )
    }

    /// Writes `trial,values,effect,reward,x,y` CSV, one row per trial
    /// (trial 1-based; the values as [`ValueSpace::format`] writes them,
    /// quoted, for they hold commas), with a first `session` column when
    /// `session` is given.
    pub fn write_trials_csv(
        &self,
        space: &ValueSpace,
        session: Option<usize>,
        header: bool,
        mut out: impl Write,
    ) -> io::Result<()> {
        let lead = |s: Option<usize>| s.map_or(String::new(), |s| format!("{s},"));
        if header {
            let h = if session.is_some() { "session," } else { "" };
            writeln!(out, "{h}trial,values,effect,reward,x,y")?;
        }
        for t in 0..self.trials() {
            let [x, y] = self.points[t];
            writeln!(
                out,
                "{}{},\"{}\",{},{},{},{}",
                lead(session),
                t + 1,
                space.format(self.values_of(t)),
                self.effects[t],
                self.rewards[t],
                x,
                y
            )?;
        }
        Ok(())
    }
}

/// Runs `config.trials` trials of a learner of continuous commands on a
/// continuous world, calling `progress(t)` with the trials done every 64
/// trials and at the end.
///
/// ```
/// use e3d::{run_value_session, LearnerKind, Params, Scene, SessionConfig, Target};
/// let scene = Scene::builtin("arm7_continuous").unwrap();
/// let mut world = scene.as_continuous().unwrap().world(1);
/// let space = scene.value_space().unwrap();
/// let mut l = LearnerKind::E3d
///     .make_continuous(&Params::TASK1, &space, scene.num_effects(), &Target::Uniform)
///     .unwrap();
/// let cfg = SessionConfig { trials: 20, seed: 1, use_reward: false };
/// let rec = run_value_session(&mut world, &mut l, &cfg, |_| {}).unwrap();
/// assert_eq!(rec.trials(), 20);
/// assert_eq!(rec.values.len(), 20 * 7);
/// ```
pub fn run_value_session<W, L>(
    world: &mut W,
    learner: &mut L,
    config: &SessionConfig,
    mut progress: impl FnMut(usize),
) -> Result<ValueSessionRecord, WorldError>
where
    W: ContinuousWorld + ?Sized,
    L: ContinuousLearner + ?Sized,
{
    let n = world.value_space().num_slots();
    let trials = config.trials;
    let mut rec = ValueSessionRecord::empty(n, world.num_effects(), trials);
    let mut rng = SessionRng::seed_from_u64(config.seed);
    let mut values = Vec::with_capacity(n);
    for t in 0..trials {
        learner.propose(&mut rng, &mut values);
        let mut outcome = world.execute_values(&values)?;
        if !config.use_reward {
            outcome.reward = 0.0;
        }
        learner.learn(&values, &outcome);
        rec.push(&values, &outcome);
        if (t + 1) % 64 == 0 {
            progress(t + 1);
        }
    }
    progress(trials);
    rec.final_policy = (0..n).map(|s| learner.slot_gaussian(s)).collect();
    Ok(rec)
}

/// Runs several sessions of continuous commands on one world in
/// lockstep: at every trial each session proposes its values, the world
/// executes them all in one
/// [`execute_values_batch`](ContinuousWorld::execute_values_batch)
/// (several copies of a physics scene stepped together), then each
/// session learns from its own outcome.
///
/// Every session follows its algorithm exactly as [`run_value_session`]
/// would, trial by trial, with its own generator: on a world whose batches
/// give each command's single-world outcome (copies that are exact), the
/// records are those of the sessions run alone (tested). All sessions run
/// the trials of the longest; a session with fewer trials stops proposing
/// at its end. A session whose values fail gets the error; the others go
/// on. `progress(k)` is called with the `k` trials done, summed over the
/// sessions, every 64 lockstep trials and at the end.
pub fn run_value_lockstep<W, L>(
    world: &mut W,
    learners: &mut [L],
    configs: &[SessionConfig],
    mut progress: impl FnMut(u64),
) -> Vec<Result<ValueSessionRecord, WorldError>>
where
    W: ContinuousWorld + ?Sized,
    L: ContinuousLearner,
{
    assert_eq!(learners.len(), configs.len(), "one config per learner");
    let n = world.value_space().num_slots();
    let mut records: Vec<Result<ValueSessionRecord, WorldError>> = configs
        .iter()
        .map(|c| Ok(ValueSessionRecord::empty(n, world.num_effects(), c.trials)))
        .collect();
    let mut rngs: Vec<SessionRng> = configs
        .iter()
        .map(|c| SessionRng::seed_from_u64(c.seed))
        .collect();
    let mut batch: Vec<Vec<f64>> = configs.iter().map(|_| Vec::with_capacity(n)).collect();
    let mut active: Vec<usize> = Vec::with_capacity(configs.len());
    let mut outcomes = Vec::with_capacity(configs.len());
    let longest = configs.iter().map(|c| c.trials).max().unwrap_or(0);
    let mut since = 0u64;
    for t in 0..longest {
        active.clear();
        for (i, c) in configs.iter().enumerate() {
            if t < c.trials && records[i].is_ok() {
                learners[i].propose(&mut rngs[i], &mut batch[active.len()]);
                active.push(i);
            }
        }
        if active.is_empty() {
            break;
        }
        outcomes.clear();
        world.execute_values_batch(&batch[..active.len()], &mut outcomes);
        for ((&i, values), result) in active.iter().zip(&batch).zip(outcomes.drain(..)) {
            let Ok(rec) = &mut records[i] else {
                continue;
            };
            match result {
                Ok(mut outcome) => {
                    if !configs[i].use_reward {
                        outcome.reward = 0.0;
                    }
                    learners[i].learn(values, &outcome);
                    rec.push(values, &outcome);
                }
                Err(e) => records[i] = Err(e),
            }
        }
        since += active.len() as u64;
        if (t + 1) % 64 == 0 {
            progress(since);
            since = 0;
        }
    }
    progress(since);
    for (rec, l) in records.iter_mut().zip(learners.iter()) {
        if let Ok(rec) = rec {
            rec.final_policy = (0..n).map(|s| l.slot_gaussian(s)).collect();
        }
    }
    records
}

/// Runs each session of continuous commands, a config and its learner,
/// the way `exec` plans them ([`Executor::for_values`]), on every core of
/// the current rayon pool. The sessions are cut into
/// [`Executor::session_groups`], each group stepping together on one
/// world of [`Executor::copies_for`] copies of [`Executor::continuous`]
/// ([`run_value_lockstep`]; a group of one is [`run_value_session`]), and
/// the groups run in parallel. The records, in the order of `sessions`,
/// are those of [`run_value_session`] alone, whatever the threads.
/// `progress(k)` is called with each batch of `k` trials done. The first
/// session to fail gives the error; an executor of a scene of symbols is
/// an error.
///
/// ```
/// use e3d::world::{Executor, Workload};
/// use e3d::{run_value_session, run_value_sessions, LearnerKind, Params, Scene, SessionConfig, Target};
/// let scene = Scene::builtin("arm7_continuous").unwrap();
/// let space = scene.value_space().unwrap();
/// let learner = || {
///     LearnerKind::E3d
///         .make_continuous(&Params::TASK1, &space, scene.num_effects(), &Target::Uniform)
///         .unwrap()
/// };
/// let configs: Vec<SessionConfig> =
///     (0..2).map(|seed| SessionConfig { trials: 10, seed, use_reward: false }).collect();
/// let work = Workload { trials: 10, sessions: 2, threads: 2 };
/// let exec = Executor::for_values(&scene, &work).unwrap();
/// let sessions = configs.iter().map(|&c| (c, learner())).collect();
/// let recs = run_value_sessions(&exec, sessions, &|_| {}).unwrap();
/// let mut world = scene.as_continuous().unwrap().world(1);
/// let alone = run_value_session(&mut world, &mut learner(), &configs[1], |_| {}).unwrap();
/// assert_eq!(recs[1], alone);
/// ```
pub fn run_value_sessions<L>(
    exec: &Executor<'_>,
    sessions: Vec<(SessionConfig, L)>,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<ValueSessionRecord>, WorldError>
where
    L: ContinuousLearner + Send,
{
    use rayon::prelude::*;
    let scene = exec.continuous().ok_or_else(|| {
        WorldError::Other(
            "sessions of continuous commands need an executor of a continuous scene (Executor::for_values)"
                .into(),
        )
    })?;
    let mut rest = sessions.into_iter();
    let groups: Vec<(Vec<SessionConfig>, Vec<L>)> = exec
        .session_groups(rest.len())
        .into_iter()
        .map(|g| rest.by_ref().take(g.len()).unzip())
        .collect();
    groups
        .into_par_iter()
        .map(|(configs, mut learners)| {
            let mut world = scene.world(exec.copies_for(configs.len()));
            if let ([cfg], [learner]) = (&configs[..], &mut learners[..]) {
                let mut done = 0;
                let rec = run_value_session(&mut world, learner, cfg, |t| {
                    progress((t - done) as u64);
                    done = t;
                });
                return vec![rec];
            }
            run_value_lockstep(&mut world, &mut learners, &configs, progress)
        })
        .collect::<Vec<_>>()
        .into_iter()
        .flatten()
        .collect()
}
