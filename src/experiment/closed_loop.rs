//! Closed loop against open loop on equal budgets of moves (what
//! `e3d closed-loop` prints): on a grid scene, or a physics scene on a
//! sequential schedule, whose command has `n` moves (slots), episodes of `K` commands of `n` moves against one command of
//! `K n` moves.
//!
//! The arms, every one `K n` moves per episode and the reward of the
//! episode's terminal cell:
//!
//! - `e3d_closed_loop`: [`ClosedLoopE3d`], `K` commands, the context the
//!   current cell;
//! - `e3d_contextual`: the same with `gamma = 0` (no bootstrap from
//!   `Q_ref`: contextual E3D on the episode's reward);
//! - `e3d_open_loop`: E3D with one command of `K n` moves (the paper's
//!   learner on the longer command);
//! - `qlearning`: [`QLearning`], `K` commands, the context the current cell;
//! - `qlearning_moves`: per-move Q-learning ([`LearnerKind::QlearningMoves`]):
//!   `K n` commands of one move, the context the current cell before each
//!   move, values from `params.initial` ([`QLearning::OPTIMISTIC`] by
//!   default), epsilon [`ClosedLoopConfig::moves_epsilon`];
//! - `uniform`: `K n` uniform moves.

use crate::episode::{run_episodes, EpisodeConfig, EpisodeRecord, Observe};
use crate::learner::LearnerSetup;
use crate::learner::{
    ClosedLoopE3d, ContextTargets, ContextualLearner, LearnerError, LearnerKind, Params, QLearning,
};
use crate::scene::physics::Schedule;
use crate::scene::{CommandSpec, Scene, WorldSpec};
use crate::session::{run_episode_sessions, Control};
use crate::world::Episodic;
use crate::Target;

/// The arms, in the order of the table.
pub const ARMS: [&str; 6] = [
    "e3d_closed_loop",
    "e3d_contextual",
    "e3d_open_loop",
    "qlearning",
    "qlearning_moves",
    "uniform",
];

/// The exploration rate of the arm `qlearning_moves`: 0, its optimistic
/// values explore.
pub const MOVES_EPSILON: f64 = 0.0;

/// The settings of a comparison.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClosedLoopConfig {
    /// Episodes per session.
    pub episodes: usize,
    /// Sessions (seeds `0..seeds`) per arm.
    pub seeds: u64,
    /// Commands per episode of the closed-loop arms, `K`.
    pub commands: usize,
    /// The parameters of the E3D arms (`alpha`, `beta`, `lambda`, `eta`)
    /// and of Q-learning (`alpha`, `epsilon`).
    pub params: Params,
    /// The discount of `Q_ref` and of Q-learning.
    pub gamma: f64,
    /// The exploration rate of `qlearning_moves` ([`MOVES_EPSILON`] by
    /// default; its initial value is `params.initial`).
    pub moves_epsilon: f64,
}

impl Default for ClosedLoopConfig {
    /// 5000 episodes, 20 seeds, `K = 3`, the paper's task 2, `gamma = 0.9`.
    fn default() -> Self {
        ClosedLoopConfig {
            episodes: 5000,
            seeds: 20,
            commands: 3,
            params: Params::TASK2,
            gamma: ClosedLoopE3d::GAMMA,
            moves_epsilon: MOVES_EPSILON,
        }
    }
}

/// One session's figures.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmSession {
    /// The arm (one of [`ARMS`]).
    pub arm: &'static str,
    /// The seed.
    pub seed: u64,
    /// The first rewarded episode (1-based).
    pub first_reward_episode: Option<usize>,
    /// The reward collected over all episodes.
    pub cumulative_reward: f64,
    /// The reward collected over the last 1000 episodes (or all, if fewer).
    pub late_reward: f64,
}

