//! Sessions: the trial loop, what it records, and the metrics of a run.
//!
//! One trial: the learner proposes a command, the world executes it open
//! loop, the learner learns from the outcome. [`run_session`] repeats it
//! and records, per trial, the command, the effect and the reward.

use crate::command::{Command, CommandSpace, ValueSpace};
use crate::effect::{entropy, kl_divergence, normalized_entropy_over, Target};
use crate::learner::{ContinuousLearner, Learner};
use crate::world::{ContinuousWorld, Executor, Outcome, OutcomeTable, World, WorldError};
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use std::io::{self, Write};

use crate::rng::SessionRng;

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

/// What a session recorded, trial by trial.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SessionRecord {
    /// The number of slots of each command.
    pub num_slots: usize,
    /// The number of effects of the world.
    pub num_effects: usize,
    /// The commands, `num_slots` symbol indices per trial, one after another.
    pub commands: Vec<u8>,
    /// The effect of each trial (as in [`Outcome::effect`]).
    pub effects: Vec<usize>,
    /// The reward the learner received at each trial.
    pub rewards: Vec<f64>,
    /// The terminal point `(x, y)` of each trial (as in [`Outcome::point`]).
    pub points: Vec<[f64; 2]>,
}

/// Runs `config.trials` trials of `learner` on `world`.
///
/// ```
/// use e3d::{run_session, LearnerKind, Params, Scene, SessionConfig, Target};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let mut world = scene.build();
/// let mut learner = LearnerKind::E3d
///     .make(&Params::TASK1, &scene.command_space(), scene.num_effects(), &Target::Uniform)
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
    run_session_with(world, learner, config, |_| {})
}

/// [`run_session`], calling `progress(trials_done)` every 256 trials.
pub fn run_session_with<W, L>(
    world: &mut W,
    learner: &mut L,
    config: &SessionConfig,
    progress: impl FnMut(usize),
) -> Result<SessionRecord, WorldError>
where
    W: World + ?Sized,
    L: Learner + ?Sized,
{
    let mut rec = SessionRecord::new(world, config.trials);
    run_session_into(world, learner, config, &mut rec, progress)?;
    Ok(rec)
}

/// Runs a session, handing each trial to `recorder` instead of keeping
/// them: with a [`RunningMetrics`], a session of any length runs in
/// constant memory. `progress(trials_done)` is called every 256 trials and
/// at the end.
///
/// ```
/// use e3d::{run_session, run_session_into, LearnerKind, Params, RunningMetrics, Scene,
///           SessionConfig, Target};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let make = || LearnerKind::E3d
///     .make(&Params::TASK1, &scene.command_space(), scene.num_effects(), &Target::Uniform)
///     .unwrap();
/// let cfg = SessionConfig { trials: 3000, seed: 1, use_reward: false };
/// let mut running = RunningMetrics::new(scene.num_effects());
/// run_session_into(&mut scene.build(), &mut make(), &cfg, &mut running, |_| {}).unwrap();
/// let kept = run_session(&mut scene.build(), &mut make(), &cfg).unwrap();
/// // the same metrics, bit for bit, without keeping the 3000 trials
/// assert_eq!(running.metrics(&Target::Uniform), kept.metrics(&Target::Uniform));
/// ```
pub fn run_session_into<W, L, R>(
    world: &mut W,
    learner: &mut L,
    config: &SessionConfig,
    recorder: &mut R,
    mut progress: impl FnMut(usize),
) -> Result<(), WorldError>
where
    W: World + ?Sized,
    L: Learner + ?Sized,
    R: Recorder + ?Sized,
{
    let mut rng = SessionRng::seed_from_u64(config.seed);
    let mut command = world.command_space().first();
    for t in 0..config.trials {
        learner.propose(&mut rng, &mut command);
        let mut outcome = world.execute(&command)?;
        if !config.use_reward {
            outcome.reward = 0.0;
        }
        learner.learn(&command, &outcome);
        recorder.record(&command, &outcome);
        if t % 256 == 255 {
            progress(t + 1);
        }
    }
    progress(config.trials);
    Ok(())
}

