//! Sessions: the trial loop, what it records, and the metrics of a run.
//!
//! One trial: the learner proposes a command, the world executes it open
//! loop, the learner learns from the outcome. [`run_session`] repeats it
//! and records, per trial, the command, the effect and the reward.

use crate::command::{Command, CommandSpace, ValueSpace};
use crate::effect::Target;
use crate::learner::{ContinuousLearner, Effort, Effortful, Learner};
use crate::rng::SessionRng;
use crate::world::{ContinuousWorld, Outcome, World, WorldError};
use serde::{Deserialize, Serialize};
use std::io::{self, Write};

mod builder;
mod engine;
mod metrics;
mod repeat;

pub use builder::{Session, SessionError};
pub use engine::{
    run_episode_sessions, run_group, run_planned, run_sessions, Control, Executes, Learns,
    Observer, Worlds,
};

pub use metrics::{policy_effect_distribution, trials_to_fraction, Metrics, RunningMetrics};
pub use repeat::{
    episode_reproducibility, reevaluate, reevaluate_with, reproducibility, run_key, RepeatOptions,
    Repeated, Reproducibility,
};

/// How to run a session.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SessionConfig {
    /// The number of trials.
    pub trials: usize,
    /// The seed of the session's generator ([`SessionRng`]).
    pub seed: u64,
    /// Whether the learner sees the scene's reward (task 2) or 0 always
    /// (task 1, `--no-reward`).
    pub use_reward: bool,
}

/// What a session recorded, trial by trial, of commands of `num_slots`
/// elements `T`: symbol indices ([`SessionRecord`]) or values
/// ([`ValueSessionRecord`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrialRecord<T> {
    /// The number of slots of each command.
    pub num_slots: usize,
    /// The number of effects of the world.
    pub num_effects: usize,
    /// The commands, `num_slots` elements per trial, one after another.
    pub commands: Vec<T>,
    /// The effect of each trial (as in [`Outcome::effect`]).
    pub effects: Vec<usize>,
    /// The reward the learner received at each trial.
    pub rewards: Vec<f64>,
    /// The terminal point `(x, y)` of each trial (as in [`Outcome::point`]).
    pub points: Vec<[f64; 2]>,
    /// Per slot, the mean and standard deviation of a learner of values'
    /// policy at the end ([`ValueSessionRecord::set_policy`]); else empty.
    pub final_policy: Vec<(f64, f64)>,
}

/// What a session of commands of symbols recorded.
pub type SessionRecord = TrialRecord<u8>;

/// Runs `config.trials` trials of `learner` on `world`.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::{run_session, LearnerKind, Params, Scene, SessionConfig, Target};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let mut world = scene.build();
/// let mut learner = LearnerSetup::new(LearnerKind::E3d)
///     .symbols(&scene.command_space(), scene.num_effects())
///     .unwrap();
/// let cfg = SessionConfig { trials: 500, seed: 1, use_reward: false };
/// let rec = run_session(&mut world, &mut learner, &cfg).unwrap();
/// assert_eq!(rec.effects.len(), 500);
/// assert!(rec.metrics(&Target::Uniform).distinct_effects > 10);
/// ```
pub fn run_session<W, L>(
    world: &mut W,
    learner: &mut L,
    config: &SessionConfig,
) -> Result<SessionRecord, WorldError>
where
    W: World + ?Sized,
    L: Learner + ?Sized,
{
    let mut rec = SessionRecord::new(world, config.trials);
    run_session_into(world, learner, config, &mut rec, &Control::default())?;
    Ok(rec)
}

/// Runs a session, handing each trial to `recorder` instead of keeping
/// them: with a [`RunningMetrics`], a session of any length runs in
/// constant memory. A session of symbols or of values alike: [`run_group`]
/// of one session.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::session::{run_session_into, Control};
/// use e3d::{run_session, LearnerKind, Params, Scene, SessionConfig, Target};
/// use e3d::session::RunningMetrics;
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let make = || LearnerSetup::new(LearnerKind::E3d)
///     .symbols(&scene.command_space(), scene.num_effects())
///     .unwrap();
/// let cfg = SessionConfig { trials: 3000, seed: 1, use_reward: false };
/// let mut running = RunningMetrics::new(scene.num_effects());
/// run_session_into(&mut scene.build(), &mut make(), &cfg, &mut running, &Control::default())
///     .unwrap();
/// let kept = run_session(&mut scene.build(), &mut make(), &cfg).unwrap();
/// // the same metrics, bit for bit, without keeping the 3000 trials
/// assert_eq!(running.metrics(&Target::Uniform), kept.metrics(&Target::Uniform));
/// ```
pub fn run_session_into<C, W, L, R>(
    world: &mut W,
    learner: &mut L,
    config: &SessionConfig,
    recorder: &mut R,
    control: &(impl Observer + ?Sized),
) -> Result<(), WorldError>
where
    C: Clone,
    W: Executes<C> + ?Sized,
    L: Learns<C> + ?Sized,
    R: Recorder<C> + ?Sized,
{
    let (learner, recorder) = (&mut [One(learner)], &mut [recorder]);
    run_group(
        world,
        learner,
        std::slice::from_ref(config),
        recorder,
        control,
    )
    .remove(0)
}

