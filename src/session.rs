//! Sessions: the trial loop, what it records, and the metrics of a run.
//!
//! One trial: the learner proposes a command, the world executes it open
//! loop, the learner learns from the outcome. [`run_session`] repeats it
//! and records, per trial, the command, the effect and the reward.

use crate::command::{Command, CommandSpace};
use crate::effect::{entropy, kl_divergence, Target};
use crate::learner::Learner;
use crate::world::{OutcomeTable, World, WorldError};
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use std::io::{self, Write};

/// The random generator of a session: PCG 64-bit MCG (`rand_pcg::Pcg64Mcg`),
/// portable and fixed by its seed. A session seeded with `s` uses
/// `SessionRng::seed_from_u64(s)`.
pub type SessionRng = rand_pcg::Pcg64Mcg;

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
    /// The effect of each trial.
    pub effects: Vec<u32>,
    /// The reward the learner received at each trial.
    pub rewards: Vec<f64>,
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
    mut progress: impl FnMut(usize),
) -> Result<SessionRecord, WorldError>
where
    W: World + ?Sized,
    L: Learner + ?Sized,
{
    let n = world.command_space().num_slots();
    let mut rng = SessionRng::seed_from_u64(config.seed);
    let mut rec = SessionRecord {
        num_slots: n,
        num_effects: world.num_effects(),
        commands: Vec::with_capacity(config.trials * n),
        effects: Vec::with_capacity(config.trials),
        rewards: Vec::with_capacity(config.trials),
    };
    let mut command = world.command_space().first();
    for t in 0..config.trials {
        learner.propose(&mut rng, &mut command);
        let mut outcome = world.execute(&command)?;
        if !config.use_reward {
            outcome.reward = 0.0;
        }
        learner.learn(&command, &outcome);
        rec.commands.extend_from_slice(&command.symbols);
        rec.effects.push(outcome.effect as u32);
        rec.rewards.push(outcome.reward);
        if t % 256 == 255 {
            progress(t + 1);
        }
    }
    progress(config.trials);
    Ok(rec)
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
    assert_eq!(learners.len(), configs.len(), "one config per learner");
    let n = world.command_space().num_slots();
    let mut rngs: Vec<SessionRng> = configs
        .iter()
        .map(|c| SessionRng::seed_from_u64(c.seed))
        .collect();
    let mut records: Vec<Result<SessionRecord, WorldError>> = configs
        .iter()
        .map(|c| {
            Ok(SessionRecord {
                num_slots: n,
                num_effects: world.num_effects(),
                commands: Vec::with_capacity(c.trials * n),
                effects: Vec::with_capacity(c.trials),
                rewards: Vec::with_capacity(c.trials),
            })
        })
        .collect();
    let mut commands: Vec<Command> = configs
        .iter()
        .map(|_| world.command_space().first())
        .collect();
    let mut active: Vec<usize> = Vec::with_capacity(configs.len());
    // reused from trial to trial: no allocation per trial
    let mut batch: Vec<Command> = commands.clone();
    let mut outcomes = Vec::with_capacity(configs.len());
    let longest = configs.iter().map(|c| c.trials).max().unwrap_or(0);
    for t in 0..longest {
        active.clear();
        for (i, c) in configs.iter().enumerate() {
            if t < c.trials && records[i].is_ok() {
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
                    records[i] = Err(e);
                    continue;
                }
            };
            if !configs[i].use_reward {
                outcome.reward = 0.0;
            }
            learners[i].learn(&commands[i], &outcome);
            if let Ok(rec) = &mut records[i] {
                rec.commands.extend_from_slice(&commands[i].symbols);
                rec.effects.push(outcome.effect as u32);
                rec.rewards.push(outcome.reward);
            }
        }
    }
    records
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
}

impl SessionRecord {
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
            counts[e as usize] += 1.0;
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
        let t = self.trials();
        let all = self.effect_counts(0..t);
        let last = self.effect_counts(t.saturating_sub(1000)..t);
        let norm = (self.num_effects as f64).ln();
        let norm = if norm > 0.0 { norm } else { 1.0 };
        let log_target = target
            .log_probs(self.num_effects)
            .unwrap_or_else(|_| vec![-norm; self.num_effects]);
        Metrics {
            normalized_entropy: entropy(&all) / norm,
            normalized_entropy_last_1000: entropy(&last) / norm,
            kl_to_target: kl_divergence(&all, &log_target),
            distinct_effects: all.iter().filter(|&&c| c > 0.0).count(),
            cumulative_reward: self.rewards.iter().sum(),
            first_reward_trial: self.rewards.iter().position(|&r| r > 0.0).map(|i| i + 1),
            trials: t,
        }
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