/// What a session keeps of each trial.
///
/// [`SessionRecord`] keeps every trial; [`RunningMetrics`] only what the
/// metrics need (constant memory); a pair `(A, B)` hands each trial to
/// both; implement it to stream trials elsewhere (a file, a plot).
pub trait Recorder {
    /// One trial: the command and its outcome as the learner saw it (the
    /// reward is 0 when the session ignores rewards).
    fn record(&mut self, command: &Command, outcome: &Outcome);
}

impl<R: Recorder + ?Sized> Recorder for &mut R {
    fn record(&mut self, command: &Command, outcome: &Outcome) {
        (**self).record(command, outcome)
    }
}

/// `None` records nothing (an optional output).
impl<R: Recorder> Recorder for Option<R> {
    fn record(&mut self, command: &Command, outcome: &Outcome) {
        if let Some(r) = self {
            r.record(command, outcome)
        }
    }
}

impl<A: Recorder, B: Recorder> Recorder for (A, B) {
    fn record(&mut self, command: &Command, outcome: &Outcome) {
        self.0.record(command, outcome);
        self.1.record(command, outcome);
    }
}

impl Recorder for SessionRecord {
    fn record(&mut self, command: &Command, outcome: &Outcome) {
        self.commands.extend_from_slice(&command.symbols);
        self.effects.push(outcome.effect);
        self.rewards.push(outcome.reward);
        self.points.push(outcome.point);
    }
}

/// The trials the last-trials entropy covers.
const LAST: usize = 1000;

/// The metrics of a session, kept as it runs, in constant memory: effect
/// counts, the last 1000 effects, the reward so far and at chosen trials.
/// Its [`metrics`](Self::metrics) equal [`SessionRecord::metrics`] bit for
/// bit.
#[derive(Debug, Clone, PartialEq)]
pub struct RunningMetrics {
    counts: Vec<u64>,
    /// The last [`LAST`] effects, a ring (`trials % LAST` is the next).
    last: Vec<u32>,
    trials: usize,
    cumulative: f64,
    first_reward: Option<usize>,
    /// The 1-based trial at which each effect was first reached, in order.
    discoveries: Vec<usize>,
    /// Trials (1-based, increasing) at which the cumulative reward is kept.
    checkpoints: Vec<usize>,
    at_checkpoints: Vec<f64>,
}

impl RunningMetrics {
    /// Nothing recorded yet, for a world of `num_effects` effects.
    pub fn new(num_effects: usize) -> Self {
        Self::with_checkpoints(num_effects, &[])
    }

    /// The same, keeping the cumulative reward after each of the trials
    /// `checkpoints` (1-based) for [`cumulative_reward_at`](Self::cumulative_reward_at).
    pub fn with_checkpoints(num_effects: usize, checkpoints: &[usize]) -> Self {
        let mut checkpoints = checkpoints.to_vec();
        checkpoints.sort_unstable();
        checkpoints.dedup();
        RunningMetrics {
            counts: vec![0; num_effects],
            last: Vec::with_capacity(LAST),
            trials: 0,
            cumulative: 0.0,
            first_reward: None,
            discoveries: Vec::new(),
            at_checkpoints: Vec::with_capacity(checkpoints.len()),
            checkpoints,
        }
    }

    /// The number of trials recorded.
    pub fn trials(&self) -> usize {
        self.trials
    }

    /// How many trials ended in each effect.
    pub fn effect_counts(&self) -> Vec<f64> {
        self.counts.iter().map(|&c| c as f64).collect()
    }

    /// The sum of the rewards after trial `t` (1-based), if `t` was one of
    /// the checkpoints and has been reached.
    pub fn cumulative_reward_at(&self, t: usize) -> Option<f64> {
        let k = self.checkpoints.iter().position(|&c| c == t)?;
        self.at_checkpoints.get(k).copied()
    }

    /// The session's metrics against the target `p*`.
    pub fn metrics(&self, target: &Target) -> Metrics {
        self.metrics_given(target, None)
    }