/// A learner borrowed for [`run_session_into`].
struct One<'a, L: ?Sized>(&'a mut L);

impl<C, L: Learns<C> + ?Sized> Learns<C> for One<'_, L> {
    fn propose_next(&mut self, rng: &mut SessionRng, command: &mut C) {
        self.0.propose_next(rng, command)
    }
    fn learn_from(&mut self, command: &C, outcome: &Outcome) {
        self.0.learn_from(command, outcome)
    }
    fn likely(&self, blank: &C, n: usize, rng: &mut SessionRng) -> Option<Vec<C>> {
        self.0.likely(blank, n, rng)
    }
}

/// What a session keeps of each trial of commands of kind `C` ([`Command`]
/// by default; `Vec<f64>` for continuous commands).
///
/// [`SessionRecord`] keeps every trial; [`RunningMetrics`] only what the
/// metrics need (constant memory); a pair `(A, B)` hands each trial to
/// both; implement it to stream trials elsewhere (a file, a plot).
pub trait Recorder<C: ?Sized = Command> {
    /// One trial: the command and its outcome as the learner saw it (the
    /// reward is 0 when the session ignores rewards).
    fn record(&mut self, command: &C, outcome: &Outcome);
}

impl<C: ?Sized, R: Recorder<C> + ?Sized> Recorder<C> for &mut R {
    fn record(&mut self, command: &C, outcome: &Outcome) {
        (**self).record(command, outcome)
    }
}

/// `None` records nothing (an optional output).
impl<C: ?Sized, R: Recorder<C>> Recorder<C> for Option<R> {
    fn record(&mut self, command: &C, outcome: &Outcome) {
        if let Some(r) = self {
            r.record(command, outcome)
        }
    }
}

impl<C: ?Sized, A: Recorder<C>, B: Recorder<C>> Recorder<C> for (A, B) {
    fn record(&mut self, command: &C, outcome: &Outcome) {
        self.0.record(command, outcome);
        self.1.record(command, outcome);
    }
}

impl<T: Copy, C: AsRef<[T]> + ?Sized> Recorder<C> for TrialRecord<T> {
    fn record(&mut self, command: &C, outcome: &Outcome) {
        self.commands.extend_from_slice(command.as_ref());
        self.effects.push(outcome.effect);
        self.rewards.push(outcome.reward);
        self.points.push(outcome.point);
    }
}

impl<T> TrialRecord<T> {
    /// A record of no trials yet, with room for `trials`.
    fn with_room(num_slots: usize, num_effects: usize, trials: usize) -> Self {
        TrialRecord {
            num_slots,
            num_effects,
            commands: Vec::with_capacity(trials.saturating_mul(num_slots)),
            effects: Vec::with_capacity(trials),
            rewards: Vec::with_capacity(trials),
            points: Vec::with_capacity(trials),
            final_policy: Vec::new(),
        }
    }

    /// The number of trials.
    pub fn trials(&self) -> usize {
        self.effects.len()
    }

    /// The command of trial `t` (0-based): its slots' symbol indices or
    /// values.
    pub fn values_of(&self, t: usize) -> &[T] {
        &self.commands[t * self.num_slots..(t + 1) * self.num_slots]
    }

    /// How many trials in `range` ended in each effect.
    pub fn effect_counts(&self, range: std::ops::Range<usize>) -> Vec<f64> {
        let mut counts = vec![0.0; self.num_effects];
        for &e in &self.effects[range] {
            counts[e] += 1.0;
        }
        counts
    }

    /// The running sum of rewards, one value per trial.
    pub fn cumulative_rewards(&self) -> Vec<f64> {
        self.rewards
            .iter()
            .scan(0.0, |acc, r| {
                *acc += r;
                Some(*acc)
            })
            .collect()
    }

    /// The session's metrics against the target `p*`.
    pub fn metrics(&self, target: &Target) -> Metrics {
        self.replay().metrics(target)
    }

