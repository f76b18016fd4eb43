//! Learners: propose a command, learn from its outcome.
//!
//! The paper's [`E3d`], [`UniformPolicy`] and [`EpsilonGreedy`]; the drives
//! beyond it on the same per-slot softmax ([`RelaxedE3d`], [`CountBonus`],
//! [`StateMarginalMatching`]); the baselines that keep commands and vary
//! them ([`GoalBabbling`], [`Archive`], [`ArchiveReached`], [`MapElites`]); and behind [`ContinuousLearner`],
//! the learners of continuous commands ([`GaussianE3d`], [`UniformValues`],
//! [`GoalBabblingValues`], [`ArchiveValues`]). Their equations:
//! docs/algorithms.md. Implement [`Learner`] (or [`ContinuousLearner`]) to
//! plug in your own.

/// `Box<L>` is a `$learner` as `L` is: its `&self` methods, then its
/// `&mut self` methods, forwarded.
macro_rules! boxed {
    ($learner:ident
        { $(fn $m:ident(&self $(, $a:ident: $t:ty)*) $(-> $r:ty)?;)* }
        { $(fn $mm:ident(&mut self $(, $ma:ident: $mt:ty)*);)* }) => {
        impl<L: $learner + ?Sized> $learner for Box<L> {
            $(fn $m(&self $(, $a: $t)*) $(-> $r)? {
                (**self).$m($($a),*)
            })*
            $(fn $mm(&mut self $(, $ma: $mt)*) {
                (**self).$mm($($ma),*)
            })*
        }
    };
}

mod archive;
pub mod contextual;
mod drives;
mod e3d;
mod effort;
mod egreedy;
mod exp;
pub mod gaussian;
mod goal_babbling;
pub mod mutation;
mod setup;
pub mod state;
mod uniform;

pub use archive::{
    Archive, ArchiveOf, ArchiveReached, ArchiveReachedOf, ArchiveReachedValues, ArchiveValues,
    Chosen, Elites, MapElites, MapElitesOf, MapElitesValues, Reached, Variant, MAP_ELITES_INITIAL,
    REACHED_BATCH,
};
pub use contextual::{ClosedLoopE3d, ContextTargets, ContextualLearner, PerContext, QLearning};
pub use drives::{CountBonus, RelaxedE3d, StateMarginalMatching};
pub use e3d::E3d;
pub use effort::{Effort, Effortful, ValueEffort};
pub use egreedy::EpsilonGreedy;
pub use gaussian::{GaussianE3d, UniformValues};
pub use goal_babbling::{
    GoalBabbling, GoalBabblingOf, GoalBabblingValues, GOAL_MARGIN, PROGRESS_BINS, PROGRESS_WINDOW,
};
pub use setup::LearnerSetup;
pub use state::LearnerState;
pub use uniform::UniformPolicy;

use crate::command::{Command, CommandSpace};
use crate::effect::{EffectError, TargetError};
use crate::rng::SessionRng;
use crate::world::Outcome;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// A learner of open-loop commands.
///
/// A session calls [`propose`](Learner::propose), executes the command,
/// then calls [`learn`](Learner::learn) with its outcome. The learner sees
/// nothing of the world but the command space and the outcomes.
pub trait Learner {
    /// A short name (`"e3d"`, `"uniform"`, `"egreedy"`).
    fn name(&self) -> &str;

    /// Draws the next command into `command` (reused from trial to trial).
    /// Every random draw comes from `rng`, the session's generator (a
    /// concrete type, so that draws inline), through `rand::RngExt`.
    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command);

    /// Learns from the outcome of `command`.
    fn learn(&mut self, command: &Command, outcome: &Outcome);

    /// The probability of each symbol of `slot` under the current policy,
    /// if the policy draws slots independently (all the shipped learners
    /// do). Used for the exact effect distribution of a policy.
    fn slot_policy(&self, _slot: usize) -> Option<Vec<f64>> {
        None
    }
}

boxed!(Learner {
    fn name(&self) -> &str;
    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>>;
} {
    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command);
    fn learn(&mut self, command: &Command, outcome: &Outcome);
});