    /// The same, with the entropy over the `reachable_effects` effects
    /// some command reaches (see [`SessionRecord::metrics_over_reachable`]).
    pub fn metrics_over_reachable(&self, target: &Target, reachable_effects: usize) -> Metrics {
        self.metrics_given(target, Some(reachable_effects))
    }

    fn metrics_given(&self, target: &Target, reachable: Option<usize>) -> Metrics {
        let mut last = vec![0.0; self.counts.len()];
        for &e in &self.last {
            last[e as usize] += 1.0;
        }
        Metrics::from_counts(
            &self.effect_counts(),
            &last,
            self.cumulative,
            self.first_reward,
            &self.discoveries,
            self.trials,
            target,
            reachable,
        )
    }
}

impl Recorder for RunningMetrics {
    fn record(&mut self, _command: &Command, outcome: &Outcome) {
        if self.counts[outcome.effect] == 0 {
            self.discoveries.push(self.trials + 1);
        }
        self.counts[outcome.effect] += 1;
        if self.last.len() < LAST {
            self.last.push(outcome.effect as u32);
        } else {
            self.last[self.trials % LAST] = outcome.effect as u32;
        }
        self.trials += 1;
        self.cumulative += outcome.reward;
        if self.first_reward.is_none() && outcome.reward > 0.0 {
            self.first_reward = Some(self.trials);
        }
        if self.checkpoints.get(self.at_checkpoints.len()) == Some(&self.trials) {
            self.at_checkpoints.push(self.cumulative);
        }
    }
}

/// Runs several sessions on one world in lockstep: at every trial each
/// session proposes its command, the world executes them all in one
/// [`World::execute_batch`] (several copies of a physics scene stepped
/// together), then each session learns from its own outcome.
///
/// Every session follows its algorithm exactly as [`run_session`] would,
/// trial by trial, with its own generator: the records are the same as
/// running the sessions one after the other (tested). All sessions run the
/// trials of the longest; a session with fewer trials stops proposing at
/// its end. A session whose command fails gets the error; the others go on.
pub fn run_lockstep<W, L>(
    world: &mut W,
    learners: &mut [L],
    configs: &[SessionConfig],
) -> Vec<Result<SessionRecord, WorldError>>
where
    W: World + ?Sized,
    L: Learner,
{
    let mut records: Vec<SessionRecord> = configs
        .iter()
        .map(|c| SessionRecord::new(world, c.trials))
        .collect();
    let status = run_lockstep_into(world, learners, configs, &mut records, |_| {});
    status
        .into_iter()
        .zip(records)
        .map(|(s, r)| s.map(|()| r))
        .collect()
}

/// [`run_lockstep`], handing each session's trials to its own recorder
/// (`recorders[i]` for session `i`); returns each session's status. A
/// session whose command fails stops there with the error (its recorder
/// keeps the trials before it); the others go on. `progress(trials)` is
/// called every 256 lockstep trials with the trials done since the last
/// call, summed over the sessions, and at the end.
pub fn run_lockstep_into<W, L, R>(
    world: &mut W,
    learners: &mut [L],
    configs: &[SessionConfig],
    recorders: &mut [R],
    mut progress: impl FnMut(u64),
) -> Vec<Result<(), WorldError>>
where
    W: World + ?Sized,
    L: Learner,
    R: Recorder,
{
    assert_eq!(learners.len(), configs.len(), "one config per learner");
    assert_eq!(recorders.len(), configs.len(), "one recorder per session");
    let mut rngs: Vec<SessionRng> = configs
        .iter()
        .map(|c| SessionRng::seed_from_u64(c.seed))
        .collect();
    let mut status: Vec<Result<(), WorldError>> = configs.iter().map(|_| Ok(())).collect();
    let mut commands: Vec<Command> = configs
        .iter()
        .map(|_| world.command_space().first())
        .collect();
    let mut active: Vec<usize> = Vec::with_capacity(configs.len());
    // reused from trial to trial: no allocation per trial
    let mut batch: Vec<Command> = commands.clone();
    let mut outcomes = Vec::with_capacity(configs.len());
    let longest = configs.iter().map(|c| c.trials).max().unwrap_or(0);
    let mut since = 0u64;
    for t in 0..longest {
        if t % 256 == 0 && since > 0 {
            progress(since);
            since = 0;
        }
        active.clear();
        for (i, c) in configs.iter().enumerate() {
            if t < c.trials && status[i].is_ok() {
                learners[i].propose(&mut rngs[i], &mut commands[i]);
                batch[active.len()].symbols.clone_from(&commands[i].symbols);
                active.push(i);
            }
        }
        if active.is_empty() {
            break;
        }
        outcomes.clear();
        world.execute_batch(&batch[..active.len()], &mut outcomes);
        for (&i, result) in active.iter().zip(outcomes.drain(..)) {
            let mut outcome = match result {
                Ok(o) => o,
                Err(e) => {
                    status[i] = Err(e);
                    continue;
                }
            };
            if !configs[i].use_reward {
                outcome.reward = 0.0;
            }
            learners[i].learn(&commands[i], &outcome);
            recorders[i].record(&commands[i], &outcome);
        }
        since += active.len() as u64;
    }
    progress(since);
    status
}

