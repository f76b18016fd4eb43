//! Re-evaluation under a scene's noise: each command run again and again
//! (its modal effect and the share of runs that keep it), and the
//! reproducibility of a learner's repertoire (of commands of symbols or
//! values, or of episodes).

use super::engine::{Executes, Learns};
use crate::command::Command;
use crate::episode::EpisodeConfig;
use crate::learner::{draw_weighted, ContextualLearner};
use crate::rng::SessionRng;
use crate::scene::physics::{draw_key, session_key, DrawKey};
use crate::world::{Episodic, Outcome, WorldError};
use rand::{RngExt, SeedableRng};
use serde::Serialize;

/// A command's effect under re-evaluation: its modal effect (ties to the
/// lowest) and how many of its runs end there.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Repeated {
    /// The modal effect of the runs.
    pub effect: usize,
    /// How many runs end in it.
    pub kept: usize,
    /// How many runs were made (1 on a deterministic world).
    pub runs: usize,
}

impl Repeated {
    /// The share of the runs that end in the modal effect.
    pub fn share(&self) -> f64 {
        self.kept as f64 / self.runs.max(1) as f64
    }

    /// Whether the modal effect holds in at least 90% of the runs.
    pub fn holds(&self) -> bool {
        self.kept * 10 >= self.runs * 9
    }

    /// The modal effect of `runs` (ties to the lowest) and its count.
    ///
    /// ```
    /// use e3d::session::Repeated;
    /// use e3d::Outcome;
    /// let o = |effect| Outcome { effect, reward: 0.0, point: [0.0; 2] };
    /// let r = Repeated::of(&[o(3), o(1), o(3), o(1), o(2)]);
    /// assert_eq!((r.effect, r.kept, r.runs), (1, 2, 5));
    /// assert_eq!(r.share(), 0.4);
    /// assert!(!r.holds());
    /// ```
    pub fn of(runs: &[Outcome]) -> Repeated {
        let mut counts = std::collections::BTreeMap::new();
        for o in runs {
            *counts.entry(o.effect).or_insert(0usize) += 1;
        }
        // the largest count, the lowest effect among equals
        let (&effect, &kept) = (counts.iter().rev())
            .max_by_key(|(_, &n)| n)
            .unwrap_or((&0, &0));
        Repeated {
            effect,
            kept,
            runs: runs.len(),
        }
    }
}

/// The keys of the draws of run `run` of command `index` (of a list)
/// under seed `seed`: the execution's `draw_key(draw_key(seed, run),
/// index)`, and the session's `session_key(seed)` (every run of every
/// command of one seed draws the same numbers per session: those of the
/// session of that seed).
///
/// ```
/// use e3d::scene::physics::{draw_key, session_key, DrawKey};
/// use e3d::session::run_key;
/// let k = run_key(3, 1, 4);
/// assert_eq!(k, DrawKey { session: session_key(3), execution: draw_key(draw_key(3, 1), 4) });
/// ```
pub fn run_key(seed: u64, run: u64, index: u64) -> DrawKey {
    DrawKey {
        session: session_key(seed),
        execution: draw_key(draw_key(seed, run), index),
    }
}

/// Re-evaluates `commands`, commands `first..` of a list: each runs `runs`
/// times, run `r` of command `i` keyed [`run_key`]`(seed, r, i)`, through
/// `exec` (given the commands, command after command and run after run,
/// and their keys; it appends their results in order). Each command's
/// [`Repeated`], up to and with the first that fails (one run failing).
/// The one function behind [`reevaluate`] and `e3d scene exec --repeat`.
pub fn reevaluate_with<C: Clone>(
    commands: &[C],
    first: u64,
    runs: usize,
    seed: u64,
    mut exec: impl FnMut(&[C], &[DrawKey], &mut Vec<Result<Outcome, WorldError>>),
) -> Vec<Result<Repeated, WorldError>> {
    let runs = runs.max(1);
    let each = (commands.iter()).flat_map(|c| std::iter::repeat_n(c, runs).cloned());
    let repeated: Vec<C> = each.collect();
    let keys: Vec<DrawKey> = (first..first + commands.len() as u64)
        .flat_map(|i| (0..runs as u64).map(move |r| run_key(seed, r, i)))
        .collect();
    let mut results = Vec::with_capacity(repeated.len());
    exec(&repeated, &keys, &mut results);
    let mut results = results.into_iter();
    let mut out = Vec::with_capacity(commands.len());
    let mut outcomes = Vec::with_capacity(runs);
    for _ in commands {
        outcomes.clear();
        for r in results.by_ref().take(runs) {
            match r {
                Ok(o) => outcomes.push(o),
                Err(e) => {
                    out.push(Err(e));
                    return out;
                }
            }
        }
        if outcomes.len() < runs {
            out.push(Err(WorldError::Stopped));
            return out;
        }
        out.push(Ok(Repeated::of(&outcomes)));
    }
    out
}