/// A learner of continuous commands (one value per slot, in the slot's
/// range: [`ValueSpace`](crate::command::ValueSpace)), driven as a
/// [`Learner`] is.
pub trait ContinuousLearner {
    /// A short name (`"e3d"`, `"uniform"`).
    fn name(&self) -> &str;

    /// Draws the next command into `values` (cleared first; one value per
    /// slot, each within its slot's range), every random draw from `rng`.
    fn propose(&mut self, rng: &mut SessionRng, values: &mut Vec<f64>);

    /// Learns from the outcome of `values`.
    fn learn(&mut self, values: &[f64], outcome: &Outcome);

    /// The mean and standard deviation of slot `slot`'s policy now, in the
    /// slot's unit (before the clamping to its range).
    fn slot_gaussian(&self, slot: usize) -> (f64, f64);

    /// The slots' ranges the learner proposes in, if it keeps them: a
    /// caller can check the values it is told to learn from.
    fn value_space(&self) -> Option<&crate::command::ValueSpace> {
        None
    }
}

boxed!(ContinuousLearner {
    fn name(&self) -> &str;
    fn slot_gaussian(&self, slot: usize) -> (f64, f64);
    fn value_space(&self) -> Option<&crate::command::ValueSpace>;
} {
    fn propose(&mut self, rng: &mut SessionRng, values: &mut Vec<f64>);
    fn learn(&mut self, values: &[f64], outcome: &Outcome);
});

/// A hyper-parameter out of its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{name} = {}: expected {expected}", crate::text::show_number(*value))]
pub struct ParamError {
    /// The parameter (`alpha`, `beta`, ...).
    pub name: &'static str,
    /// The value given.
    pub value: f64,
    /// The accepted range, in words.
    pub expected: &'static str,
}

/// Why a shipped learner could not be made ([`LearnerSetup::symbols`](crate::learner::LearnerSetup::symbols),
/// [`E3d::new`]): the error of the part at fault, whose message it shows.
///
/// ```
/// use e3d::learner::LearnerSetup;
/// use e3d::{LearnerKind, Params, Target};
/// use e3d::command::CommandSpace;
/// use e3d::learner::LearnerError;
/// let space = CommandSpace::repeat(2, &['a', 'b']).unwrap();
/// let bad = Params { eta: 1.5, ..Params::TASK1 };
/// let e = LearnerSetup::new(LearnerKind::E3d).params(bad).symbols(&space, 4).err().unwrap();
/// assert!(matches!(&e, LearnerError::Params(p) if p.name == "eta"));
/// assert_eq!(e.to_string(), "eta = 1.5: expected a number in (0, 1]");
/// let e = LearnerSetup::new(LearnerKind::E3d).target(Target::Weights(vec![1.0])).symbols(&space, 4).err().unwrap();
/// assert!(matches!(e, LearnerError::Target(_)));
/// ```
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LearnerError {
    /// A hyper-parameter out of its range.
    #[error(transparent)]
    Params(#[from] ParamError),
    /// The effect model cannot be made (no effects).
    #[error(transparent)]
    Effects(#[from] EffectError),
    /// The target does not fit the effects.
    #[error(transparent)]
    Target(#[from] TargetError),
    /// Contexts that do not fit (a target per context of the wrong
    /// length, no context, a table of action-values too large).
    #[error("contexts: {reason}")]
    Contexts {
        /// What is wrong.
        reason: String,
    },
    /// The learner has no continuous version ([`LearnerSetup::values`](crate::learner::LearnerSetup::values)).
    #[error("learner `{learner}` takes symbols; continuous commands take one of: {}", LearnerKind::CONTINUOUS.map(LearnerKind::as_str).join(", "))]
    NotContinuous {
        /// The learner's name.
        learner: &'static str,
    },
    /// A learner's state that cannot be set or read back (a Q of the
    /// wrong length, bytes that are not a saved state): what is wrong.
    #[error("{0}")]
    State(String),
}

impl LearnerError {
    pub(crate) fn contexts(reason: impl Into<String>) -> LearnerError {
        let reason = reason.into();
        LearnerError::Contexts { reason }
    }
}

/// The hyper-parameters of the shipped learners. Defaults: the paper's task
/// 1 (alpha 0.3, beta 1, lambda 0.03, eta 0.01), epsilon 0.1, for the
/// learners that mutate kept commands k 2, sigma 0.1, rarity 0.5 and
/// goal_progress 0, and per-move Q-learning's initial value 1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Params {
    /// Learning rate, > 0.
    pub alpha: f64,
    /// Inverse temperature of the softmax policy, > 0.
    pub beta: f64,
    /// Weight of the extrinsic reward, >= 0.
    pub lambda: f64,
    /// Rate of the running effect histogram, in (0, 1].
    pub eta: f64,
    /// Exploration rate of epsilon-greedy, in [0, 1].
    pub epsilon: f64,
    /// Slots a mutation resamples (goal babbling and the archive on
    /// symbols), >= 1; capped at the slots of more than one symbol.
    #[serde(default = "default_k")]
    pub k: usize,
    /// Standard deviation of a mutation of continuous values, in the unit
    /// coordinates of each range (`[-1, 1]`: 0.1 is 5% of the range), > 0.
    #[serde(default = "default_sigma")]
    pub sigma: f64,
    /// How strongly the archive favours rarely chosen cells: a cell is
    /// picked with weight `(1 + times chosen)^(-rarity)`; 0 is uniform, 0.5
    /// Go-Explore's `1 / sqrt(n + 1)`. >= 0.
    #[serde(default = "default_rarity")]
    pub rarity: f64,
    /// The share of goal babbling's goals chosen by learning progress
    /// rather than uniformly, in [0, 1].
    #[serde(default)]
    pub goal_progress: f64,
    /// The value every action-value of per-move Q-learning
    /// (`qlearning_moves`) starts at: 1 (optimistic: the shipped scenes'
    /// reward) by default, 0 for the plain start; finite. Written (a run's
    /// `summary.json`) only when not the default.
    #[serde(
        default = "default_initial",
        skip_serializing_if = "is_default_initial"
    )]
    pub initial: f64,
}