/// Runs sessions that share one world: a session alone by
/// [`run_session_into`], several in lockstep by [`run_lockstep_into`] (the
/// same records either way). `progress(trials)` is called with the trials
/// done since its last call, summed over the sessions. Returns each
/// session's status.
pub fn run_group<W, L, R>(
    world: &mut W,
    learners: &mut [L],
    configs: &[SessionConfig],
    recorders: &mut [R],
    mut progress: impl FnMut(u64),
) -> Vec<Result<(), WorldError>>
where
    W: World + ?Sized,
    L: Learner,
    R: Recorder,
{
    match (learners, recorders, configs) {
        ([learner], [recorder], [config]) => {
            let mut done = 0usize;
            vec![run_session_into(world, learner, config, recorder, |t| {
                progress(t.saturating_sub(done) as u64);
                done = done.max(t);
            })]
        }
        (learners, recorders, configs) => {
            run_lockstep_into(world, learners, configs, recorders, progress)
        }
    }
}

/// Runs sessions of one scene the way `exec` plans them, on every core of
/// the current rayon pool: session `i` is `learners[i]` with `configs[i]`,
/// its trials handed to `recorders[i]`. The sessions are cut into
/// [`Executor::session_groups`] (alone on a table, else in lockstep
/// groups that step together on one world of [`Executor::world`]), and
/// the groups run in parallel. The records are those of running each
/// session alone with [`run_session_into`], whatever the threads.
///
/// `progress(trials)` is called from the workers with the trials done
/// since the group's last call. Returns each session's status, in order:
/// a session whose command fails stops there with the error (its recorder
/// keeps the trials before it), the others go on. Call
/// [`Executor::finish`] afterwards to keep a memo's outcomes.
///
/// ```
/// use e3d::world::{ExecOptions, Executor, Workload};
/// use e3d::{run_session, run_sessions, LearnerKind, Params, Scene, SessionConfig,
///           SessionRecord, Target};
/// let scene = Scene::builtin("puck_rooms").unwrap();
/// let make = || LearnerKind::E3d
///     .make(&Params::TASK1, &scene.command_space(), scene.num_effects(), &Target::Uniform)
///     .unwrap();
/// let configs: Vec<SessionConfig> = (0..4)
///     .map(|seed| SessionConfig { trials: 100, seed, use_reward: true })
///     .collect();
/// let work = Workload { trials: 400, sessions: 4, threads: 2 };
/// let exec = Executor::new(&scene, &work, &ExecOptions::default()).unwrap();
/// let mut learners: Vec<_> = configs.iter().map(|_| make()).collect();
/// let mut records: Vec<SessionRecord> =
///     configs.iter().map(|c| SessionRecord::new(&*exec.world(1), c.trials)).collect();
/// let status = run_sessions(&exec, &mut learners, &configs, &mut records, &|_| {});
/// assert!(status.iter().all(Result::is_ok));
/// // the same as each session alone on a world of its own
/// let alone = run_session(&mut scene.build(), &mut make(), &configs[2]).unwrap();
/// assert_eq!(records[2], alone);
/// ```
pub fn run_sessions<L, R>(
    exec: &Executor<'_>,
    learners: &mut [L],
    configs: &[SessionConfig],
    recorders: &mut [R],
    progress: &(dyn Fn(u64) + Sync),
) -> Vec<Result<(), WorldError>>
where
    L: Learner + Send,
    R: Recorder + Send,
{
    run_sessions_until(exec, learners, configs, recorders, progress, &|| false)
}

