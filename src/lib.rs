//! # e3d: learning compositional motor commands by End-Effect Exploration
//!
//! A 2D sandbox for the experiments of E. Daucé, "End-Effect Exploration
//! Drive for Effective Motor Learning" (2020). An agent sends a command of
//! `n` elementary parts (one symbol per slot); the world executes it open
//! loop; the learner reads only the terminal state, binned into an
//! *effect*, and a reward.
//!
//! ## Start here
//!
//! `use e3d::prelude::*;` brings the names a session needs; a scene and a
//! learner make a [`Session`], run as `e3d run` runs it:
//!
//! ```
//! use e3d::prelude::*;
//!
//! let scene = Scene::builtin("two_rooms").unwrap();
//! let e3d = Session::new(&scene, LearnerKind::E3d).reward(false).seed(7).run()?;
//! let uniform = Session::new(&scene, LearnerKind::Uniform).reward(false).seed(7).run()?;
//! // E3D spreads the terminal cells more evenly than the uniform policy.
//! let h = |r: &SessionRecord| r.metrics(&Target::Uniform).normalized_entropy;
//! assert!(h(&e3d) > h(&uniform) + 0.05);
//! # Ok::<(), e3d::session::SessionError>(())
//! ```
//!
//! [`run_session`] runs a learner you made yourself (any [`Learner`]) on
//! any [`World`], trial by trial.
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
//! ## The modules
//!
//! - [`scene`]: the RON scene format, parsed and checked into a [`Scene`]
//!   (valid by construction: building its world cannot fail); a scene
//!   built or edited in code is a [`SceneSpec`]; every mistake is a
//!   [`SceneError`];
//! - [`command`]: [`command::CommandSpace`] (slots and alphabets), [`Command`], and
//!   the ranges of continuous commands ([`command::ValueSpace`]);
//! - [`world`]: the [`World`] trait, the grid and Rapier worlds, the
//!   [`OutcomeTable`] (every command once, up front), the outcome memo
//!   (every proposed command once) and the [`Executor`] that chooses
//!   between them by cost;
//! - [`effect`]: binning, the running histogram of effects and the
//!   [`Target`] distribution;
//! - [`learner`]: the [`Learner`] trait (and [`ContinuousLearner`] for
//!   values), E3D and the drives beyond the paper, all made by a
//!   [`LearnerKind`] from [`Params`];
//! - [`rng`]: the [`SessionRng`] every session draws from, fixed by its
//!   seed;
//! - [`session`]: the one session engine, for commands of symbols and of
//!   values alike: [`run_session`], sessions that share a world in
//!   lockstep ([`session::run_group`]), the groups an [`Executor`] plans
//!   run in parallel ([`run_sessions`]), a [`Control`] for progress and
//!   stop, what is kept of each trial (a [`Recorder`]: a
//!   [`SessionRecord`], or running metrics in constant memory) and the
//!   [`Metrics`];
//! - [`sweep`]: grids of sessions over scenes, learners and parameters
//!   ([`Sweep`], from a file or a [`sweep::SweepSpec`] built in code), run
//!   in parallel, resumable, in shards;
//! - [`episode`]: episodes of several commands, each from where the last
//!   left the world (start contexts, closed loop);
//! - [`experiment`]: the experiments behind `e3d reproduce` (the paper's
//!   figures), `e3d compare` (every drive) and `e3d closed-loop`;
//! - [`report`]: what runs, sweeps and experiments produced, drawn
//!   (tables, SVG figures, HTML pages); it runs no session.
//!
//! ARCHITECTURE.md in the repository draws the layers and says where to
//! add a world, a learner or a kind of command.

#![warn(missing_docs)]

pub mod command;
#[doc(hidden)]
pub mod csv;
pub mod effect;
pub mod episode;
pub mod experiment;
#[doc(hidden)]
pub mod hash;
#[doc(hidden)]
pub mod io;
pub mod learner;
pub mod report;
pub mod rng;
pub mod scene;
pub mod session;
pub mod sweep;
#[doc(hidden)]
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

pub use command::Command;
pub use effect::Target;
pub use learner::{ContinuousLearner, Learner, LearnerKind, Params};
pub use rng::SessionRng;
pub use scene::{Scene, SceneError, SceneSpec};
pub use session::{
    run_session, run_sessions, Control, Metrics, Recorder, Session, SessionConfig, SessionRecord,
};
pub use sweep::Sweep;
pub use world::{Executor, Outcome, OutcomeTable, World, WorldError};

/// The names a session needs, in one import: `use e3d::prelude::*;`.
///
/// ```
/// use e3d::prelude::*;
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let mut learner = LearnerSetup::new(LearnerKind::E3d)
///     .symbols(&scene.command_space(), scene.num_effects())
///     .unwrap();
/// let config = SessionConfig { trials: 500, seed: 0, use_reward: false };
/// let record = run_session(&mut scene.build(), &mut learner, &config).unwrap();
/// assert_eq!(record.trials(), 500);
/// ```
pub mod prelude {
    pub use crate::learner::{ContinuousLearner, Learner, LearnerKind, LearnerSetup, Params};
    pub use crate::session::{run_session, Recorder, Session, SessionConfig};
    pub use crate::world::{ContinuousWorld, Episodic, World};
    pub use crate::{Scene, SessionRecord, Target};
}