/// Re-evaluates `commands` on `world` ([`reevaluate_with`], from index 0):
/// `runs` runs each on a noisy world, one on a deterministic one (kept 1
/// of 1: share 1). The first failure is returned.
///
/// ```
/// use e3d::session::reevaluate;
/// use e3d::Scene;
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let mut world = scene.build();
/// let c = scene.command_space().parse("EEEEEEE").unwrap();
/// let r = reevaluate(&mut *world, &[c], 20, 0).unwrap();
/// assert_eq!((r[0].share(), r[0].runs), (1.0, 1)); // a grid has no noise
/// ```
pub fn reevaluate<C: Clone, W: Executes<C> + ?Sized>(
    world: &mut W,
    commands: &[C],
    runs: usize,
    seed: u64,
) -> Result<Vec<Repeated>, WorldError> {
    let runs = if world.deterministic() { 1 } else { runs };
    let results = reevaluate_with(commands, 0, runs, seed, |cs, keys, out| {
        world.draw_keys(keys);
        world.execute_all(cs, out)
    });
    results.into_iter().collect()
}

/// How [`reproducibility`] measures a repertoire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct RepeatOptions {
    /// How many likely commands are drawn from the final policy (M).
    pub commands: usize,
    /// How many runs each gets (R).
    pub runs: usize,
}

impl Default for RepeatOptions {
    /// 64 commands, 20 runs each.
    fn default() -> Self {
        RepeatOptions {
            commands: 64,
            runs: 20,
        }
    }
}

/// The reproducibility of a learner's repertoire on a world.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reproducibility {
    /// The share of the likely commands whose modal effect holds in at
    /// least 90% of their runs ([`Repeated::holds`]).
    pub share: f64,
    /// Each likely command's re-evaluation, in the order drawn.
    pub each: Vec<Repeated>,
}

impl Reproducibility {
    /// The share of `each` that holds, and `each`.
    fn of(each: Vec<Repeated>) -> Reproducibility {
        let holding = each.iter().filter(|r| r.holds()).count();
        Reproducibility {
            share: holding as f64 / each.len().max(1) as f64,
            each,
        }
    }
}

/// The reproducibility of `learner`'s repertoire on `world`: the share of
/// its policy's likely commands whose effect holds in at least 90% of
/// `options.runs` runs under the world's noise.
///
/// The likely commands are `options.commands` commands drawn from the
/// learner's current policy (each slot from its distribution,
/// [`Learner::slot_policy`](crate::Learner::slot_policy), or for values
/// from its Gaussian clamped to the slot's range,
/// [`ContinuousLearner::slot_gaussian`](crate::learner::ContinuousLearner::slot_gaussian);
/// repeats kept, so that a command counts by its probability) by the
/// generator seeded
/// `draw_key(seed, u64::MAX)`; command `i`'s run `r` draws its noise from
/// [`run_key`]`(seed, r, i)` ([`reevaluate`]; one run on a deterministic
/// world, whose share is 1). `seed` is the session's seed in `e3d run`
/// and sweeps. `None` when the policy cannot be drawn from
/// ([`Learns::likely`]). The result depends only on the policy, the
/// world, the options and the seed: not on threads or batches.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::session::{reproducibility, RepeatOptions};
/// use e3d::{LearnerKind, Scene};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let learner = LearnerSetup::new(LearnerKind::Uniform)
///     .symbols(&scene.command_space(), scene.num_effects())
///     .unwrap();
/// let mut world = scene.build();
/// let r = reproducibility(&mut *world, &learner, RepeatOptions::default(), 7).unwrap().unwrap();
/// assert_eq!((r.share, r.each.len()), (1.0, 64)); // no noise
/// ```
pub fn reproducibility<C: Clone, W: Executes<C> + ?Sized, L: Learns<C> + ?Sized>(
    world: &mut W,
    learner: &L,
    options: RepeatOptions,
    seed: u64,
) -> Result<Option<Reproducibility>, WorldError> {
    let mut rng = SessionRng::seed_from_u64(draw_key(seed, u64::MAX));
    let Some(likely) = learner.likely(&world.blank(), options.commands, &mut rng) else {
        return Ok(None);
    };
    let each = reevaluate(world, &likely, options.runs, seed)?;
    Ok(Some(Reproducibility::of(each)))
}

