//! # e3d: learning compositional motor commands by End-Effect Exploration
//!
//! A 2D sandbox for the experiments of E. Daucé, "End-Effect Exploration
//! Drive for Effective Motor Learning" (2020). An agent sends a command of
//! `n` elementary parts (one symbol per slot); the world executes it open
//! loop; the learner reads only the terminal state, binned into an
//! *effect*, and a reward.
//!
//! The flow of one trial:
//!
//! ```text
//! scenes/*.ron --Scene::load--> Scene --Scene::build--> World
//! Learner::propose(rng) -> Command
//! World::execute(&Command) -> Outcome   (effect, reward, terminal point)
//! Learner::learn(&Command, &Outcome)
//! ```
//!
//! - [`scene`]: the RON scene format, parsed and checked into a [`Scene`]
//!   (valid by construction: building its world cannot fail); a scene
//!   built or edited in code is a [`SceneSpec`], turned into a [`Scene`] by
//!   [`SceneSpec::validate`] and written back by [`SceneSpec::to_ron`];
//!   every mistake is a [`SceneError`] of some [`SceneErrorKind`];
//! - [`command`]: [`CommandSpace`] (slots and alphabets) and [`Command`];
//! - [`world`]: the [`World`] trait, the [`GridWorld`], the Rapier-based
//!   [`PhysicsWorld`], the [`OutcomeTable`] (every command once, up
//!   front), the [`OutcomeMemo`] (every proposed command once, whatever
//!   the size of the space) and the [`ExecutionPlan`] that chooses between
//!   them by cost;
//! - [`effect`]: binning ([`EffectGrid`]), the running histogram
//!   ([`EffectModel`]) and the target ([`Target`]);
//! - [`hash`]: the FNV-1a hash that keys outcome tables and the rule that
//!   derives a session's seed from its identity;
//! - [`learner`]: the [`Learner`] trait, [`E3d`], [`UniformPolicy`],
//!   [`EpsilonGreedy`], and drives beyond the paper
//!   ([`RelaxedE3d`](learner::RelaxedE3d), an E3D that cannot lock;
//!   [`CountBonus`](learner::CountBonus);
//!   [`StateMarginalMatching`](learner::StateMarginalMatching));
//! - [`rng`]: the [`SessionRng`] every session draws from, fixed by its
//!   seed;
//! - [`session`]: the one session engine, for commands of symbols and of
//!   values alike: the trial loop ([`run_session`], or [`run_session_into`]
//!   a [`Recorder`] such as [`RunningMetrics`], in constant memory),
//!   sessions that share a world in lockstep ([`run_group`]), sessions run
//!   the way an [`Executor`] plans them, in parallel ([`run_sessions`]),
//!   a [`Control`] for progress and stop, and their [`Metrics`];
//! - [`sweep`]: grids of sessions over scenes, learners and parameters
//!   ([`Sweep`], from a file or a [`SweepSpec`](sweep::SweepSpec) built in
//!   code), run in parallel, resumable, in shards; your own worlds and
//!   learners go in through [`sweep::Worlds`] and [`sweep::Learners`];
//! - [`experiment`]: the experiments behind `e3d reproduce` (the paper's
//!   figures), `e3d compare` (every drive) and `e3d closed-loop`, run;
//! - [`report`]: what runs, sweeps and experiments produced, drawn
//!   (tables, SVG figures, HTML pages); it runs no session;
//! - [`csv`]: e3d's own `summary.csv`, `results.csv` and `trials.csv`,
//!   read back (by `e3d report` and `e3d plot`).
//!
//! ```
//! use e3d::{run_session, LearnerKind, Params, Scene, SessionConfig, Target};
//!
//! let scene = Scene::builtin("two_rooms").unwrap();
//! let mut world = scene.build();
//! let space = scene.command_space();
//! let cfg = SessionConfig { trials: 5000, seed: 7, use_reward: false };
//!
//! let mut e3d = LearnerKind::E3d
//!     .make(&Params::TASK1, &space, scene.num_effects(), &Target::Uniform)
//!     .unwrap();
//! let explored = run_session(&mut world, &mut e3d, &cfg).unwrap().metrics(&Target::Uniform);
//!
//! let mut uniform = LearnerKind::Uniform
//!     .make(&Params::TASK1, &space, scene.num_effects(), &Target::Uniform)
//!     .unwrap();
//! let baseline = run_session(&mut world, &mut uniform, &cfg).unwrap().metrics(&Target::Uniform);
//!
//! // E3D spreads the terminal cells more evenly than the uniform policy.
//! assert!(explored.normalized_entropy > baseline.normalized_entropy + 0.05);
//! ```

#![warn(missing_docs)]

pub mod command;
pub mod csv;
pub mod effect;
pub mod episode;
pub mod experiment;
pub mod hash;
pub mod io;
pub mod learner;
pub mod report;
pub mod rng;
pub mod scene;
pub mod session;
pub mod sweep;
pub mod text;
pub mod world;

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// The examples of `docs/outcomes.md`, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../docs/outcomes.md")]
pub struct OutcomesDoctests;

/// The `rand` crate (0.10) whose traits e3d's generators implement: a
/// custom [`Learner`] draws from its [`SessionRng`] with `e3d::rand::RngExt`
/// (`rng.random::<f64>()`, `rng.random_range(0..k)`), with no version of
/// rand to pin in its own manifest.
pub use rand;

pub use command::{Command, CommandError, CommandSpace, ValueSpace};
pub use effect::{EffectError, EffectGrid, EffectModel, Target, TargetError};
pub use learner::{
    ContinuousLearner, E3d, EpsilonGreedy, GaussianE3d, Learner, LearnerError, LearnerKind,
    LearnerState, ParamError, Params, ParseLearnerError, UniformPolicy, UniformValues,
};
pub use rng::SessionRng;
pub use scene::{Scene, SceneError, SceneErrorKind, SceneSpec};
pub use session::{
    policy_effect_distribution, run_group, run_session, run_session_into, run_sessions,
    run_value_session, Control, Metrics, Recorder, RunningMetrics, SessionConfig, SessionRecord,
    ValueSessionRecord,
};
pub use sweep::{Sweep, SweepError};
pub use world::{
    ContinuousWorld, ExecutionPlan, Executor, GridWorld, Memoized, Outcome, OutcomeMemo,
    OutcomeTable, ParseStrategyError, PhysicsWorld, Strategy, ValueWorld, World, WorldError,
    WorldState,
};