/// [`run_sessions`] that can be stopped: once `stop()` returns `true`
/// (asked before every execution), the sessions still running end with
/// [`WorldError::Other`]`("stopped")`. A Ctrl-C, a cancelled call.
pub fn run_sessions_until<L, R>(
    exec: &Executor<'_>,
    learners: &mut [L],
    configs: &[SessionConfig],
    recorders: &mut [R],
    progress: &(dyn Fn(u64) + Sync),
    stop: &(dyn Fn() -> bool + Sync),
) -> Vec<Result<(), WorldError>>
where
    L: Learner + Send,
    R: Recorder + Send,
{
    use rayon::prelude::*;
    assert_eq!(learners.len(), configs.len(), "one config per learner");
    assert_eq!(recorders.len(), configs.len(), "one recorder per session");
    // the groups, cut off the slices in order
    let mut parts = Vec::new();
    let (mut l, mut r, mut c) = (learners, recorders, configs);
    for g in exec.session_groups(c.len()) {
        let (l0, l1) = l.split_at_mut(g.len());
        let (r0, r1) = r.split_at_mut(g.len());
        let (c0, c1) = c.split_at(g.len());
        parts.push((l0, r0, c0));
        (l, r, c) = (l1, r1, c1);
    }
    parts
        .into_par_iter()
        .map(|(l, r, c)| {
            let mut world = exec.world(l.len());
            let mut world = Stoppable {
                world: &mut *world,
                stop,
            };
            run_group(&mut world, l, c, r, progress)
        })
        .collect::<Vec<_>>()
        .into_iter()
        .flatten()
        .collect()
}

/// A world whose executions fail once `stop()` says so.
struct Stoppable<'a, W: ?Sized> {
    world: &'a mut W,
    stop: &'a (dyn Fn() -> bool + Sync),
}

/// The error of an execution asked after `stop()`.
fn stopped() -> WorldError {
    WorldError::Other("stopped".into())
}

impl<W: World + ?Sized> World for Stoppable<'_, W> {
    fn command_space(&self) -> &CommandSpace {
        self.world.command_space()
    }
    fn num_effects(&self) -> usize {
        self.world.num_effects()
    }
    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        if (self.stop)() {
            return Err(stopped());
        }
        self.world.execute(command)
    }
    fn is_deterministic(&self) -> bool {
        self.world.is_deterministic()
    }
    fn execute_batch(&mut self, commands: &[Command], out: &mut Vec<Result<Outcome, WorldError>>) {
        if (self.stop)() {
            out.extend(commands.iter().map(|_| Err(stopped())));
        } else {
            self.world.execute_batch(commands, out)
        }
    }
    fn mirror_of(&self, command: &Command) -> Option<Command> {
        self.world.mirror_of(command)
    }
    fn mirror_outcome(&self, outcome: Outcome) -> Outcome {
        self.world.mirror_outcome(outcome)
    }
}

