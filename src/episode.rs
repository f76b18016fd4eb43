//! Episodes: start contexts and closed loops.
//!
//! An episode starts from a start context of the world (drawn with the
//! session's generator when the world has several) and executes `K`
//! commands one after another: the terminal state of command `k` is the
//! start of command `k + 1`, continued exactly, with no reset
//! ([`Episodic::execute_from`]). Before each command the learner reads its
//! context ([`Observe`]); there is no feedback within a command. With
//! `K = 1` an episode is one trial of an open-loop session started from a
//! context.

use crate::command::Command;
use crate::effect::normalized_entropy_over;
use crate::learner::ContextualLearner;
use crate::rng::SessionRng;
use crate::scene::physics::DrawKey;
use crate::world::{Episodic, Observer, Outcome, WorldError};

/// How often (in episodes) [`run_episodes`] reports progress and checks
/// for a stop.
const PROGRESS_EVERY: usize = 64;
use rand::{RngExt, SeedableRng};
use serde::{Deserialize, Serialize};

/// What the learner observes as its context before each command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Observe {
    /// The index of the episode's start context (the same for every
    /// command of the episode); a learner of [`Episodic::num_contexts`]
    /// contexts.
    StartContext,
    /// The bin of the current state ([`Episodic::bin_state`]: on a grid, the
    /// cell): a learner of [`World::num_effects`](crate::World::num_effects) contexts.
    State,
    /// Nothing: context 0 always, a learner of one context (the
    /// context-blind baseline).
    Blind,
}

impl Observe {
    /// What `e3d run` observes when not told: the current state with
    /// several commands per episode or a closed-loop learner, else the
    /// start context.
    pub fn default_for(commands: usize, closed_loop: bool) -> Observe {
        if commands > 1 || closed_loop {
            Observe::State
        } else {
            Observe::StartContext
        }
    }

    /// The context observed in an episode started in context `start`,
    /// `cell` giving the current state's bin (at the start, the start
    /// state's; after a command, its effect): called only when observing
    /// [`Observe::State`].
    pub(crate) fn context(
        self,
        start: usize,
        cell: impl FnOnce() -> Result<usize, WorldError>,
    ) -> Result<usize, WorldError> {
        match self {
            Observe::StartContext => Ok(start),
            Observe::State => cell(),
            Observe::Blind => Ok(0),
        }
    }
}

/// How to run a session of episodes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EpisodeConfig {
    /// The number of episodes.
    pub episodes: usize,
    /// The commands of an episode, `K >= 1`.
    pub commands: usize,
    /// The seed of the session's generator.
    pub seed: u64,
    /// Whether the learner sees the scene's reward (else 0 always).
    pub use_reward: bool,
    /// What the learner reads before each command.
    pub observe: Observe,
}

/// The most commands a session of episodes may execute in all (episodes
/// times commands per episode): 10^8, the cap on a session's trials
/// ([`MAX_TRIALS`](crate::sweep::MAX_TRIALS)); its record keeps every one.
pub const MAX_EPISODE_COMMANDS: usize = 100_000_000;

/// Refuses `episodes` episodes of `commands` commands when they make more
/// than [`MAX_EPISODE_COMMANDS`] commands in all (the message says so).
///
/// ```
/// use e3d::episode::check_size;
/// assert!(check_size(1_000_000, 64).is_ok());
/// assert!(check_size(100_000_000, 64).is_err());
/// ```
pub fn check_size(episodes: usize, commands: usize) -> Result<(), String> {
    match episodes.checked_mul(commands) {
        Some(n) if n <= MAX_EPISODE_COMMANDS => Ok(()),
        _ => Err(format!(
            "at most {MAX_EPISODE_COMMANDS} commands in all per session (episodes x commands), found {episodes} episodes of {commands} commands"
        )),
    }
}

