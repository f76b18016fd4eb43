//! The session engine: the one trial loop of every session, whatever its
//! kind of command, alone or in lockstep, and the groups of an
//! [`Executor`] run in parallel (see ARCHITECTURE.md, "One trial").

pub use crate::world::{Control, Observer};

use super::{Recorder, SessionConfig};
use crate::command::Command;
use crate::episode::{run_episodes_into, EpisodeConfig, EpisodeRecorder};
use crate::learner::{draw_weighted, ContextualLearner, ContinuousLearner, Learner};
use crate::rng::SessionRng;
use crate::scene::physics::DrawKey;
use crate::world::{ContinuousWorld, Episodic, Executor, Outcome, OutcomeTable, World, WorldError};
use rand::SeedableRng;
use std::ops::{DerefMut, Range};

/// A learner of commands of kind `C`: every [`Learner`] of [`Command`],
/// every [`ContinuousLearner`] of `Vec<f64>`. Implement those instead.
pub trait Learns<C> {
    /// Draws the next command into `command`.
    fn propose_next(&mut self, rng: &mut SessionRng, command: &mut C);
    /// Learns from the outcome of `command`.
    fn learn_from(&mut self, command: &C, outcome: &Outcome);
    /// `n` commands drawn from the current policy with `rng`, each of the
    /// shape of `blank` (the policy's likely commands: see
    /// [`reproducibility`](super::reproducibility)); `None` if the policy
    /// cannot be drawn from without changing the learner (a policy that is
    /// not a product of per-slot distributions, a learner of values that
    /// keeps no ranges).
    fn likely(&self, blank: &C, n: usize, rng: &mut SessionRng) -> Option<Vec<C>>;
}

impl<L: Learner + ?Sized> Learns<Command> for L {
    fn propose_next(&mut self, rng: &mut SessionRng, command: &mut Command) {
        self.propose(rng, command)
    }
    fn learn_from(&mut self, command: &Command, outcome: &Outcome) {
        self.learn(command, outcome)
    }
    fn likely(&self, blank: &Command, n: usize, rng: &mut SessionRng) -> Option<Vec<Command>> {
        let slots: Vec<Vec<f64>> = (0..blank.len())
            .map(|s| self.slot_policy(s))
            .collect::<Option<_>>()?;
        let draw = |rng: &mut SessionRng| {
            let each = slots
                .iter()
                .map(|p| draw_weighted(p.iter().copied(), rng) as u8);
            Command::new(each.collect())
        };
        Some((0..n).map(|_| draw(rng)).collect())
    }
}

impl<L: ContinuousLearner + ?Sized> Learns<Vec<f64>> for L {
    fn propose_next(&mut self, rng: &mut SessionRng, values: &mut Vec<f64>) {
        self.propose(rng, values)
    }
    fn learn_from(&mut self, values: &Vec<f64>, outcome: &Outcome) {
        self.learn(values, outcome)
    }
    /// Each slot's value drawn from its policy's Gaussian
    /// ([`ContinuousLearner::slot_gaussian`]: the mean plus the standard
    /// deviation times a standard normal draw, Box-Muller, two uniform
    /// numbers) and clamped to the slot's range; `None` for a learner that
    /// keeps no ranges ([`ContinuousLearner::value_space`]).
    fn likely(&self, _: &Vec<f64>, n: usize, rng: &mut SessionRng) -> Option<Vec<Vec<f64>>> {
        use rand::RngExt;
        let space = self.value_space()?;
        let mut draw = |slot: usize| {
            let (mean, sd) = self.slot_gaussian(slot);
            let u: f64 = 1.0 - rng.random::<f64>(); // in (0, 1]
            let z = (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * rng.random::<f64>()).cos();
            let (lo, hi) = space.range(slot);
            (mean + sd * z).clamp(lo, hi)
        };
        let slots = space.num_slots();
        Some(
            (0..n)
                .map(|_| (0..slots).map(&mut draw).collect())
                .collect(),
        )
    }
}