/// Why a comparison cannot run.
#[derive(Debug, thiserror::Error)]
pub enum ClosedLoopError {
    /// Not a scene of repeated one-alphabet slots, one after another.
    #[error("scene `{0}`: a closed-loop comparison takes a scene whose command is `Repeat`: a Grid scene, or a Physics scene on a `Sequential` schedule")]
    Scene(String),
    /// The scene and the settings do not fit ([`check_scene`]).
    #[error("{0}")]
    Setup(String),
    /// A learner could not be made.
    #[error(transparent)]
    Learner(#[from] LearnerError),
    /// A session failed.
    #[error(transparent)]
    World(#[from] crate::WorldError),
    /// The scene of the long command is invalid.
    #[error(transparent)]
    Long(#[from] crate::SceneError),
}

/// Checks that `scene` can be compared with `commands` commands per
/// episode, before any work: a Grid scene whose command is `Repeat`,
/// without start contexts (the closed-loop arms observe the current cell
/// from the scene's one start), whose open-loop command of `commands`
/// times its moves fits in [`MAX_SLOTS`](crate::command::MAX_SLOTS)
/// slots. The error names the scene and what was expected.
pub fn check_scene(scene: &Scene, commands: usize) -> Result<(), ClosedLoopError> {
    let name = crate::text::echo(&scene.spec().name);
    // a physics scene's open-loop arm runs its K n slots one after
    // another: a sequential schedule, whose budget is the same moves
    let (contexts, noisy) = match &scene.spec().world {
        WorldSpec::Grid(g) => (
            g.contexts.iter().map(|c| &c.name).collect::<Vec<_>>(),
            false,
        ),
        WorldSpec::Physics(p) if matches!(p.schedule, Schedule::Sequential { .. }) => (
            p.contexts.iter().map(|c| &c.name).collect(),
            p.active_noise().is_some(),
        ),
        _ => return Err(ClosedLoopError::Scene(name)),
    };
    if !matches!(scene.spec().command, CommandSpec::Repeat { .. }) {
        return Err(ClosedLoopError::Scene(name));
    }
    if let Some(first) = contexts.first() {
        let (k, first) = (contexts.len(), crate::text::echo(first));
        return Err(ClosedLoopError::Setup(format!(
            "scene `{name}` has {k} start contexts (`{first}`...); a closed-loop comparison observes the current cell from the scene's one start: expected a scene without `contexts`"
        )));
    }
    if noisy {
        return Err(ClosedLoopError::Setup(format!(
            "scene `{name}` has a `noise` section: the comparison's open-loop arm runs one command of K x n slots where its closed-loop arms run K commands, so the arms would not draw the same noise; expected a noise-free scene (`e3d run --commands K` runs episodes under noise)"
        )));
    }
    let (n, max) = (scene.spec().num_slots(), crate::command::MAX_SLOTS);
    let (moves, most) = (n.saturating_mul(commands), max / n.max(1));
    if moves > max {
        return Err(ClosedLoopError::Setup(format!(
            "commands per episode (K) = {commands}: the open-loop arms take one command of {commands} x {n} moves = {moves}, but a command has at most {max} slots; expected at most {most} on scene `{name}`"
        )));
    }
    Ok(())
}

/// The scene with `n` moves per command instead of its own.
fn with_slots(scene: &Scene, n: usize) -> Result<Scene, ClosedLoopError> {
    let same = scene.with_moves(n);
    Ok(same.ok_or_else(|| ClosedLoopError::Scene(scene.spec().name.clone()))??)
}

/// The episodes of a session of `arm`: `K` commands observing the
/// current cell (the closed-loop arms; `K n` commands of one move for
/// `qlearning_moves`), or one command of `K n` moves from the scene's
/// start (the open-loop arms).
/// `moves` is the scene's moves per command (`n`): `qlearning_moves` runs
/// `K n` commands of one move.
fn arm_config(arm: &str, seed: u64, cfg: &ClosedLoopConfig, moves: usize) -> EpisodeConfig {
    let closed = EpisodeConfig {
        episodes: cfg.episodes,
        commands: cfg.commands,
        seed,
        use_reward: true,
        observe: Observe::State,
    };
    match arm {
        "e3d_open_loop" | "uniform" => EpisodeConfig {
            commands: 1,
            observe: Observe::StartContext,
            ..closed
        },
        "qlearning_moves" => EpisodeConfig {
            commands: cfg.commands.saturating_mul(moves),
            ..closed
        },
        _ => closed,
    }
}

/// A session's world and learner.
type Arm = (Box<dyn Episodic + Send>, Box<dyn ContextualLearner + Send>);

/// A session of `arm`: its world (the scene, or the scene of the long
/// command) and its learner, fresh.
fn arm_setup(scene: &Scene, arm: &str, cfg: &ClosedLoopConfig) -> Result<Arm, ClosedLoopError> {
    check_scene(scene, cfg.commands)?;
    let shared = ContextTargets::Shared(Target::Uniform);
    Ok(match arm {
        "e3d_closed_loop" | "e3d_contextual" | "qlearning" => {
            let world = scene.build();
            let space = scene.command_space();
            let contexts = arm_config(arm, 0, cfg, 1).num_contexts(&*world);
            let learner: Box<dyn ContextualLearner + Send> = match arm {
                "qlearning" => Box::new(QLearning::new(&space, contexts, &cfg.params, cfg.gamma)?),
                _ => Box::new(ClosedLoopE3d::new(
                    &space,
                    scene.num_effects(),
                    contexts,
                    &cfg.params,
                    &shared,
                    if arm == "e3d_contextual" {
                        0.0
                    } else {
                        cfg.gamma
                    },
                )?),
            };
            (world, learner)
        }
        "qlearning_moves" => {
            let single = with_slots(scene, 1)?;
            let world = single.build();
            let contexts = arm_config(arm, 0, cfg, 1).num_contexts(&*world);
            let params = Params {
                epsilon: cfg.moves_epsilon,
                ..cfg.params
            };
            let learner = LearnerSetup::new(LearnerKind::QlearningMoves)
                .params(params)
                .gamma(cfg.gamma)
                .contexts(&single.command_space(), single.num_effects(), contexts)?;
            (world, learner)
        }
        "e3d_open_loop" | "uniform" => {
            let long = with_slots(scene, scene.spec().num_slots() * cfg.commands)?;
            let kind = if arm == "uniform" {
                LearnerKind::Uniform
            } else {
                LearnerKind::E3d
            };
            let learner = LearnerSetup::new(kind)
                .params(cfg.params)
                .targets(shared)
                .contexts(&long.command_space(), long.num_effects(), 1)?;
            (long.build(), learner)
        }
        _ => return Err(ClosedLoopError::Scene(format!("unknown arm {arm}"))),
    })
}

/// A session's figures, from its record.
fn figures(arm: &'static str, seed: u64, rec: &EpisodeRecord) -> ArmSession {
    let rewards: Vec<f64> = rec.episode_rewards().collect();
    let late = rewards.len().saturating_sub(1000);
    ArmSession {
        arm,
        seed,
        first_reward_episode: rec.first_reward_episode(),
        cumulative_reward: rewards.iter().sum(),
        late_reward: rewards[late..].iter().sum(),
    }
}

/// Runs one session of `arm` (one of [`ARMS`]).
pub fn run_arm(
    scene: &Scene,
    arm: &'static str,
    seed: u64,
    cfg: &ClosedLoopConfig,
) -> Result<ArmSession, ClosedLoopError> {
    let (mut world, mut learner) = arm_setup(scene, arm, cfg)?;
    let config = arm_config(arm, seed, cfg, scene.spec().num_slots());
    let rec = run_episodes(&mut *world, &mut *learner, &config, &Control::default())?;
    Ok(figures(arm, seed, &rec))
}

/// Every arm on every seed, in parallel through
/// [`run_episode_sessions`] (the results do not depend on the threads:
/// each session has its own generator), in the order arm, seed.
pub fn run_comparison(
    scene: &Scene,
    cfg: &ClosedLoopConfig,
) -> Result<Vec<ArmSession>, ClosedLoopError> {
    check_scene(scene, cfg.commands)?;
    // every move of `qlearning_moves` is a command: refuse before any work
    let moves = cfg.commands.saturating_mul(scene.spec().num_slots());
    crate::episode::check_size(cfg.episodes, moves).map_err(|e| {
        ClosedLoopError::Setup(format!("arm qlearning_moves (one move a command): {e}"))
    })?;
    let jobs: Vec<(&'static str, u64)> = ARMS
        .iter()
        .flat_map(|&a| (0..cfg.seeds).map(move |s| (a, s)))
        .collect();
    let configs: Vec<EpisodeConfig> = jobs
        .iter()
        .map(|&(arm, seed)| arm_config(arm, seed, cfg, scene.spec().num_slots()))
        .collect();
    let make = |i: usize| arm_setup(scene, jobs[i].0, cfg);
    let mut records = vec![EpisodeRecord::default(); jobs.len()];
    let status = run_episode_sessions(&configs, make, &mut records, &Control::default());
    jobs.iter()
        .zip(status)
        .zip(&records)
        .map(|((&(arm, seed), st), rec)| st.map(|()| figures(arm, seed, rec)))
        .collect()
}