impl EpisodeConfig {
    /// The number of contexts a learner needs for `world` under this
    /// configuration.
    pub fn num_contexts<W: Episodic + ?Sized>(&self, world: &W) -> usize {
        match self.observe {
            Observe::StartContext => world.num_contexts(),
            Observe::State => world.num_effects(),
            Observe::Blind => 1,
        }
    }
}

/// What keeps the episodes of a session as they run
/// ([`run_episodes_into`]): an [`EpisodeRecord`] keeps every command, an
/// [`EpisodeTally`] only the session's figures (in memory that does not
/// grow with the episodes), and a recorder of your own may stream them to
/// a file. A pair of recorders records into both.
pub trait EpisodeRecorder {
    /// Called once, before the first episode, with the session's
    /// configuration and the world's number of effects.
    fn begin(&mut self, config: &EpisodeConfig, num_effects: usize) {
        let _ = (config, num_effects);
    }
    /// A new episode starts, from start context `start`.
    fn start(&mut self, start: usize);
    /// The episode's next command, proposed in `context`, had `outcome`
    /// (its reward zeroed but for the episode's last command, and for all
    /// when rewards are not used).
    fn record(&mut self, context: usize, command: &Command, outcome: &Outcome);
}

impl<A: EpisodeRecorder, B: EpisodeRecorder> EpisodeRecorder for (A, B) {
    fn begin(&mut self, config: &EpisodeConfig, num_effects: usize) {
        self.0.begin(config, num_effects);
        self.1.begin(config, num_effects);
    }
    fn start(&mut self, start: usize) {
        self.0.start(start);
        self.1.start(start);
    }
    fn record(&mut self, context: usize, command: &Command, outcome: &Outcome) {
        self.0.record(context, command, outcome);
        self.1.record(context, command, outcome);
    }
}

impl<R: EpisodeRecorder> EpisodeRecorder for Option<R> {
    fn begin(&mut self, config: &EpisodeConfig, num_effects: usize) {
        if let Some(r) = self {
            r.begin(config, num_effects)
        }
    }
    fn start(&mut self, start: usize) {
        if let Some(r) = self {
            r.start(start)
        }
    }
    fn record(&mut self, context: usize, command: &Command, outcome: &Outcome) {
        if let Some(r) = self {
            r.record(context, command, outcome)
        }
    }
}

/// A session's figures over its episodes, kept as they run: what
/// [`EpisodeRecord`]'s methods compute from the whole record, the same to
/// the bit, in memory that does not grow with the episodes (start
/// contexts x effects counts).
///
/// ```
/// use e3d::episode::{run_episodes, run_episodes_into, EpisodeConfig, EpisodeTally, Observe};
/// use e3d::learner::LearnerSetup;
/// use e3d::{Control, LearnerKind, Params, Scene};
/// let scene = Scene::builtin("four_rooms").unwrap();
/// let cfg = EpisodeConfig { episodes: 300, commands: 2, seed: 4, use_reward: true,
///                           observe: Observe::State };
/// let setup = LearnerSetup::new(LearnerKind::E3d).params(Params::TASK2).closed_loop(true);
/// let n = scene.num_effects(); // four_rooms: 36 cells, one context each
/// let learner = || setup.contexts(&scene.command_space(), n, n).unwrap();
/// let whole = run_episodes(&mut scene.build(), &mut learner(), &cfg, &Control::default()).unwrap();
/// let mut tally = EpisodeTally::new(1);
/// run_episodes_into(&mut scene.build(), &mut learner(), &cfg, &mut tally, &Control::default()).unwrap();
/// assert_eq!(tally.episodes(), 300);
/// assert_eq!(tally.cumulative_reward(), whole.cumulative_reward());
/// assert_eq!(tally.first_reward_episode(), whole.first_reward_episode());
/// assert_eq!(tally.entropy_per_start(), whole.entropy_per_start(1));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct EpisodeTally {
    num_effects: usize,
    commands_per_episode: usize,
    /// Per start context, the episodes' terminal cells counted
    /// (`num_effects` per start).
    terminal: Vec<f64>,
    starts: usize,
    episodes: usize,
    /// The command of the current episode reached, and its start.
    command: usize,
    start: usize,
    /// The current episode's reward so far.
    reward: f64,
    cumulative: f64,
    first_reward_episode: Option<usize>,
}