/// A world that executes commands of kind `C`: every [`World`] of
/// [`Command`], every [`ContinuousWorld`] of `Vec<f64>`. Implement those
/// instead.
pub trait Executes<C> {
    /// A command buffer for a learner to propose into.
    fn blank(&self) -> C;
    /// The number of effects.
    fn effects(&self) -> usize;
    /// Executes one command.
    fn execute_one(&mut self, command: &C) -> Result<Outcome, WorldError>;
    /// Executes several commands, appending their outcomes in order.
    fn execute_all(&mut self, commands: &[C], out: &mut Vec<Result<Outcome, WorldError>>);
    /// Copies `from` into `to` without allocating.
    fn copy(&self, from: &C, to: &mut C);
    /// The keys of the draws of the next commands (see
    /// [`World::set_draw_keys`]).
    fn draw_keys(&mut self, keys: &[DrawKey]);
    /// Whether a command always gives the same outcome (no `noise`):
    /// [`World::is_deterministic`], [`ContinuousWorld::is_deterministic`].
    fn deterministic(&self) -> bool;
}

impl<W: World + ?Sized> Executes<Command> for W {
    fn blank(&self) -> Command {
        self.command_space().first()
    }
    fn effects(&self) -> usize {
        self.num_effects()
    }
    fn execute_one(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        self.execute(command)
    }
    fn execute_all(&mut self, commands: &[Command], out: &mut Vec<Result<Outcome, WorldError>>) {
        self.execute_batch(commands, out)
    }
    fn copy(&self, from: &Command, to: &mut Command) {
        to.symbols.clone_from(&from.symbols)
    }
    fn draw_keys(&mut self, keys: &[DrawKey]) {
        self.set_draw_keys(keys)
    }
    fn deterministic(&self) -> bool {
        self.is_deterministic()
    }
}

impl<W: ContinuousWorld + ?Sized> Executes<Vec<f64>> for W {
    fn blank(&self) -> Vec<f64> {
        Vec::with_capacity(self.value_space().num_slots())
    }
    fn effects(&self) -> usize {
        ContinuousWorld::num_effects(self)
    }
    fn execute_one(&mut self, values: &Vec<f64>) -> Result<Outcome, WorldError> {
        self.execute_values(values)
    }
    fn execute_all(&mut self, commands: &[Vec<f64>], out: &mut Vec<Result<Outcome, WorldError>>) {
        self.execute_values_batch(commands, out)
    }
    fn copy(&self, from: &Vec<f64>, to: &mut Vec<f64>) {
        to.clone_from(from)
    }
    fn draw_keys(&mut self, keys: &[DrawKey]) {
        self.set_draw_keys(keys)
    }
    fn deterministic(&self) -> bool {
        self.is_deterministic()
    }
}

/// How often (in lockstep trials) the engine reports progress.
const PROGRESS_EVERY: usize = 64;