/// The reproducibility of a session of episodes: the share of the final
/// policy's likely episodes whose terminal effect holds in at least 90% of
/// `options.runs` runs under the world's noise.
///
/// The likely episodes are `options.commands` episodes drawn from
/// `learner`'s policy by the generator seeded `draw_key(config.seed,
/// u64::MAX)`: each starts as [`run_episodes`](crate::episode::run_episodes)
/// starts one (the start context, then its start state), then each of its
/// `config.commands` commands is drawn slot by slot from the policy of the
/// context observed ([`ContextualLearner::slot_policy`], observed as
/// `config.observe` says along the episode's run 0). Each episode is then
/// run `options.runs` times from its start, its commands in order whatever
/// their outcomes (the episode's commands re-run, open loop); command `i`
/// of run `r` of episode `j` draws its noise from the execution key
/// `draw_key(run_key(seed, r, j).execution, i)` and the session's
/// `session_key(seed)`. One run on a deterministic world (share 1). `None`
/// when a policy cannot be drawn from (a slot's policy is not known). The
/// result depends only on the policy, the world, the options and the
/// seed.
///
/// ```
/// use e3d::episode::{run_episodes, EpisodeConfig, Observe};
/// use e3d::learner::LearnerSetup;
/// use e3d::session::{episode_reproducibility, RepeatOptions};
/// use e3d::{Control, LearnerKind, Scene};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let cfg = EpisodeConfig { episodes: 50, commands: 2, seed: 1, use_reward: true,
///                           observe: Observe::State };
/// let n = scene.num_effects();
/// let mut learner = LearnerSetup::new(LearnerKind::E3d)
///     .contexts(&scene.command_space(), n, n)
///     .unwrap();
/// let mut world = scene.build();
/// run_episodes(&mut *world, &mut *learner, &cfg, &Control::default()).unwrap();
/// let r = episode_reproducibility(&mut *world, &*learner, &cfg, RepeatOptions::default())
///     .unwrap()
///     .unwrap();
/// assert_eq!((r.share, r.each.len()), (1.0, 64)); // a grid has no noise
/// ```
pub fn episode_reproducibility<W, L>(
    world: &mut W,
    learner: &L,
    config: &EpisodeConfig,
    options: RepeatOptions,
) -> Result<Option<Reproducibility>, WorldError>
where
    W: Episodic + ?Sized,
    L: ContextualLearner + ?Sized,
{
    let slots = world.command_space().num_slots();
    // every context's policy, slot by slot
    let mut policies = Vec::with_capacity(learner.num_contexts() * slots);
    for context in 0..learner.num_contexts() {
        for slot in 0..slots {
            let Some(p) = learner.slot_policy(context, slot) else {
                return Ok(None);
            };
            policies.push(p);
        }
    }
    let mut rng = SessionRng::seed_from_u64(draw_key(config.seed, u64::MAX));
    let (num_starts, k) = (world.num_contexts(), config.commands.max(1));
    let runs = if world.is_deterministic() {
        1
    } else {
        options.runs.max(1)
    };
    let mut each = Vec::with_capacity(options.commands);
    let mut commands: Vec<Command> = Vec::with_capacity(k);
    let mut terminal = Vec::with_capacity(runs);
    for j in 0..options.commands as u64 {
        let start = match num_starts {
            0 | 1 => 0,
            n => rng.random_range(0..n),
        };
        let first = world.draw_start(start, &mut rng)?;
        let mut context = config.observe.context(start, || world.bin_state(&first))?;
        commands.clear();
        terminal.clear();
        for r in 0..runs as u64 {
            let key = run_key(config.seed, r, j);
            let mut state = first.clone();
            for i in 0..k {
                if r == 0 {
                    let policy = &policies[context * slots..(context + 1) * slots];
                    let each = policy
                        .iter()
                        .map(|p| draw_weighted(p.iter().copied(), &mut rng));
                    commands.push(Command::new(each.map(|s| s as u8).collect()));
                }
                world.set_draw_keys(&[DrawKey {
                    session: key.session,
                    execution: draw_key(key.execution, i as u64),
                }]);
                if i + 1 == k {
                    terminal.push(world.execute_outcome_from(&state, &commands[i])?);
                } else {
                    let (o, next) = world.execute_from(&state, &commands[i])?;
                    if r == 0 {
                        context = config.observe.context(start, || Ok(o.effect))?;
                    }
                    state = next;
                }
            }
        }
        each.push(Repeated::of(&terminal));
    }
    Ok(Some(Reproducibility::of(each)))
}
