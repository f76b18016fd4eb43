//! Sweeps: grids of sessions over scenes, learners, hyper-parameters and
//! scene fields.
//!
//! A sweep file (RON, documented in `docs/sweeps.md`) names the scenes, the
//! learners, the reward settings, a list or a range of values for each
//! hyper-parameter, the number of sessions (seeds) per cell, the trials per
//! session, a base seed and the metrics to keep:
//!
//! ```ron
//! Sweep(
//!     scenes: ["two_rooms"],
//!     learners: [e3d, uniform],
//!     use_reward: [false],
//!     params: (
//!         beta: (scale: Log, from: 1, to: 1000, steps: 4),
//!         eta: [0.01, 0.1],
//!     ),
//!     sessions: 3,
//!     trials: 500,
//!     seed: 2020,
//!     metrics: [normalized_entropy, cumulative_reward(500)],
//! )
//! ```
//!
//! [`Sweep::parse`] (or [`Sweep::load`]) checks everything before any work
//! starts; [`Sweep::cells`] lists the grid and [`Sweep::sessions`] every
//! session with its seed; [`Sweep::run`] runs them in parallel and returns
//! the results in canonical order; [`Sweep::run_to_dir`] is the resumable,
//! shardable form behind `e3d sweep`. The [`factory`] makes the spec's
//! scenes ([`Worlds`]) and learners ([`Learners`]). A scene with start
//! contexts, or a spec that sets [`SweepSpec::commands`],
//! [`SweepSpec::observe`] or [`SweepSpec::closed_loop`], runs sessions of
//! episodes ([`Sweep::runs_episodes`]); a scene of continuous commands
//! runs live, in lockstep groups.
//!
//! # Cells
//!
//! The cells are the product, in this order, of the scenes, the values of
//! the scene axes ([`SweepSpec::axes`]: fields set by path, each
//! combination a derived scene, the last axis fastest), the learners, the
//! `use_reward` values and the values of `alpha`, `beta`, `lambda`,
//! `eta` and `epsilon`, each in the order of the file. A learner's grid
//! spans only the parameters it uses ([`uses_param`]; for a custom
//! learner, [`Learners::uses`]): the uniform policy uses none,
//! epsilon-greedy `alpha` and `epsilon`, E3D the four others.
//! A parameter a learner does not use is left empty in the results.
//!
//! # Seeds
//!
//! Session `i` of a cell (`i` in `0..sessions`) is seeded with
//! [`session_seed`]`(base_seed, identity)`, where the identity is the text
//! `scene=S;learner=L;use_reward=B;alpha=A;beta=B;lambda=L;eta=E;epsilon=P;session=I`
//! with every number written as in `results.csv` (Rust's shortest
//! round-trip form, `-` for an unused parameter), and each scene axis's
//! `;PATH=V` after `epsilon`. A session's seed thus
//! depends on what it is, never on when or where it runs: the results are
//! the same, byte for byte, with one thread or many, in one process or in
//! shards.
//!
//! ```
//! use e3d::sweep::Sweep;
//! let text = r#"Sweep(
//!     scenes: ["two_rooms"], learners: [e3d, uniform], use_reward: [false],
//!     params: (eta: [0.01, 0.1]), sessions: 2, trials: 300, seed: 1,
//! )"#;
//! let sweep = Sweep::parse(text, "example.ron", None).unwrap();
//! // e3d x 2 values of eta, and the uniform policy once
//! assert_eq!(sweep.cells().len(), 3);
//! assert_eq!(sweep.sessions().len(), 6);
//! let results = sweep.run(2).unwrap();
//! let one_thread = sweep.run(1).unwrap();
//! assert_eq!(results, one_thread);
//! assert_eq!(results[0].values.len(), sweep.metric_columns().len());
//! ```

pub mod journal;
pub mod summary;

pub mod factory;

mod axes;
mod contexts;
mod episodes;
mod error;
mod plan;
mod results;
mod run;
mod spec;

pub use crate::hash::{fnv1a64, session_seed, splitmix64};
pub(crate) use error::io_err;
pub use error::{BoxError, SweepError};
pub use factory::{uses_param, FactoryError, Learners, LiveScene, MakeLearner, SweepScene, Worlds};
pub use plan::{format_number, Cell, ParseShardError, SessionSpec, Shard, Sweep};
pub use results::{
    merge, DirReport, SessionResult, JOURNAL, MAX_RESULTS_BYTES, PHYSICS_FINGERPRINT, RESULTS,
    SUMMARY, SWEEP_COPY, VERSION, VERSION_FILE,
};
pub use run::{cap_threads, max_threads, DirOptions, THREADS_PER_CORE};
pub use spec::{
    MetricSpec, ParamValues, Scale, SweepSpec, Values, MAX_COMMANDS, MAX_SESSIONS, MAX_STEPS,
    MAX_TRIALS,
};
pub use summary::{CELL_COLUMNS, FAILURE_COLUMN, KEY_COLUMNS};
