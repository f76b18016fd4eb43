//! Sessions of continuous commands: the trial loop with values in place
//! of symbols, and what it records.

use super::metrics::{Metrics, RunningMetrics};
use super::{Control, Recorder, SessionConfig};
use crate::command::ValueSpace;
use crate::effect::Target;
use crate::learner::ContinuousLearner;
use crate::world::{ContinuousWorld, Outcome, WorldError};
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

impl Recorder<Vec<f64>> for ValueSessionRecord {
    fn record(&mut self, values: &Vec<f64>, outcome: &Outcome) {
        self.values.extend_from_slice(values);
        self.effects.push(outcome.effect);
        self.rewards.push(outcome.reward);
        self.points.push(outcome.point);
    }
}

impl ValueSessionRecord {
    /// A record of no trials yet, with room for `trials`.
    pub fn new(num_slots: usize, num_effects: usize, trials: usize) -> ValueSessionRecord {
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

    /// Sets [`final_policy`](Self::final_policy) from `learner`'s policy now.
    pub fn set_policy<L: ContinuousLearner + ?Sized>(&mut self, learner: &L) {
        self.final_policy = (0..self.num_slots)
            .map(|s| learner.slot_gaussian(s))
            .collect();
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
        super::count_effects(self.num_effects, &self.effects[range])
    }

    /// The session's metrics against the target `p*` (as
    /// [`SessionRecord::metrics`](super::SessionRecord::metrics)).
    pub fn metrics(&self, target: &Target) -> Metrics {
        RunningMetrics::replay(self.num_effects, &self.effects, &self.rewards)
            .metrics_given(target, None)
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
/// continuous world ([`run_session_into`](super::run_session_into) into a
/// [`ValueSessionRecord`], with the learner's final policy).
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::{LearnerKind, Scene, SessionConfig};
/// use e3d::session::run_value_session;
/// let scene = Scene::builtin("arm7_continuous").unwrap();
/// let mut world = scene.as_continuous().unwrap().world(1);
/// let space = scene.value_space().unwrap();
/// let mut l = LearnerSetup::new(LearnerKind::E3d).values(&space, scene.num_effects()).unwrap();
/// let cfg = SessionConfig { trials: 20, seed: 1, use_reward: false };
/// let rec = run_value_session(&mut world, &mut l, &cfg).unwrap();
/// assert_eq!(rec.trials(), 20);
/// assert_eq!(rec.values.len(), 20 * 7);
/// ```
pub fn run_value_session<W, L>(
    world: &mut W,
    learner: &mut L,
    config: &SessionConfig,
) -> Result<ValueSessionRecord, WorldError>
where
    W: ContinuousWorld + ?Sized,
    L: ContinuousLearner + ?Sized,
{
    let n = world.value_space().num_slots();
    let mut rec = ValueSessionRecord::new(n, world.num_effects(), config.trials);
    super::run_session_into(world, learner, config, &mut rec, &Control::default())?;
    rec.set_policy(learner);
    Ok(rec)
}