/// Runs sessions that share one world: session `i` is `learners[i]` with
/// `configs[i]`, its trials handed to `recorders[i]`. Each trial, every
/// session still running proposes; one session executes alone, several
/// in one batch; then each learns from its own outcome (the reward zeroed
/// unless its config uses rewards). Each session draws from its own
/// generator, so its record is the one it makes alone; a noisy world
/// draws each command's noise from [`DrawKey::trial`]`(seed, trial)`, alike. A session whose
/// command fails stops there (its recorder keeps the trials before); the
/// others go on. Returns each session's status.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::session::{run_group, Control};
/// use e3d::{run_session, LearnerKind, Params, Scene, SessionConfig, SessionRecord, Target};
/// let scene = Scene::builtin("puck_rooms").unwrap();
/// let make = || LearnerSetup::new(LearnerKind::E3d)
///     .symbols(&scene.command_space(), scene.num_effects())
///     .unwrap();
/// let configs: Vec<SessionConfig> =
///     (0..3).map(|seed| SessionConfig { trials: 50, seed, use_reward: true }).collect();
/// let mut learners: Vec<_> = configs.iter().map(|_| make()).collect();
/// let mut world = scene.build();
/// let mut records: Vec<SessionRecord> =
///     configs.iter().map(|c| SessionRecord::new(&*world, c.trials)).collect();
/// let status = run_group(&mut world, &mut learners, &configs, &mut records, &Control::default());
/// assert!(status.iter().all(Result::is_ok));
/// assert_eq!(records[1], run_session(&mut scene.build(), &mut make(), &configs[1]).unwrap());
/// ```
pub fn run_group<C, W, L, R>(
    world: &mut W,
    learners: &mut [L],
    configs: &[SessionConfig],
    recorders: &mut [R],
    control: &(impl Observer + ?Sized),
) -> Vec<Result<(), WorldError>>
where
    C: Clone,
    W: Executes<C> + ?Sized,
    L: Learns<C>,
    R: Recorder<C>,
{
    assert_eq!(learners.len(), configs.len(), "one config per learner");
    assert_eq!(recorders.len(), configs.len(), "one recorder per session");
    let mut rngs: Vec<SessionRng> = configs
        .iter()
        .map(|c| SessionRng::seed_from_u64(c.seed))
        .collect();
    let mut status: Vec<Result<(), WorldError>> = configs.iter().map(|_| Ok(())).collect();
    let mut commands: Vec<C> = configs.iter().map(|_| world.blank()).collect();
    // reused from trial to trial: no allocation per trial
    let mut batch: Vec<C> = commands.clone();
    let mut active: Vec<usize> = Vec::with_capacity(configs.len());
    let mut outcomes = Vec::with_capacity(configs.len());
    let mut keys: Vec<DrawKey> = Vec::with_capacity(configs.len());
    let alone = configs.len() == 1;
    let longest = configs.iter().map(|c| c.trials).max().unwrap_or(0);
    let mut since = 0u64;
    for t in 0..longest {
        if t % PROGRESS_EVERY == 0 && since > 0 {
            control.progress(since);
            since = 0;
        }
        active.clear();
        for (i, c) in configs.iter().enumerate() {
            if t < c.trials && status[i].is_ok() {
                learners[i].propose_next(&mut rngs[i], &mut commands[i]);
                active.push(i);
            }
        }
        if active.is_empty() {
            break;
        }
        outcomes.clear();
        // a noisy world's draws: keyed by each session's seed and the trial
        keys.clear();
        keys.extend((active.iter()).map(|&i| DrawKey::trial(configs[i].seed, t as u64)));
        world.draw_keys(&keys);
        if control.stopped() {
            outcomes.extend(active.iter().map(|_| Err(WorldError::Stopped)));
        } else if alone {
            outcomes.push(world.execute_one(&commands[0]));
        } else {
            for (j, &i) in active.iter().enumerate() {
                world.copy(&commands[i], &mut batch[j]);
            }
            world.execute_all(&batch[..active.len()], &mut outcomes);
        }
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
            learners[i].learn_from(&commands[i], &outcome);
            recorders[i].record(&commands[i], &outcome);
        }
        since += active.len() as u64;
    }
    control.progress(since);
    status
}

/// Where sessions of kind `C` run: the groups that step together, and a
/// world for each (an [`Executor`], of both kinds).
pub trait Worlds<C>: Sync {
    /// The groups `sessions` sessions are cut into, as ranges in order.
    fn session_groups(&self, sessions: usize) -> Vec<Range<usize>>;
    /// A fresh world for `width` sessions stepping together; its outcomes
    /// do not depend on the width.
    fn world_for(&self, width: usize) -> Result<Box<dyn Executes<C> + Send + '_>, WorldError>;
}