impl EpisodeTally {
    /// A tally of a world of `starts` start contexts.
    pub fn new(starts: usize) -> EpisodeTally {
        EpisodeTally {
            num_effects: 0,
            commands_per_episode: 1,
            terminal: Vec::new(),
            starts,
            episodes: 0,
            command: 0,
            start: 0,
            // as `Iterator::sum` of f64 starts
            reward: -0.0,
            cumulative: -0.0,
            first_reward_episode: None,
        }
    }
    /// The episodes run.
    pub fn episodes(&self) -> usize {
        self.episodes
    }
    /// The reward of all episodes ([`EpisodeRecord::cumulative_reward`]).
    pub fn cumulative_reward(&self) -> f64 {
        self.cumulative
    }
    /// The first rewarded episode, 1-based
    /// ([`EpisodeRecord::first_reward_episode`]).
    pub fn first_reward_episode(&self) -> Option<usize> {
        self.first_reward_episode
    }
    /// Per start context, the normalised entropy of the episodes' terminal
    /// cells ([`EpisodeRecord::entropy_per_start`]).
    pub fn entropy_per_start(&self) -> Vec<f64> {
        (0..self.starts)
            .map(|s| {
                let counts = &self.terminal[s * self.num_effects..(s + 1) * self.num_effects];
                normalized_entropy_over(counts, self.num_effects)
            })
            .collect()
    }
}

impl EpisodeRecorder for EpisodeTally {
    fn begin(&mut self, config: &EpisodeConfig, num_effects: usize) {
        self.num_effects = num_effects;
        self.commands_per_episode = config.commands.max(1);
        self.terminal = vec![0.0; self.starts * num_effects];
    }
    fn start(&mut self, start: usize) {
        self.start = start;
        self.command = 0;
        self.reward = -0.0;
    }
    fn record(&mut self, _context: usize, _command: &Command, outcome: &Outcome) {
        self.reward += outcome.reward;
        self.command += 1;
        if self.command == self.commands_per_episode {
            self.episodes += 1;
            self.terminal[self.start * self.num_effects + outcome.effect] += 1.0;
            self.cumulative += self.reward;
            if self.reward > 0.0 && self.first_reward_episode.is_none() {
                self.first_reward_episode = Some(self.episodes);
            }
        }
    }
}

/// What a session of episodes recorded, command by command (`K` entries
/// per episode).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EpisodeRecord {
    /// The commands of an episode, `K`.
    pub commands_per_episode: usize,
    /// The number of effects of the world.
    pub num_effects: usize,
    /// The start context of each episode.
    pub starts: Vec<usize>,
    /// The context the learner observed before each command.
    pub contexts: Vec<usize>,
    /// The commands, one after another (their slots' symbol indices).
    pub commands: Vec<u8>,
    /// The effect of each command's terminal state.
    pub effects: Vec<usize>,
    /// The reward of each command: the scene's reward of the episode's
    /// terminal state after its last command, 0 after the others (and 0
    /// always without reward).
    pub rewards: Vec<f64>,
}

impl EpisodeRecorder for EpisodeRecord {
    /// Sets the record's shape and takes the memory of every command
    /// ahead.
    fn begin(&mut self, config: &EpisodeConfig, num_effects: usize) {
        let n = config.episodes.saturating_mul(config.commands);
        self.commands_per_episode = config.commands;
        self.num_effects = num_effects;
        self.starts.reserve(config.episodes);
        self.contexts.reserve(n);
        self.effects.reserve(n);
        self.rewards.reserve(n);
    }
    fn start(&mut self, start: usize) {
        self.starts.push(start);
    }
    fn record(&mut self, context: usize, command: &Command, outcome: &Outcome) {
        self.contexts.push(context);
        self.commands.extend_from_slice(&command.symbols);
        self.effects.push(outcome.effect);
        self.rewards.push(outcome.reward);
    }
}