    /// The same, with the entropy over the `reachable_effects` effects
    /// some command reaches as well ([`Metrics::normalized_entropy_reachable`]).
    ///
    /// ```
    /// use e3d::learner::LearnerSetup;
    /// use e3d::{run_session, LearnerKind, OutcomeTable, Params, Scene, SessionConfig, Target};
    /// let scene = Scene::builtin("two_rooms").unwrap();
    /// let table = OutcomeTable::build(&mut scene.build()).unwrap();
    /// let mut l = LearnerSetup::new(LearnerKind::E3d)
    ///     .symbols(&scene.command_space(), scene.num_effects())
    ///     .unwrap();
    /// let cfg = SessionConfig { trials: 2000, seed: 3, use_reward: false };
    /// let rec = run_session(&mut &table, &mut l, &cfg).unwrap();
    /// let m = rec.metrics_over_reachable(&Target::Uniform, table.reachable_effects());
    /// assert_eq!(m.reachable_effects, Some(table.reachable_effects()));
    /// // fewer cells in the normaliser: a higher entropy than over all of them
    /// assert!(m.normalized_entropy_reachable.unwrap() >= m.normalized_entropy);
    /// assert_eq!(rec.metrics(&Target::Uniform).normalized_entropy_reachable, None);
    /// ```
    pub fn metrics_over_reachable(&self, target: &Target, reachable_effects: usize) -> Metrics {
        self.replay()
            .metrics_over_reachable(target, reachable_effects)
    }

    /// The QD-score of the recorded commands by `effort`
    /// ([`Metrics::qd_score`], which [`metrics`](Self::metrics) leaves
    /// `None`): the sum over the reached cells of the best effort quality
    /// among the commands that reached them; `None` if `effort` does not
    /// vary ([`Effort::varies`]).
    ///
    /// ```
    /// use e3d::learner::Effort;
    /// use e3d::{Command, Outcome, Recorder, SessionRecord, Scene};
    /// let scene = Scene::builtin("arm7").unwrap();
    /// let space = scene.command_space();
    /// let mut rec = SessionRecord::new(&scene.build(), 2);
    /// let o = Outcome { effect: 3, reward: 0.0, point: [0.0; 2] };
    /// rec.record(&space.parse("+000000").unwrap(), &o); // 1.8 N·m
    /// rec.record(&space.parse("00000-0").unwrap(), &o); // 0.12 N·m: the elite
    /// let qd = rec.qd_score(&Effort::of_scene(&scene)).unwrap();
    /// assert!((qd - (1.0 - 0.12 / 4.62)).abs() < 1e-12);
    /// ```
    pub fn qd_score(&self, effort: &Effort) -> Option<f64>
    where
        [T]: Effortful,
    {
        let mut m = RunningMetrics::new(self.num_effects).with_effort(effort.clone());
        for t in 0..self.trials() {
            let (effect, reward, point) = (self.effects[t], self.rewards[t], self.points[t]);
            m.record(
                self.values_of(t),
                &Outcome {
                    effect,
                    reward,
                    point,
                },
            );
        }
        m.metrics(&Target::Uniform).qd_score
    }

    fn replay(&self) -> RunningMetrics {
        let mut m = RunningMetrics::new(self.num_effects);
        for (&effect, &reward) in self.effects.iter().zip(&self.rewards) {
            let point = [0.0; 2];
            m.record(
                &(),
                &Outcome {
                    effect,
                    reward,
                    point,
                },
            );
        }
        m
    }
}

impl SessionRecord {
    /// An empty record for `trials` trials on `world`.
    pub fn new<W: World + ?Sized>(world: &W, trials: usize) -> Self {
        Self::with_room(
            world.command_space().num_slots(),
            world.num_effects(),
            trials,
        )
    }

    /// The command of trial `t` (0-based).
    pub fn command(&self, t: usize) -> Command {
        Command::new(self.values_of(t).to_vec())
    }

    /// Writes `trial,command,effect,reward` CSV, one row per trial (trial
    /// 1-based, the command as its symbols).
    pub fn write_trials_csv(&self, space: &CommandSpace, mut out: impl Write) -> io::Result<()> {
        writeln!(out, "trial,command,effect,reward")?;
        let mut c = space.first();
        for t in 0..self.trials() {
            c.symbols.copy_from_slice(self.values_of(t));
            writeln!(
                out,
                "{},{},{},{}",
                t + 1,
                space.format(&c),
                self.effects[t],
                self.rewards[t]
            )?;
        }
        Ok(())
    }
}

/// What a session of continuous commands recorded.
pub type ValueSessionRecord = TrialRecord<f64>;

impl ValueSessionRecord {
    /// A record of no trials yet, with room for `trials`.
    pub fn new(num_slots: usize, num_effects: usize, trials: usize) -> ValueSessionRecord {
        Self::with_room(num_slots, num_effects, trials)
    }

    /// Sets [`final_policy`](Self::final_policy) from `learner`'s policy now.
    pub fn set_policy<L: ContinuousLearner + ?Sized>(&mut self, learner: &L) {
        self.final_policy = (0..self.num_slots)
            .map(|s| learner.slot_gaussian(s))
            .collect();
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
/// continuous world ([`run_session_into`] into a
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
/// assert_eq!(rec.commands.len(), 20 * 7);
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
    run_session_into(world, learner, config, &mut rec, &Control::default())?;
    rec.set_policy(learner);
    Ok(rec)
}