impl Worlds<Command> for Executor<'_> {
    fn session_groups(&self, sessions: usize) -> Vec<Range<usize>> {
        Executor::session_groups(self, sessions)
    }
    fn world_for(
        &self,
        width: usize,
    ) -> Result<Box<dyn Executes<Command> + Send + '_>, WorldError> {
        Ok(Box::new(self.world(width)))
    }
}

/// An outcome table: every session alone on it, all in parallel.
impl Worlds<Command> for OutcomeTable {
    fn session_groups(&self, sessions: usize) -> Vec<Range<usize>> {
        (0..sessions).map(|i| i..i + 1).collect()
    }
    fn world_for(
        &self,
        _width: usize,
    ) -> Result<Box<dyn Executes<Command> + Send + '_>, WorldError> {
        Ok(Box::new(self))
    }
}

impl Worlds<Vec<f64>> for Executor<'_> {
    fn session_groups(&self, sessions: usize) -> Vec<Range<usize>> {
        Executor::session_groups(self, sessions)
    }
    fn world_for(
        &self,
        width: usize,
    ) -> Result<Box<dyn Executes<Vec<f64>> + Send + '_>, WorldError> {
        let scene = self.continuous().ok_or_else(|| {
            WorldError::Other(
                "sessions of continuous commands need an executor of a continuous scene (Executor::for_values)"
                    .into(),
            )
        })?;
        Ok(Box::new(scene.world(self.copies_for(width))))
    }
}

/// Runs sessions of one scene as `worlds` plans them: cut into
/// [`Worlds::session_groups`], each group a [`run_group`], the groups in
/// parallel on the current rayon pool; the records are those of each
/// session alone. Returns each session's status, in order. Call
/// [`Executor::finish`] afterwards to keep a memo's outcomes.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::world::{ExecOptions, Executor, Workload};
/// use e3d::session::{run_sessions, Control};
/// use e3d::{run_session, LearnerKind, Params, Scene, SessionConfig, SessionRecord, Target};
/// let scene = Scene::builtin("puck_rooms").unwrap();
/// let make = || LearnerSetup::new(LearnerKind::E3d)
///     .symbols(&scene.command_space(), scene.num_effects())
///     .unwrap();
/// let configs: Vec<SessionConfig> = (0..4)
///     .map(|seed| SessionConfig { trials: 100, seed, use_reward: true })
///     .collect();
/// let work = Workload { trials: 400, sessions: 4, threads: 2 };
/// let exec = Executor::new(&scene, &work, &ExecOptions::default()).unwrap();
/// let mut learners: Vec<_> = configs.iter().map(|_| make()).collect();
/// let mut records: Vec<SessionRecord> =
///     configs.iter().map(|c| SessionRecord::new(&*exec.world(1), c.trials)).collect();
/// let status = run_sessions(&exec, &mut learners, &configs, &mut records, &Control::default());
/// assert!(status.iter().all(Result::is_ok));
/// // the same as each session alone on a world of its own
/// let alone = run_session(&mut scene.build(), &mut make(), &configs[2]).unwrap();
/// assert_eq!(records[2], alone);
/// ```
pub fn run_sessions<C, L, R>(
    worlds: &(impl Worlds<C> + ?Sized),
    learners: &mut [L],
    configs: &[SessionConfig],
    recorders: &mut [R],
    control: &(impl Observer + Sync + ?Sized),
) -> Vec<Result<(), WorldError>>
where
    C: Clone,
    L: Learns<C> + Send,
    R: Recorder<C> + Send,
{
    assert_eq!(learners.len(), configs.len(), "one config per learner");
    assert_eq!(recorders.len(), configs.len(), "one recorder per session");
    // the groups, cut off the slices in order
    let mut parts = Vec::new();
    let (mut l, mut r, mut c) = (learners, recorders, configs);
    for g in worlds.session_groups(c.len()) {
        let (l0, l1) = l.split_at_mut(g.len());
        let (r0, r1) = r.split_at_mut(g.len());
        let (c0, c1) = c.split_at(g.len());
        parts.push((g.len(), (l0, r0, c0)));
        (l, r, c) = (l1, r1, c1);
    }
    run_planned(worlds, parts, |(l, r, c), world| match world {
        Ok(world) => run_group(world, l, c, r, control),
        Err(e) => c.iter().map(|_| Err(e.clone())).collect(),
    })
    .into_iter()
    .flatten()
    .collect()
}