/// The numbers that summarise a session.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Metrics {
    /// Entropy of the terminal effects over all trials, divided by
    /// `log(num_effects)` (1 = perfectly uniform over every effect).
    pub normalized_entropy: f64,
    /// The same over the last 1000 trials (all trials if fewer).
    pub normalized_entropy_last_1000: f64,
    /// `KL(empirical || target)` of the terminal effects over all trials, in nats.
    pub kl_to_target: f64,
    /// The number of distinct effects reached.
    pub distinct_effects: usize,
    /// The sum of the rewards over all trials.
    pub cumulative_reward: f64,
    /// The 1-based trial of the first positive reward, if any.
    pub first_reward_trial: Option<usize>,
    /// The number of trials.
    pub trials: usize,
    /// The number of effects some command reaches, when it is known (an
    /// [`OutcomeTable`] knows it: [`OutcomeTable::reachable_effects`]) and
    /// given to [`SessionRecord::metrics_over_reachable`] or
    /// [`RunningMetrics::metrics_over_reachable`]; `None` otherwise.
    pub reachable_effects: Option<usize>,
    /// The entropy of the terminal effects over all trials divided by
    /// `log(reachable_effects)`: 1 = uniform over what can be reached
    /// (see [`crate::effect::normalized_entropy_over`]).
    /// `None` when the reachable effects are not known.
    pub normalized_entropy_reachable: Option<f64>,
    /// The cells the coverage measures count against: the reachable
    /// effects when they are known ([`reachable_effects`](Self::reachable_effects)),
    /// else every effect.
    pub coverage_cells: usize,
    /// The fraction of [`coverage_cells`](Self::coverage_cells) reached by
    /// the last trial: `distinct_effects / coverage_cells`.
    pub coverage: f64,
    /// The 1-based trial by which 50% of the coverage cells were reached
    /// (`ceil(0.5 coverage_cells)` distinct effects), if they were.
    pub trials_to_50_percent: Option<usize>,
    /// The same for 90% (`ceil(0.9 coverage_cells)` distinct effects).
    pub trials_to_90_percent: Option<usize>,
    /// The 1-based trial at which each distinct effect was first reached,
    /// in order: the fraction of the coverage cells found by trial `t` is
    /// the number of these `<= t` over [`coverage_cells`](Self::coverage_cells)
    /// ([`coverage_at`](Self::coverage_at)).
    pub discovery_trials: Vec<usize>,
}

impl Metrics {
    /// The metrics from the effect counts over all trials and over the last
    /// 1000, the sum of the rewards, the first rewarded trial and the
    /// number of trials.
    #[allow(clippy::too_many_arguments)]
    fn from_counts(
        all: &[f64],
        last: &[f64],
        cumulative_reward: f64,
        first_reward_trial: Option<usize>,
        discoveries: &[usize],
        trials: usize,
        target: &Target,
        reachable: Option<usize>,
    ) -> Metrics {
        let num_effects = all.len();
        let norm = (num_effects as f64).ln();
        let norm = if norm > 0.0 { norm } else { 1.0 };
        let log_target = target
            .log_probs(num_effects)
            .unwrap_or_else(|_| vec![-norm; num_effects]);
        Metrics {
            normalized_entropy: entropy(all) / norm,
            normalized_entropy_last_1000: entropy(last) / norm,
            kl_to_target: kl_divergence(all, &log_target),
            distinct_effects: all.iter().filter(|&&c| c > 0.0).count(),
            cumulative_reward,
            first_reward_trial,
            trials,
            reachable_effects: reachable,
            normalized_entropy_reachable: reachable.map(|k| normalized_entropy_over(all, k)),
            coverage_cells: coverage_cells(reachable, num_effects),
            coverage: all.iter().filter(|&&c| c > 0.0).count() as f64
                / coverage_cells(reachable, num_effects) as f64,
            trials_to_50_percent: trials_to_fraction(
                discoveries,
                coverage_cells(reachable, num_effects),
                0.5,
            ),
            trials_to_90_percent: trials_to_fraction(
                discoveries,
                coverage_cells(reachable, num_effects),
                0.9,
            ),
            discovery_trials: discoveries.to_vec(),
        }
    }