impl EpisodeRecord {
    /// The number of episodes recorded.
    pub fn episodes(&self) -> usize {
        self.starts.len()
    }

    /// The terminal effect of each episode (its last command's).
    pub fn terminal_effects(&self) -> impl Iterator<Item = usize> + '_ {
        self.effects
            .iter()
            .skip(self.commands_per_episode - 1)
            .step_by(self.commands_per_episode)
            .copied()
    }

    /// The reward of each episode.
    pub fn episode_rewards(&self) -> impl Iterator<Item = f64> + '_ {
        self.rewards
            .chunks(self.commands_per_episode)
            .map(|c| c.iter().sum())
    }

    /// The total reward.
    pub fn cumulative_reward(&self) -> f64 {
        self.episode_rewards().sum()
    }

    /// The first episode (1-based) with a reward > 0.
    pub fn first_reward_episode(&self) -> Option<usize> {
        self.episode_rewards().position(|r| r > 0.0).map(|i| i + 1)
    }

    /// The total reward of the episodes started in each start context,
    /// context by context (`num_contexts` entries; 0 for a context never
    /// drawn).
    pub fn reward_per_start(&self, num_contexts: usize) -> Vec<f64> {
        let mut sums = vec![0.0; num_contexts];
        for (&s, r) in self.starts.iter().zip(self.episode_rewards()) {
            sums[s] += r;
        }
        sums
    }

    /// Per start context, the first episode (1-based, counted over all the
    /// session's episodes, as [`first_reward_episode`](Self::first_reward_episode))
    /// started in it with a reward > 0 (`None`: none).
    pub fn first_reward_per_start(&self, num_contexts: usize) -> Vec<Option<usize>> {
        let mut first = vec![None; num_contexts];
        for (i, (&s, r)) in self.starts.iter().zip(self.episode_rewards()).enumerate() {
            if r > 0.0 && first[s].is_none() {
                first[s] = Some(i + 1);
            }
        }
        first
    }

    /// The normalised entropy (over all `num_effects` effects) of the
    /// terminal effects of the episodes started in each start context,
    /// context by context (`num_contexts` entries; 0 for a context never
    /// drawn).
    pub fn entropy_per_start(&self, num_contexts: usize) -> Vec<f64> {
        let mut counts = vec![vec![0.0; self.num_effects]; num_contexts];
        for (&s, e) in self.starts.iter().zip(self.terminal_effects()) {
            counts[s][e] += 1.0;
        }
        counts
            .iter()
            .map(|c| normalized_entropy_over(c, self.num_effects))
            .collect()
    }
}

/// Runs `config.episodes` episodes of `learner` on `world`.
///
/// Draws, in order, per episode: the start context (one integer of the
/// session's generator, only when the world has more than one), the
/// start state in it ([`Episodic::draw_start`]), then each command's draws
/// by the learner. A world of one context and `K = 1` with
/// [`Observe::StartContext`] draws exactly what
/// [`run_session`](crate::run_session) draws.
///
/// On a noisy world (a scene's `noise` section), command `i` of episode
/// `e` draws its noise from [`DrawKey::trial`]`(seed, e * K + i)`: the
/// record depends on the seed only, whatever the threads. The start
/// offsets apply to an episode's start (the later commands continue from
/// where the last left the world); the other draws to every command.
///
/// `control` is told of the episodes done (every 64 episodes and at the
/// end), and asked before each command is executed whether to stop: a
/// stop ends the run with [`WorldError::Stopped`]. Many sessions in parallel:
/// [`run_episode_sessions`](crate::session::run_episode_sessions).
///
/// ```
/// use e3d::episode::{run_episodes, EpisodeConfig, Observe};
/// use e3d::learner::{ClosedLoopE3d, ContextTargets};
/// use e3d::{Control, Params, Scene, Target};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let mut world = scene.build();
/// let cfg = EpisodeConfig { episodes: 200, commands: 2, seed: 1, use_reward: true,
///                           observe: Observe::State };
/// let mut l = ClosedLoopE3d::new(&scene.command_space(), 18, cfg.num_contexts(&world),
///     &Params::TASK2, &ContextTargets::Shared(Target::Uniform), 0.9).unwrap();
/// let rec = run_episodes(&mut world, &mut l, &cfg, &Control::default()).unwrap();
/// assert_eq!((rec.episodes(), rec.effects.len()), (200, 400));
/// ```
pub fn run_episodes<W, L>(
    world: &mut W,
    learner: &mut L,
    config: &EpisodeConfig,
    control: &(impl Observer + ?Sized),
) -> Result<EpisodeRecord, WorldError>
where
    W: Episodic + ?Sized,
    L: ContextualLearner + ?Sized,
{
    let mut rec = EpisodeRecord::default();
    run_episodes_into(world, learner, config, &mut rec, control)?;
    Ok(rec)
}