/// Runs `parts` (each a group's width and its sessions) in parallel on the
/// current rayon pool: `run(part, world)` on a fresh world of its width,
/// or the error that made none; the answers in order. A sweep makes its
/// learners as each group starts; [`run_sessions`] has them already.
pub fn run_planned<C, P, T>(
    worlds: &(impl Worlds<C> + ?Sized),
    parts: Vec<(usize, P)>,
    run: impl Fn(P, Result<&mut dyn Executes<C>, WorldError>) -> T + Sync,
) -> Vec<T>
where
    P: Send,
    T: Send,
{
    use rayon::prelude::*;
    parts
        .into_par_iter()
        .map(|(width, part)| match worlds.world_for(width) {
            Ok(mut world) => run(part, Ok(&mut *world)),
            Err(e) => run(part, Err(e)),
        })
        .collect()
}

/// Runs sessions of episodes ([`run_episodes_into`]) in parallel on the
/// current rayon pool: session `i` runs `configs[i]` on the world and
/// learner `make(i)` returns, into `recorders[i]`; its record is the one
/// it makes alone. `control` is told of the episodes done over all
/// sessions; its stop ends each with [`WorldError::Stopped`]. Returns
/// each session's status, in order (an error of `make` is that session's).
///
/// ```
/// use e3d::episode::{run_episodes, EpisodeConfig, EpisodeRecord, Observe};
/// use e3d::session::{run_episode_sessions, Control};
/// use e3d::learner::LearnerSetup;
/// use e3d::{LearnerKind, Params, Scene};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let configs: Vec<EpisodeConfig> = (0..3)
///     .map(|seed| EpisodeConfig { episodes: 100, commands: 2, seed, use_reward: true,
///                                 observe: Observe::State })
///     .collect();
/// let make = |_| -> Result<_, Box<dyn std::error::Error + Send + Sync>> {
///     let learner = LearnerSetup::new(LearnerKind::E3d)
///         .params(Params::TASK2)
///         .closed_loop(true)
///         .contexts(&scene.command_space(), scene.num_effects(), scene.num_effects())?;
///     Ok((scene.build(), learner))
/// };
/// let mut records = vec![EpisodeRecord::default(); 3];
/// let status = run_episode_sessions(&configs, make, &mut records, &Control::default());
/// assert!(status.iter().all(Result::is_ok));
/// let (mut world, mut learner) = make(1).unwrap();
/// let alone = run_episodes(&mut world, &mut learner, &configs[1], &Control::default());
/// assert_eq!(records[1], alone.unwrap());
/// ```
pub fn run_episode_sessions<W, L, R, E>(
    configs: &[EpisodeConfig],
    make: impl Fn(usize) -> Result<(W, L), E> + Sync,
    recorders: &mut [R],
    control: &(impl Observer + Sync + ?Sized),
) -> Vec<Result<(), E>>
where
    W: DerefMut<Target: Episodic>,
    L: DerefMut<Target: ContextualLearner>,
    R: EpisodeRecorder + Send,
    E: From<WorldError> + Send,
{
    use rayon::prelude::*;
    assert_eq!(recorders.len(), configs.len(), "one recorder per session");
    configs
        .par_iter()
        .zip(recorders)
        .enumerate()
        .map(|(i, (config, recorder))| {
            let (mut world, mut learner) = make(i)?;
            Ok(run_episodes_into(
                &mut *world,
                &mut *learner,
                config,
                recorder,
                control,
            )?)
        })
        .collect()
}