    /// The fraction of the coverage cells reached by trial `t` (1-based;
    /// 0 before the first trial).
    ///
    /// ```
    /// use e3d::{Command, Outcome, Recorder, RunningMetrics, Target};
    /// let mut m = RunningMetrics::new(4);
    /// for e in [0, 0, 1, 0, 3] {
    ///     m.record(&Command::new(vec![0]), &Outcome { effect: e, reward: 0.0, point: [0.0; 2] });
    /// }
    /// let m = m.metrics(&Target::Uniform);
    /// assert_eq!(m.discovery_trials, [1, 3, 5]);
    /// assert_eq!((m.coverage_at(2), m.coverage_at(3), m.coverage), (0.25, 0.5, 0.75));
    /// assert_eq!((m.trials_to_50_percent, m.trials_to_90_percent), (Some(3), None));
    /// ```
    pub fn coverage_at(&self, t: usize) -> f64 {
        let found = self.discovery_trials.partition_point(|&d| d <= t);
        found as f64 / self.coverage_cells.max(1) as f64
    }
}

/// The cells coverage counts against: `reachable` if known, else all.
fn coverage_cells(reachable: Option<usize>, num_effects: usize) -> usize {
    reachable.unwrap_or(num_effects).max(1)
}

/// The trial by which `ceil(fraction x cells)` distinct effects were
/// reached, given the trials of the discoveries (in order); `None` if
/// they were not.
///
/// ```
/// use e3d::session::trials_to_fraction;
/// assert_eq!(trials_to_fraction(&[1, 4, 9, 30], 4, 0.5), Some(4));
/// assert_eq!(trials_to_fraction(&[1, 4, 9, 30], 4, 0.9), Some(30));
/// assert_eq!(trials_to_fraction(&[1, 4, 9], 4, 0.9), None);
/// // ceil: 50% of 5 cells is 3 of them
/// assert_eq!(trials_to_fraction(&[1, 4, 9], 5, 0.5), Some(9));
/// ```
pub fn trials_to_fraction(discoveries: &[usize], cells: usize, fraction: f64) -> Option<usize> {
    let need = ((fraction * cells as f64) - 1e-9).ceil().max(1.0) as usize;
    discoveries.get(need - 1).copied()
}

/// The 1-based trial at which each distinct effect of `effects` was first
/// reached, in order.
pub fn discovery_trials(effects: &[usize], num_effects: usize) -> Vec<usize> {
    let mut seen = vec![false; num_effects];
    let mut out = Vec::new();
    for (t, &e) in effects.iter().enumerate() {
        if !std::mem::replace(&mut seen[e], true) {
            out.push(t + 1);
        }
    }
    out
}

impl SessionRecord {
    /// An empty record for `trials` trials on `world`.
    pub fn new<W: World + ?Sized>(world: &W, trials: usize) -> Self {
        let n = world.command_space().num_slots();
        SessionRecord {
            num_slots: n,
            num_effects: world.num_effects(),
            commands: Vec::with_capacity(trials.saturating_mul(n)),
            effects: Vec::with_capacity(trials),
            rewards: Vec::with_capacity(trials),
            points: Vec::with_capacity(trials),
        }
    }

    /// The number of trials.
    pub fn trials(&self) -> usize {
        self.effects.len()
    }

    /// The command of trial `t` (0-based).
    pub fn command(&self, t: usize) -> Command {
        Command::new(self.commands[t * self.num_slots..(t + 1) * self.num_slots].to_vec())
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
        self.metrics_given(target, None)
    }