fn default_initial() -> f64 {
    Params::TASK1.initial
}

fn is_default_initial(v: &f64) -> bool {
    *v == Params::TASK1.initial
}

fn default_k() -> usize {
    Params::TASK1.k
}

fn default_sigma() -> f64 {
    Params::TASK1.sigma
}

fn default_rarity() -> f64 {
    Params::TASK1.rarity
}

impl Default for Params {
    fn default() -> Self {
        Params::TASK1
    }
}

impl Params {
    /// The paper's task 1 (exploration without reward).
    pub const TASK1: Params = Params {
        alpha: 0.3,
        beta: 1.0,
        lambda: 0.03,
        eta: 0.01,
        epsilon: 0.1,
        k: 2,
        sigma: 0.1,
        rarity: 0.5,
        goal_progress: 0.0,
        initial: QLearning::OPTIMISTIC,
    };
    /// The paper's task 2 (sparse reward): beta = 100.
    pub const TASK2: Params = Params {
        beta: 100.0,
        ..Params::TASK1
    };

    /// The hyper-parameters' names, in the order of [`named`](Self::named),
    /// as [`LearnerKind::params`] and a sweep's columns name them.
    pub const NAMES: [&'static str; 10] = [
        "alpha",
        "beta",
        "lambda",
        "eta",
        "epsilon",
        "k",
        "sigma",
        "rarity",
        "goal_progress",
        "initial",
    ];