/// [`run_episodes`], each episode's start and commands handed to
/// `recorder` as they run (an [`EpisodeTally`] keeps the session's
/// figures without keeping the episodes; a file may take them as they
/// come). On an error, `recorder` holds the episodes before it.
pub fn run_episodes_into<W, L>(
    world: &mut W,
    learner: &mut L,
    config: &EpisodeConfig,
    recorder: &mut (impl EpisodeRecorder + ?Sized),
    control: &(impl Observer + ?Sized),
) -> Result<(), WorldError>
where
    W: Episodic + ?Sized,
    L: ContextualLearner + ?Sized,
{
    let k = config.commands;
    if k == 0 {
        return Err(WorldError::Other(
            "an episode needs at least one command".into(),
        ));
    }
    check_size(config.episodes, k).map_err(WorldError::Other)?;
    let needed = config.num_contexts(world);
    if learner.num_contexts() < needed {
        return Err(WorldError::Other(format!(
            "the learner keeps {} contexts; this world and observation need {needed}",
            learner.num_contexts()
        )));
    }
    let num_starts = world.num_contexts();
    recorder.begin(config, world.num_effects());
    let mut rng = SessionRng::seed_from_u64(config.seed);
    let mut command: Command = world.command_space().first();
    let mut since = 0;
    for episode in 0..config.episodes {
        if since == PROGRESS_EVERY {
            control.progress(since as u64);
            since = 0;
        }
        since += 1;
        let start = if num_starts > 1 {
            rng.random_range(0..num_starts)
        } else {
            0
        };
        let mut state = world.draw_start(start, &mut rng)?;
        let mut context = config.observe.context(start, || world.bin_state(&state))?;
        recorder.start(start);
        for i in 0..k {
            learner.propose(context, &mut rng, &mut command);
            if control.stopped() {
                return Err(WorldError::Stopped);
            }
            let last = i + 1 == k;
            // a noisy world's draws: keyed by the seed and the command's
            // place in the session
            let step = (episode * k + i) as u64;
            world.set_draw_keys(&[DrawKey::trial(config.seed, step)]);
            // the last command's terminal state is not needed: its outcome
            // may be looked up (a memo keyed by context and command)
            let (mut outcome, next_state) = if last {
                (world.execute_outcome_from(&state, &command)?, None)
            } else {
                let (o, s) = world.execute_from(&state, &command)?;
                (o, Some(s))
            };
            if !last || !config.use_reward {
                outcome.reward = 0.0;
            }
            let next = config.observe.context(start, || Ok(outcome.effect))?;
            learner.learn(context, &command, &outcome, (!last).then_some(next));
            recorder.record(context, &command, &outcome);
            if let Some(s) = next_state {
                state = s;
            }
            context = next;
        }
    }
    control.progress(since as u64);
    Ok(())
}