    /// The same, with the entropy over the `reachable_effects` effects
    /// some command reaches as well ([`Metrics::normalized_entropy_reachable`]).
    ///
    /// ```
    /// use e3d::{run_session, LearnerKind, OutcomeTable, Params, Scene, SessionConfig, Target};
    /// let scene = Scene::builtin("two_rooms").unwrap();
    /// let table = OutcomeTable::build(&mut scene.build()).unwrap();
    /// let mut l = LearnerKind::E3d
    ///     .make(&Params::TASK1, &scene.command_space(), scene.num_effects(), &Target::Uniform)
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
        self.metrics_given(target, Some(reachable_effects))
    }

    fn metrics_given(&self, target: &Target, reachable: Option<usize>) -> Metrics {
        let t = self.trials();
        let all = self.effect_counts(0..t);
        let last = self.effect_counts(t.saturating_sub(LAST)..t);
        Metrics::from_counts(
            &all,
            &last,
            self.rewards.iter().fold(0.0, |a, r| a + r),
            self.rewards.iter().position(|&r| r > 0.0).map(|i| i + 1),
            &discovery_trials(&self.effects, self.num_effects),
            t,
            target,
            reachable,
        )
    }

    /// Writes `trial,command,effect,reward` CSV, one row per trial (trial
    /// 1-based, the command as its symbols).
    pub fn write_trials_csv(&self, space: &CommandSpace, mut out: impl Write) -> io::Result<()> {
        writeln!(out, "trial,command,effect,reward")?;
        let mut c = space.first();
        for t in 0..self.trials() {
            c.symbols
                .copy_from_slice(&self.commands[t * self.num_slots..(t + 1) * self.num_slots]);
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

/// The exact distribution of effects under `learner`'s current policy:
/// the sum, over every command, of its probability times the indicator of
/// its effect. `None` if the learner's policy is not a product of per-slot
/// distributions. The cost is `table.len() x num_slots`.
pub fn policy_effect_distribution(table: &OutcomeTable, learner: &dyn Learner) -> Option<Vec<f64>> {
    let space = crate::world::World::command_space(&table);
    let n = space.num_slots();
    let slot_probs: Vec<Vec<f64>> = (0..n)
        .map(|s| learner.slot_policy(s))
        .collect::<Option<_>>()?;
    let mut dist = vec![0.0; crate::world::World::num_effects(&table)];
    let mut c = space.first();
    for (i, o) in table.outcomes().enumerate() {
        space.write_command_at(i as u64, &mut c);
        let p: f64 = c
            .symbols
            .iter()
            .zip(&slot_probs)
            .map(|(&s, ps)| ps[s as usize])
            .product();
        dist[o.effect] += p;
    }
    Some(dist)
}

/// What a session of continuous commands recorded, trial by trial (the
/// twin of [`SessionRecord`], with values in place of symbols).
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
    /// [`SessionRecord::metrics`]).
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
/// let mut world = scene.physics_world().unwrap();
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
    let mut rec = ValueSessionRecord {
        num_slots: n,
        num_effects: world.num_effects(),
        values: Vec::with_capacity(trials.saturating_mul(n)),
        effects: Vec::with_capacity(trials),
        rewards: Vec::with_capacity(trials),
        points: Vec::with_capacity(trials),
        final_policy: Vec::new(),
    };
    let mut rng = SessionRng::seed_from_u64(config.seed);
    let mut values = Vec::with_capacity(n);
    for t in 0..trials {
        learner.propose(&mut rng, &mut values);
        let mut outcome = world.execute_values(&values)?;
        if !config.use_reward {
            outcome.reward = 0.0;
        }
        learner.learn(&values, &outcome);
        rec.values.extend_from_slice(&values);
        rec.effects.push(outcome.effect);
        rec.rewards.push(outcome.reward);
        rec.points.push(outcome.point);
        if (t + 1) % 64 == 0 {
            progress(t + 1);
        }
    }
    progress(trials);
    rec.final_policy = (0..n).map(|s| learner.slot_gaussian(s)).collect();
    Ok(rec)
}

/// Runs one session of continuous commands per config, in parallel on
/// every core (rayon), each on its own world from `make_world` and its own
/// learner from `make_learner`: the records, in the order of `configs`,
/// are those of [`run_value_session`] alone, whatever the number of
/// threads. `progress(k)` is called with each batch of `k` trials done.
pub fn run_value_sessions<W, L>(
    make_world: impl Fn() -> W + Sync,
    make_learner: impl Fn() -> L + Sync,
    configs: &[SessionConfig],
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Vec<ValueSessionRecord>, WorldError>
where
    W: ContinuousWorld,
    L: ContinuousLearner,
{
    use rayon::prelude::*;
    configs
        .par_iter()
        .map(|cfg| {
            let mut world = make_world();
            let mut learner = make_learner();
            let mut done = 0;
            run_value_session(&mut world, &mut learner, cfg, |t| {
                progress((t - done) as u64);
                done = t;
            })
        })
        .collect()
}