    /// The hyper-parameters a sweep spans by axes of values (the first
    /// five of [`NAMES`](Self::NAMES)), in the order of its columns.
    pub const SWEPT: [&'static str; 5] = ["alpha", "beta", "lambda", "eta", "epsilon"];

    /// Each hyper-parameter by name, in the order of [`NAMES`](Self::NAMES)
    /// (`k` as a float).
    ///
    /// ```
    /// use e3d::Params;
    /// let p = Params { beta: 100.0, ..Params::TASK1 };
    /// assert_eq!(p.named()[1], ("beta", 100.0));
    /// let changed: Vec<&str> = p.named().iter().zip(Params::TASK1.named())
    ///     .filter(|(a, b)| a.1 != b.1).map(|(a, _)| a.0).collect();
    /// assert_eq!(changed, ["beta"]);
    /// // every learner's parameters are among them
    /// for kind in e3d::LearnerKind::ALL {
    ///     assert!(kind.params().iter().all(|n| Params::NAMES.contains(n)));
    /// }
    /// ```
    pub fn named(&self) -> [(&'static str, f64); 10] {
        let v = [
            self.alpha,
            self.beta,
            self.lambda,
            self.eta,
            self.epsilon,
            self.k as f64,
            self.sigma,
            self.rarity,
            self.goal_progress,
            self.initial,
        ];
        std::array::from_fn(|i| (Self::NAMES[i], v[i]))
    }

    /// Checks every range: alpha > 0, beta > 0, lambda >= 0,
    /// 0 < eta <= 1, 0 <= epsilon <= 1, k >= 1, sigma > 0, rarity >= 0,
    /// 0 <= goal_progress <= 1, all finite (initial any finite number).
    pub fn validate(&self) -> Result<(), ParamError> {
        type Rule = (&'static str, fn(f64) -> bool);
        let pos: Rule = ("a finite number > 0", |v| v > 0.0);
        let non_neg: Rule = ("a finite number >= 0", |v| v >= 0.0);
        let unit: Rule = ("a number in [0, 1]", |v| (0.0..=1.0).contains(&v));
        let eta: Rule = ("a number in (0, 1]", |v| v > 0.0 && v <= 1.0);
        let whole: Rule = ("a whole number >= 1", |v| v >= 1.0);
        let finite: Rule = ("a finite number", |_| true);
        let checks = [
            ("alpha", self.alpha, pos),
            ("beta", self.beta, pos),
            ("lambda", self.lambda, non_neg),
            ("eta", self.eta, eta),
            ("epsilon", self.epsilon, unit),
            ("k", self.k as f64, whole),
            ("sigma", self.sigma, pos),
            ("rarity", self.rarity, non_neg),
            ("goal_progress", self.goal_progress, unit),
            ("initial", self.initial, finite),
        ];
        match checks
            .into_iter()
            .find(|&(_, value, (_, ok))| !(ok(value) && value.is_finite()))
        {
            Some((name, value, (expected, _))) => Err(ParamError {
                name,
                value,
                expected,
            }),
            None => Ok(()),
        }
    }
}

/// `LearnerKind`, its [`ALL`](LearnerKind::ALL) and its names.
macro_rules! learner_kinds {
    ($($(#[$doc:meta])* $kind:ident $name:literal,)*) => {
        /// The shipped learners, by name.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
        #[serde(rename_all = "snake_case")]
        pub enum LearnerKind {
            $($(#[$doc])* $kind,)*
        }

        impl LearnerKind {
            /// Every kind: the paper's three, the drives beyond it, the
            /// baselines that mutate kept commands, then per-move
            /// Q-learning.
            pub const ALL: [LearnerKind; 11] = [$(LearnerKind::$kind),*];

            /// The name used on the command line and in results.
            pub fn as_str(self) -> &'static str {
                match self {
                    $(LearnerKind::$kind => $name,)*
                }
            }
        }
    };
}

learner_kinds! {
    /// [`E3d`].
    E3d "e3d",
    /// [`UniformPolicy`].
    Uniform "uniform",
    /// [`EpsilonGreedy`].
    Egreedy "egreedy",
    /// [`RelaxedE3d`].
    E3dRelax "e3d_relax",
    /// [`CountBonus`].
    Count "count",
    /// [`StateMarginalMatching`].
    Smm "smm",
    /// [`GoalBabbling`].
    GoalBabbling "goal_babbling",
    /// [`Archive`].
    Archive "archive",
    /// [`ArchiveReached`].
    ArchiveReached "archive_reached",
    /// [`MapElites`].
    MapElites "map_elites",
    /// Per-move Q-learning ([`QLearning::optimistic`]): episodes of
    /// one-move commands, each chosen from the cell it starts in.
    QlearningMoves "qlearning_moves",
}

impl LearnerKind {
    /// The parameters of [`Params`] this kind reads (`alpha`, `beta`,
    /// `lambda`, `eta`, `epsilon`, `k`, `sigma`, `rarity`,
    /// `goal_progress`, `initial`); the others it ignores.
    ///
    /// ```
    /// use e3d::LearnerKind;
    /// assert_eq!(LearnerKind::E3d.params(), ["alpha", "beta", "lambda", "eta"]);
    /// assert!(LearnerKind::Uniform.params().is_empty());
    /// ```
    pub fn params(self) -> &'static [&'static str] {
        match self {
            LearnerKind::E3d | LearnerKind::E3dRelax => &["alpha", "beta", "lambda", "eta"],
            LearnerKind::Count | LearnerKind::Smm => &["alpha", "beta", "lambda"],
            LearnerKind::Egreedy => &["alpha", "epsilon"],
            LearnerKind::Uniform => &[],
            LearnerKind::GoalBabbling => &["k", "sigma", "goal_progress"],
            LearnerKind::Archive | LearnerKind::ArchiveReached => &["k", "sigma", "rarity"],
            LearnerKind::MapElites => &["k", "sigma"],
            LearnerKind::QlearningMoves => &["alpha", "epsilon", "initial"],
        }
    }

    /// The kinds with a learner of continuous commands
    /// ([`LearnerSetup::values`]).
    pub const CONTINUOUS: [LearnerKind; 6] = [
        LearnerKind::E3d,
        LearnerKind::Uniform,
        LearnerKind::GoalBabbling,
        LearnerKind::Archive,
        LearnerKind::ArchiveReached,
        LearnerKind::MapElites,
    ];
}

impl fmt::Display for LearnerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.as_str())
    }
}

/// A name that is not one of [`LearnerKind::ALL`]'s (what
/// [`LearnerKind::from_str`](std::str::FromStr::from_str) refuses); its
/// message names the built-in learners.
///
/// ```
/// use e3d::LearnerKind;
/// use e3d::learner::ParseLearnerError;
/// let e: ParseLearnerError = "e3d-relax".parse::<LearnerKind>().unwrap_err();
/// assert_eq!(e.input(), "e3d-relax");
/// assert!(e.to_string().starts_with("unknown learner `e3d-relax`; expected one of: e3d, "));
/// ```
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
#[error("unknown learner `{input}`; expected one of: {}", LearnerKind::ALL.map(|k| k.as_str()).join(", "))]
pub struct ParseLearnerError {
    input: String,
}

impl ParseLearnerError {
    /// The name that was refused.
    pub fn input(&self) -> &str {
        &self.input
    }
}

impl FromStr for LearnerKind {
    type Err = ParseLearnerError;
    fn from_str(s: &str) -> Result<Self, ParseLearnerError> {
        LearnerKind::ALL
            .into_iter()
            .find(|k| k.as_str() == s)
            .ok_or_else(|| ParseLearnerError {
                input: s.to_string(),
            })
    }
}

/// An index drawn with probability proportional to `weights` (one `f64`
/// of `rng`): the first whose running sum passes `u x total`, else the last.
pub(crate) fn draw_weighted(
    weights: impl Iterator<Item = f64> + Clone,
    rng: &mut SessionRng,
) -> usize {
    let total: f64 = weights.clone().sum();
    let u = rand::RngExt::random::<f64>(rng) * total;
    let mut acc = 0.0;
    let mut last = 0;
    for (i, w) in weights.enumerate() {
        acc += w;
        if u < acc {
            return i;
        }
        last = i;
    }
    last
}

/// Flat per-slot table storage: `offsets[slot] + symbol`.
pub(crate) fn slot_offsets(space: &CommandSpace) -> Vec<usize> {
    let ends = space.sizes().scan(0, |at, k| {
        *at += k;
        Some(*at)
    });
    std::iter::once(0).chain(ends).collect()
}
