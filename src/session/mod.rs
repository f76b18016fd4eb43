//! Sessions: the trial loop, what it records, and the metrics of a run.
//!
//! One trial: the learner proposes a command, the world executes it open
//! loop, the learner learns from the outcome. [`run_session`] repeats it
//! and records, per trial, the command, the effect and the reward.

use crate::command::{Command, CommandSpace};
use crate::effect::Target;
use crate::learner::Learner;
use crate::world::{Executor, Outcome, World, WorldError};
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use std::io::{self, Write};

use crate::rng::SessionRng;

mod metrics;
mod values;

use metrics::LAST;
pub use metrics::{
    discovery_trials, policy_effect_distribution, trials_to_fraction, Metrics, RunningMetrics,
};
pub use values::{run_value_lockstep, run_value_session, run_value_sessions, ValueSessionRecord};

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
