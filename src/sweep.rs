//! Sweeps: grids of sessions over scenes, learners and hyper-parameters.
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
//! starts; [`Sweep::cells`] lists the grid; [`Sweep::sessions`] lists every
//! session with its seed; [`Sweep::run`] runs them all in parallel and
//! returns the results in canonical order; [`Sweep::run_to_dir`] is the
//! resumable, shardable form behind `e3d sweep`.
//!
//! # Cells
//!
//! The cells are the product, in this order, of the scenes, the learners,
//! the `use_reward` values and the values of `alpha`, `beta`, `lambda`,
//! `eta` and `epsilon`, each in the order of the file. A learner's grid
//! spans only the parameters it uses ([`uses_param`]): the uniform policy
//! uses none, epsilon-greedy `alpha` and `epsilon`, E3D the four others.
//! A parameter a learner does not use is left empty in the results.
//!
//! # Seeds
//!
//! Session `i` of a cell (`i` in `0..sessions`) is seeded with
//! [`session_seed`]`(base_seed, identity)`, where the identity is the text
//! `scene=S;learner=L;use_reward=B;alpha=A;beta=B;lambda=L;eta=E;epsilon=P;session=I`
//! with every number written as in `results.csv` (Rust's shortest
//! round-trip form, `-` for an unused parameter). A session's seed thus
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

use crate::effect::Target;
use crate::learner::{LearnerKind, Params};
use crate::scene::{ron_options, Invalid, Scene, SceneError};
use crate::session::{run_lockstep_into, run_session_into, RunningMetrics, SessionConfig};
use crate::world::{ExecOptions, Executor, OutcomeTable, Strategy, Workload, World, WorldError};
use journal::{Journal, JournalHeader};
use rayon::prelude::*;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// The names of the hyper-parameters, in the order of the cells and columns.
pub const PARAM_NAMES: [&str; 5] = ["alpha", "beta", "lambda", "eta", "epsilon"];

/// The columns of `results.csv` before the metrics.
pub const KEY_COLUMNS: [&str; 10] = [
    "scene",
    "learner",
    "use_reward",
    "alpha",
    "beta",
    "lambda",
    "eta",
    "epsilon",
    "session",
    "seed",
];

/// The last column of `results.csv`: empty, or why the session failed.
pub const FAILURE_COLUMN: &str = "failure";

/// The number of leading [`KEY_COLUMNS`] that identify a cell (all but
/// `session` and `seed`).
pub const CELL_COLUMNS: usize = 8;

/// The largest number of sessions a sweep may hold: its plan keeps every
/// cell and session in memory (about 150 bytes each, so at most about
/// 1.5 GB), and is refused before any is made when it would be larger.
pub const MAX_SESSIONS: usize = 10_000_000;

/// The largest number of trials per session (the bound of `e3d run
/// --trials`).
pub const MAX_TRIALS: usize = 100_000_000;

/// The largest number of steps of a range.
pub const MAX_STEPS: usize = 100_000;

/// Whether `learner` uses the hyper-parameter `param` (one of
/// [`PARAM_NAMES`]).
///
/// ```
/// use e3d::{sweep::uses_param, LearnerKind};
/// assert!(uses_param(LearnerKind::E3d, "eta"));
/// assert!(!uses_param(LearnerKind::Egreedy, "beta"));
/// assert!(!uses_param(LearnerKind::Uniform, "alpha"));
/// ```
pub fn uses_param(learner: LearnerKind, param: &str) -> bool {
    match learner {
        LearnerKind::E3d => matches!(param, "alpha" | "beta" | "lambda" | "eta"),
        LearnerKind::Egreedy => matches!(param, "alpha" | "epsilon"),
        LearnerKind::Uniform => false,
    }
}

/// 64-bit FNV-1a of `bytes` (offset basis `0xcbf29ce484222325`, prime
/// `0x100000001b3`).
///
/// ```
/// assert_eq!(e3d::sweep::fnv1a64(b""), 0xcbf29ce484222325);
/// assert_eq!(e3d::sweep::fnv1a64(b"a"), 0xaf63dc4c8601ec8c);
/// ```
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The SplitMix64 finaliser of `x + 0x9e3779b97f4a7c15` (Steele, Lea and
/// Flood 2014): one step of the SplitMix64 generator seeded with `x`.
///
/// ```
/// assert_eq!(e3d::sweep::splitmix64(0), 0xe220a8397b1dcdaf);
/// ```
pub fn splitmix64(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The seed of a session: `splitmix64(splitmix64(base) ^ fnv1a64(identity))`,
/// where `identity` is the session's canonical text (see the module docs).
pub fn session_seed(base: u64, identity: &str) -> u64 {
    splitmix64(splitmix64(base) ^ fnv1a64(identity.as_bytes()))
}

/// A number as written in results and identities: Rust's shortest
/// round-trip decimal form (`0.3`, `100`, `0.001`).
pub fn format_number(v: f64) -> String {
    format!("{v}")
}

// ---------------------------------------------------------------------------
// The sweep file
// ---------------------------------------------------------------------------

/// The values of one hyper-parameter: a single number, a list, or a range.
///
/// In RON: `0.3`, `[0.1, 0.3]`, `(scale: Linear, from: 0.01, to: 0.1,
/// steps: 4)` or `(scale: Log, from: 1, to: 1000, steps: 7)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Values {
    /// The values given, in order.
    List(Vec<f64>),
    /// `steps` values from `from` to `to` (both included), evenly spaced on
    /// a linear or a logarithmic scale.
    Range {
        /// Linear or logarithmic spacing.
        scale: Scale,
        /// The first value.
        from: f64,
        /// The last value.
        to: f64,
        /// How many values (1: `from` alone).
        steps: usize,
    },
}

/// The spacing of a [`Values::Range`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Scale {
    /// `from + (to - from) k / (steps - 1)`.
    Linear,
    /// `from (to / from)^(k / (steps - 1))`; `from` and `to` must be > 0.
    Log,
}

impl Values {
    /// The values, in order. A range's values are rounded to 12
    /// significant digits (so that `(scale: Log, from: 1, to: 1000, steps:
    /// 4)` gives 1, 10, 100, 1000 and not 99.99999999999996); a log range
    /// is evenly spaced in `log10`.
    ///
    /// ```
    /// use e3d::sweep::{Scale, Values};
    /// let v = Values::Range { scale: Scale::Log, from: 1.0, to: 1000.0, steps: 7 };
    /// assert_eq!(v.values()[2], 10.0);
    /// assert_eq!(v.values()[1], 3.16227766017);
    /// let v = Values::Range { scale: Scale::Linear, from: 0.01, to: 0.1, steps: 4 };
    /// assert_eq!(v.values(), vec![0.01, 0.04, 0.07, 0.1]);
    /// ```
    pub fn values(&self) -> Vec<f64> {
        match *self {
            Values::List(ref v) => v.clone(),
            Values::Range {
                scale,
                from,
                to,
                steps,
            } => (0..steps)
                .map(|k| {
                    if steps == 1 {
                        return from;
                    }
                    let (a, b) = ((steps - 1 - k) as f64, k as f64);
                    let d = (steps - 1) as f64;
                    let v = match scale {
                        Scale::Linear => (from * a + to * b) / d,
                        Scale::Log => 10f64.powf((from.log10() * a + to.log10() * b) / d),
                    };
                    round12(v)
                })
                .collect(),
        }
    }
}

/// `v` rounded to 12 significant digits.
fn round12(v: f64) -> f64 {
    format!("{v:.11e}").parse().unwrap_or(v)
}

impl<'de> Deserialize<'de> for Values {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Values, D::Error> {
        struct V;
        const FIELDS: &[&str] = &["scale", "from", "to", "steps"];
        impl<'de> Visitor<'de> for V {
            type Value = Values;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a number, a list of numbers `[a, b, ...]`, or a range \
                     `(scale: Linear or Log, from: a, to: b, steps: n)`",
                )
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<Values, E> {
                Ok(Values::List(vec![v]))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<Values, E> {
                Ok(Values::List(vec![v as f64]))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<Values, E> {
                Ok(Values::List(vec![v as f64]))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut s: A) -> Result<Values, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = s.next_element::<f64>()? {
                    v.push(x);
                }
                Ok(Values::List(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<Values, A::Error> {
                let (mut scale, mut from, mut to, mut steps) = (None, None, None, None);
                while let Some(key) = m.next_key::<String>()? {
                    let dup = match key.as_str() {
                        "scale" => scale.replace(m.next_value::<Scale>()?).is_some(),
                        "from" => from.replace(m.next_value::<f64>()?).is_some(),
                        "to" => to.replace(m.next_value::<f64>()?).is_some(),
                        "steps" => steps.replace(m.next_value::<usize>()?).is_some(),
                        _ => return Err(de::Error::unknown_field(&key, FIELDS)),
                    };
                    if dup {
                        return Err(de::Error::custom(format_args!(
                            "field `{key}` given twice in a range"
                        )));
                    }
                }
                Ok(Values::Range {
                    scale: scale.ok_or_else(|| {
                        de::Error::custom(
                            "missing field `scale` in a range; expected `scale: Linear` or `scale: Log`",
                        )
                    })?,
                    from: from.ok_or_else(|| de::Error::missing_field("from"))?,
                    to: to.ok_or_else(|| de::Error::missing_field("to"))?,
                    steps: steps.ok_or_else(|| de::Error::missing_field("steps"))?,
                })
            }
        }
        d.deserialize_any(V)
    }
}

/// The values of each hyper-parameter. A parameter left out takes the
/// default of `e3d run` ([`Params::TASK1`]: alpha 0.3, beta 1, lambda 0.03,
/// eta 0.01, epsilon 0.1).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "params")]
pub struct ParamValues {
    /// Learning rate.
    #[serde(default)]
    pub alpha: Option<Values>,
    /// Inverse temperature.
    #[serde(default)]
    pub beta: Option<Values>,
    /// Weight of the extrinsic reward.
    #[serde(default)]
    pub lambda: Option<Values>,
    /// Rate of the effect histogram.
    #[serde(default)]
    pub eta: Option<Values>,
    /// Exploration rate of epsilon-greedy.
    #[serde(default)]
    pub epsilon: Option<Values>,
}

impl ParamValues {
    fn get(&self, name: &str) -> Option<&Values> {
        match name {
            "alpha" => self.alpha.as_ref(),
            "beta" => self.beta.as_ref(),
            "lambda" => self.lambda.as_ref(),
            "eta" => self.eta.as_ref(),
            _ => self.epsilon.as_ref(),
        }
    }
}

fn param_of(p: &Params, i: usize) -> f64 {
    [p.alpha, p.beta, p.lambda, p.eta, p.epsilon][i]
}

fn set_param(p: &mut Params, i: usize, v: f64) {
    match i {
        0 => p.alpha = v,
        1 => p.beta = v,
        2 => p.lambda = v,
        3 => p.eta = v,
        _ => p.epsilon = v,
    }
}

/// A metric kept for each session (a column of `results.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MetricSpec {
    /// Normalised entropy of the effects over all trials.
    NormalizedEntropy,
    /// Normalised entropy over the last 1000 trials.
    #[serde(rename = "normalized_entropy_last_1000")]
    NormalizedEntropyLast1000,
    /// KL divergence of the effects to the target, in nats.
    KlToTarget,
    /// Number of distinct effects reached.
    DistinctEffects,
    /// The sum of rewards over the first `t` trials (column
    /// `cumulative_reward_at_T`).
    CumulativeReward(usize),
    /// The 1-based trial of the first reward (empty when none).
    FirstRewardTrial,
}

impl MetricSpec {
    /// The column name.
    pub fn column(&self) -> String {
        match self {
            MetricSpec::NormalizedEntropy => "normalized_entropy".into(),
            MetricSpec::NormalizedEntropyLast1000 => "normalized_entropy_last_1000".into(),
            MetricSpec::KlToTarget => "kl_to_target".into(),
            MetricSpec::DistinctEffects => "distinct_effects".into(),
            MetricSpec::CumulativeReward(t) => format!("cumulative_reward_at_{t}"),
            MetricSpec::FirstRewardTrial => "first_reward_trial".into(),
        }
    }

    /// The metrics kept when a sweep names none: all of them, with the
    /// cumulative reward at the last trial.
    pub fn defaults(trials: usize) -> Vec<MetricSpec> {
        vec![
            MetricSpec::NormalizedEntropy,
            MetricSpec::NormalizedEntropyLast1000,
            MetricSpec::KlToTarget,
            MetricSpec::DistinctEffects,
            MetricSpec::CumulativeReward(trials),
            MetricSpec::FirstRewardTrial,
        ]
    }
}

fn default_use_reward() -> Vec<bool> {
    vec![true]
}

/// A sweep file, as written (see `docs/sweeps.md`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "Sweep")]
pub struct SweepSpec {
    /// A name, for people.
    #[serde(default)]
    pub name: String,
    /// A sentence or two, for people.
    #[serde(default)]
    pub description: String,
    /// Scene files (relative to the sweep file's folder) or built-in names.
    pub scenes: Vec<String>,
    /// The learners.
    pub learners: Vec<LearnerKind>,
    /// Whether the learners see the reward: `[true]`, `[false]` or both
    /// (default `[true]`).
    #[serde(default = "default_use_reward")]
    pub use_reward: Vec<bool>,
    /// The values of each hyper-parameter.
    #[serde(default)]
    pub params: ParamValues,
    /// Sessions (seeds) per cell, >= 1.
    pub sessions: usize,
    /// Trials per session, >= 1.
    pub trials: usize,
    /// The base seed every session's seed is derived from.
    #[serde(default)]
    pub seed: u64,
    /// The metrics to keep (default: [`MetricSpec::defaults`]).
    #[serde(default)]
    pub metrics: Option<Vec<MetricSpec>>,
}

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

/// Why a sweep could not be loaded, run, resumed or merged.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// A mistake in the sweep file (or in a scene it names), with file, line
    /// and column.
    #[error("{0}")]
    Input(#[from] SceneError),
    /// A session failed in its world.
    #[error("{0}")]
    World(#[from] WorldError),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What failed.
        source: std::io::Error,
    },
    /// An output folder that cannot be used as asked (exists, holds another
    /// sweep, is incomplete, ...).
    #[error("{0}")]
    Output(String),
    /// Anything else that stops a sweep (a learner refusing its parameters,
    /// a thread pool that cannot start, ...).
    #[error("{0}")]
    Other(String),
}

pub(crate) fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> SweepError + '_ {
    move |source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    }
}

// ---------------------------------------------------------------------------
// Cells and sessions
// ---------------------------------------------------------------------------

/// One cell of the grid: a scene, a learner, a reward setting and one value
/// of each hyper-parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// The cell's index in canonical order.
    pub index: usize,
    /// The index of the scene in [`Sweep::scenes`].
    pub scene: usize,
    /// The learner.
    pub learner: LearnerKind,
    /// Whether the learner sees the reward.
    pub use_reward: bool,
    /// The hyper-parameters (those the learner does not use hold the first
    /// value of their list; they have no effect).
    pub params: Params,
    /// Which of [`PARAM_NAMES`] the learner uses.
    pub used: [bool; 5],
}

/// One session of a sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SessionSpec {
    /// The session's index in canonical order (`cell * sessions + replicate`).
    pub index: usize,
    /// The index of its cell.
    pub cell: usize,
    /// Which session of its cell (`0..sessions`).
    pub replicate: usize,
    /// Its seed ([`session_seed`]).
    pub seed: u64,
}

/// The result of one session: its identity and the kept metrics.
#[derive(Debug, Clone, PartialEq)]
pub struct SessionResult {
    /// The session.
    pub session: SessionSpec,
    /// One value per [`Sweep::metric_columns`] (`None`: no first reward, or
    /// a failed session).
    pub values: Vec<Option<f64>>,
    /// Why the session failed (its world reported an error, for example a
    /// physics blow-up naming the command); `None` for a session that ran.
    /// A failed session is recorded, not fatal: the sweep goes on.
    pub failure: Option<String>,
}

/// A shard `K/N` of a sweep: the sessions whose index `i` has
/// `i % N == K - 1` (K is 1-based, as Slurm array task ids usually are).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which part, `1..=n`.
    pub k: usize,
    /// How many parts.
    pub n: usize,
}

impl Shard {
    /// The whole sweep (`1/1`).
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// Whether session `index` belongs to this shard.
    pub fn contains(&self, index: usize) -> bool {
        index % self.n == self.k - 1
    }

    /// How many of `total` sessions belong to this shard.
    pub fn count(&self, total: usize) -> usize {
        // the indices k-1, k-1+n, ... below total; no `total + n`, which
        // overflowed for n near usize::MAX (1/18446744073709551615 had
        // "0 sessions")
        match total.checked_sub(self.k) {
            Some(rest) => rest / self.n + 1,
            None => 0,
        }
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl FromStr for Shard {
    type Err = String;
    /// `"K/N"` with `1 <= K <= N`.
    fn from_str(s: &str) -> Result<Shard, String> {
        let bad = || format!("`{s}`: expected K/N with 1 <= K <= N, for example 2/8");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// A checked sweep: the file, its scenes and its cells.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The file as written.
    pub spec: SweepSpec,
    /// The text of the file (copied into output folders).
    pub text: String,
    /// The file's name, for messages.
    pub file: String,
    scenes: Vec<Scene>,
    metrics: Vec<MetricSpec>,
    cells: Vec<Cell>,
    exec: ExecOptions,
    notices: Option<Notices>,
    trials_done: Option<std::sync::Arc<std::sync::atomic::AtomicU64>>,
}

/// Where a sweep tells how it obtains outcomes (one line each).
#[derive(Clone)]
struct Notices(std::sync::Arc<dyn Fn(&str) + Send + Sync>);

impl fmt::Debug for Notices {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("Notices")
    }
}

fn invalid(
    file: &str,
    text: &str,
    field: &str,
    anchor: Option<&str>,
    expected: &str,
) -> SweepError {
    SweepError::Input(SceneError::from_validation(
        file,
        text,
        Invalid::at(field, anchor, expected),
    ))
}

impl Sweep {
    /// Loads and checks a sweep file; scene paths are relative to its folder.
    pub fn load(path: impl AsRef<Path>) -> Result<Sweep, SweepError> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = crate::scene::read_text(path, "sweep")?;
        Sweep::parse(&text, &file, path.parent())
    }

    /// Parses and checks sweep text; `file` names it in errors, `base`
    /// is the folder scene paths are relative to (the current folder when
    /// `None`).
    pub fn parse(text: &str, file: &str, base: Option<&Path>) -> Result<Sweep, SweepError> {
        let text = crate::scene::prepare_text(text, file, "sweep")?;
        if text.trim().is_empty() {
            return Err(SceneError::empty(file, "sweep").into());
        }
        let spec: SweepSpec = ron_options()
            .from_str(text)
            .map_err(|e| SceneError::from_ron(file, text, e))?;
        let bad = |field: &str, anchor: Option<&str>, expected: &str| {
            invalid(file, text, field, anchor, expected)
        };
        if spec.scenes.is_empty() {
            return Err(bad("scenes", None, "at least one scene, found none"));
        }
        if spec.learners.is_empty() {
            return Err(bad(
                "learners",
                None,
                "at least one learner (e3d, uniform, egreedy), found none",
            ));
        }
        for (i, l) in spec.learners.iter().enumerate() {
            if spec.learners[..i].contains(l) {
                return Err(bad(
                    "learners",
                    None,
                    &format!("each learner once, but `{l}` appears twice"),
                ));
            }
        }
        if spec.use_reward.is_empty() {
            return Err(bad(
                "use_reward",
                None,
                "[true], [false] or [false, true], found []",
            ));
        }
        if spec.use_reward.len() > 2
            || (spec.use_reward.len() == 2 && spec.use_reward[0] == spec.use_reward[1])
        {
            return Err(bad("use_reward", None, "each of true and false once"));
        }
        if spec.sessions == 0 {
            return Err(bad(
                "sessions",
                None,
                "at least 1 session per cell, found 0",
            ));
        }
        if spec.trials == 0 {
            return Err(bad("trials", None, "at least 1 trial per session, found 0"));
        }
        if spec.trials > MAX_TRIALS {
            return Err(bad(
                "trials",
                None,
                &format!(
                    "at most {} trials per session (as `e3d run --trials`), found {}",
                    MAX_TRIALS, spec.trials
                ),
            ));
        }
        // the hyper-parameters
        let mut axes: Vec<Vec<f64>> = Vec::with_capacity(5);
        for (i, name) in PARAM_NAMES.iter().enumerate() {
            let values = match spec.params.get(name) {
                None => vec![param_of(&Params::TASK1, i)],
                Some(v) => {
                    if let Values::Range {
                        scale,
                        from,
                        to,
                        steps,
                    } = *v
                    {
                        if steps == 0 {
                            return Err(bad(
                                name,
                                None,
                                "a range of at least 1 step, found steps: 0",
                            ));
                        }
                        if steps > MAX_STEPS {
                            return Err(bad(
                                name,
                                None,
                                &format!(
                                    "a range of at most {MAX_STEPS} steps, found steps: {steps}"
                                ),
                            ));
                        }
                        if !(from.is_finite() && to.is_finite()) {
                            return Err(bad(name, None, "finite bounds `from` and `to`"));
                        }
                        if scale == Scale::Log && (from <= 0.0 || to <= 0.0) {
                            return Err(bad(
                                name,
                                None,
                                &format!(
                                    "a log range between two numbers > 0, found from: {from}, to: {to} (a log range cannot reach or cross zero)"
                                ),
                            ));
                        }
                    }
                    let values = v.values();
                    if values.is_empty() {
                        return Err(bad(name, None, "at least one value, found an empty list"));
                    }
                    for (j, x) in values.iter().enumerate() {
                        if values[..j].contains(x) {
                            return Err(bad(
                                name,
                                None,
                                &format!("distinct values, but {x} appears twice"),
                            ));
                        }
                        let mut p = Params::TASK1;
                        set_param(&mut p, i, *x);
                        if let Err(e) = p.validate() {
                            return Err(bad(name, None, &format!("{}, found {x}", e.expected)));
                        }
                    }
                    values
                }
            };
            axes.push(values);
        }
        // metrics
        let metrics = spec
            .metrics
            .clone()
            .unwrap_or_else(|| MetricSpec::defaults(spec.trials));
        if metrics.is_empty() {
            return Err(bad("metrics", None, "at least one metric, found none"));
        }
        for (i, m) in metrics.iter().enumerate() {
            if let MetricSpec::CumulativeReward(t) = *m {
                if t == 0 || t > spec.trials {
                    return Err(bad(
                        "metrics",
                        Some("cumulative_reward"),
                        &format!(
                            "cumulative_reward(T) with T in 1..={} (the trials), found {t}",
                            spec.trials
                        ),
                    ));
                }
            }
            if metrics[..i].contains(m) {
                return Err(bad(
                    "metrics",
                    None,
                    &format!("each metric once, but `{}` appears twice", m.column()),
                ));
            }
        }
        // scenes
        let mut scenes: Vec<Scene> = Vec::new();
        for name in &spec.scenes {
            let scene = resolve_scene(name, base).map_err(|e| match e {
                SceneResolve::NotFound(msg) => bad("scenes", Some(&format!("\"{name}\"")), &msg),
                SceneResolve::Scene(e) => SweepError::Input(e),
            })?;
            if scene.name.contains([',', '"', '\n', '\r']) {
                return Err(bad(
                    "scenes",
                    Some(&format!("\"{name}\"")),
                    &format!(
                        "scenes whose name has no comma, quote or line break (for CSV), found `{}`",
                        scene.name
                    ),
                ));
            }
            if scenes.iter().any(|s| s.name == scene.name) {
                return Err(bad(
                    "scenes",
                    Some(&format!("\"{name}\"")),
                    &format!("each scene once, but `{}` appears twice", scene.name),
                ));
            }
            scenes.push(scene);
        }
        // the size, before making the cells
        let mut num_cells: usize = 0;
        for &learner in &spec.learners {
            let per: usize = (0..5)
                .filter(|&i| uses_param(learner, PARAM_NAMES[i]))
                .fold(1usize, |acc, i| acc.saturating_mul(axes[i].len()));
            num_cells = num_cells.saturating_add(per.saturating_mul(spec.use_reward.len()));
        }
        let num_cells = num_cells.saturating_mul(scenes.len());
        if num_cells.saturating_mul(spec.sessions) > MAX_SESSIONS {
            return Err(bad(
                "sessions",
                None,
                &format!(
                    "at most {MAX_SESSIONS} sessions in all (a sweep's plan holds each one in memory), found {num_cells} cells x {}",
                    spec.sessions
                ),
            ));
        }
        // cells
        let mut cells = Vec::with_capacity(num_cells);
        for (si, _) in scenes.iter().enumerate() {
            for &learner in &spec.learners {
                let used: [bool; 5] = std::array::from_fn(|i| uses_param(learner, PARAM_NAMES[i]));
                let dims: Vec<usize> = (0..5)
                    .map(|i| if used[i] { axes[i].len() } else { 1 })
                    .collect();
                let count: usize = dims.iter().product();
                for &use_reward in &spec.use_reward {
                    for mut k in 0..count {
                        let mut params = Params::TASK1;
                        let mut pick = [0usize; 5];
                        for i in (0..5).rev() {
                            pick[i] = k % dims[i];
                            k /= dims[i];
                        }
                        for i in 0..5 {
                            set_param(&mut params, i, axes[i][pick[i]]);
                        }
                        cells.push(Cell {
                            index: cells.len(),
                            scene: si,
                            learner,
                            use_reward,
                            params,
                            used,
                        });
                    }
                }
            }
        }
        Ok(Sweep {
            spec,
            text: text.to_string(),
            file: file.to_string(),
            scenes,
            metrics,
            cells,
            exec: ExecOptions::default(),
            notices: None,
            trials_done: None,
        })
    }

    /// Keeps the outcome tables of the sweep's scenes in the folder `dir`
    /// (see [`OutcomeTable::cached`]): a physics scene's commands are then
    /// simulated once for every run, resume and shard that shares the
    /// folder. The results are the same bytes with or without it.
    pub fn with_table_cache(mut self, dir: impl Into<PathBuf>) -> Self {
        self.exec.cache = Some(dir.into());
        self
    }

    /// Caps the outcome memo of each scene at `cap` entries (0: no memo;
    /// default [`DEFAULT_MEMO_CAP`]). The results are the same bytes
    /// whatever the cap; only the time changes.
    pub fn with_memo_cap(mut self, cap: usize) -> Self {
        self.exec.memo_cap = cap;
        self
    }

    /// Uses `strategy` for every scene where it can be used, whatever it
    /// costs (`None`: the cheapest, the default). The results are the same
    /// bytes whatever the strategy.
    pub fn with_strategy(mut self, strategy: Option<Strategy>) -> Self {
        self.exec.force = strategy;
        self
    }

    /// Calls `f` with one line for each scene saying how its outcomes are
    /// obtained (table, memo or live, and why), and after the run what the
    /// memo simulated and kept. `e3d sweep` prints them on stderr.
    pub fn with_notices(mut self, f: impl Fn(&str) + Send + Sync + 'static) -> Self {
        self.notices = Some(Notices(std::sync::Arc::new(f)));
        self
    }

    /// Adds every trial run to `counter` as sessions go (from the worker
    /// threads, every 256 lockstep trials, or when a session on a table
    /// ends): progress finer than whole sessions, for sessions in lockstep
    /// that all end together.
    pub fn with_trial_counter(
        mut self,
        counter: std::sync::Arc<std::sync::atomic::AtomicU64>,
    ) -> Self {
        self.trials_done = Some(counter);
        self
    }

    fn count_trials(&self, n: u64) {
        if let Some(c) = &self.trials_done {
            c.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
        }
    }

    fn notice(&self, line: &str) {
        if let Some(f) = &self.notices {
            (f.0)(line);
        }
    }

    /// The scenes, in the order of the file.
    pub fn scenes(&self) -> &[Scene] {
        &self.scenes
    }

    /// The cells, in canonical order.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// The kept metrics.
    pub fn metrics(&self) -> &[MetricSpec] {
        &self.metrics
    }

    /// The metric column names.
    pub fn metric_columns(&self) -> Vec<String> {
        self.metrics.iter().map(MetricSpec::column).collect()
    }

    /// The header line of `results.csv` (without line break).
    pub fn results_header(&self) -> String {
        let mut cols: Vec<String> = KEY_COLUMNS.iter().map(|s| s.to_string()).collect();
        cols.extend(self.metric_columns());
        cols.push(FAILURE_COLUMN.to_string());
        cols.join(",")
    }

    /// The number of sessions.
    pub fn num_sessions(&self) -> usize {
        self.cells.len() * self.spec.sessions
    }

    /// The cell columns of `cell` (scene, learner, use_reward, then the five
    /// parameters, empty when unused), as written in the CSV files.
    pub fn cell_fields(&self, cell: &Cell) -> Vec<String> {
        let mut f = vec![
            self.scenes[cell.scene].name.clone(),
            cell.learner.as_str().to_string(),
            cell.use_reward.to_string(),
        ];
        for i in 0..5 {
            f.push(if cell.used[i] {
                format_number(param_of(&cell.params, i))
            } else {
                String::new()
            });
        }
        f
    }

    /// The canonical identity text of session `replicate` of `cell` (see
    /// the module docs); its seed is `session_seed(base, identity)`.
    pub fn identity(&self, cell: &Cell, replicate: usize) -> String {
        let f = self.cell_fields(cell);
        let mut s = format!("scene={};learner={};use_reward={}", f[0], f[1], f[2]);
        for (i, name) in PARAM_NAMES.iter().enumerate() {
            let v = if f[3 + i].is_empty() { "-" } else { &f[3 + i] };
            s.push_str(&format!(";{name}={v}"));
        }
        s.push_str(&format!(";session={replicate}"));
        s
    }

    /// Every session, in canonical order.
    pub fn sessions(&self) -> Vec<SessionSpec> {
        let per = self.spec.sessions;
        self.cells
            .iter()
            .flat_map(|c| {
                (0..per).map(move |r| SessionSpec {
                    index: c.index * per + r,
                    cell: c.index,
                    replicate: r,
                    seed: session_seed(self.spec.seed, &self.identity(c, r)),
                })
            })
            .collect()
    }

    /// The CSV row of a result (without line break).
    pub fn result_row(&self, r: &SessionResult) -> String {
        let cell = &self.cells[r.session.cell];
        let mut f = self.cell_fields(cell);
        f.push(r.session.replicate.to_string());
        f.push(r.session.seed.to_string());
        f.extend(
            r.values
                .iter()
                .map(|v| v.map(format_number).unwrap_or_default()),
        );
        // one line, no comma: the reason stays one CSV field
        f.push(
            r.failure
                .as_deref()
                .unwrap_or_default()
                .replace([',', '\n', '\r'], ";"),
        );
        f.join(",")
    }

    /// Runs one session on `world` (which must be a world of the session's
    /// scene, or its outcome table), in constant memory.
    pub fn run_session(
        &self,
        session: &SessionSpec,
        world: &mut dyn World,
    ) -> Result<SessionResult, SweepError> {
        let mut learner = self.learner(session, world)?;
        let mut metrics = self.recorder(world);
        let status = run_session_into(
            world,
            &mut learner,
            &self.config(session),
            &mut metrics,
            |_| {},
        );
        self.count_trials(metrics.trials() as u64);
        Ok(self.result(session, status, &metrics))
    }

    /// Runs `sessions` (all of one scene) in lockstep on `world`: at each
    /// trial the new commands of all of them are executed together. The
    /// results are those of [`run_session`](Self::run_session), in order.
    pub fn run_sessions_lockstep(
        &self,
        sessions: &[SessionSpec],
        world: &mut dyn World,
    ) -> Result<Vec<SessionResult>, SweepError> {
        let mut learners = sessions
            .iter()
            .map(|s| self.learner(s, world))
            .collect::<Result<Vec<_>, _>>()?;
        let configs: Vec<SessionConfig> = sessions.iter().map(|s| self.config(s)).collect();
        let mut recorders: Vec<RunningMetrics> =
            sessions.iter().map(|_| self.recorder(world)).collect();
        let status = run_lockstep_into(world, &mut learners, &configs, &mut recorders, |t| {
            self.count_trials(t)
        });
        Ok(sessions
            .iter()
            .zip(status)
            .zip(&recorders)
            .map(|((s, st), m)| self.result(s, st, m))
            .collect())
    }

    fn learner(
        &self,
        session: &SessionSpec,
        world: &dyn World,
    ) -> Result<Box<dyn crate::learner::Learner + Send>, SweepError> {
        let cell = &self.cells[session.cell];
        if world.command_space() != &self.scenes[cell.scene].command_space() {
            return Err(SweepError::Other(format!(
                "session {} is of scene `{}`, but the world has another command space",
                session.index, self.scenes[cell.scene].name
            )));
        }
        cell.learner
            .make(
                &cell.params,
                world.command_space(),
                world.num_effects(),
                &Target::Uniform,
            )
            .map_err(|e| SweepError::Other(e.to_string()))
    }

    fn config(&self, session: &SessionSpec) -> SessionConfig {
        SessionConfig {
            trials: self.spec.trials,
            seed: session.seed,
            use_reward: self.cells[session.cell].use_reward,
        }
    }

    /// The running metrics a session keeps: the cumulative reward at the
    /// trials the metrics name.
    fn recorder(&self, world: &dyn World) -> RunningMetrics {
        let checkpoints: Vec<usize> = self
            .metrics
            .iter()
            .filter_map(|m| match *m {
                MetricSpec::CumulativeReward(t) => Some(t),
                _ => None,
            })
            .collect();
        RunningMetrics::with_checkpoints(world.num_effects(), &checkpoints)
    }

    fn result(
        &self,
        session: &SessionSpec,
        status: Result<(), WorldError>,
        running: &RunningMetrics,
    ) -> SessionResult {
        if let Err(e) = status {
            return SessionResult {
                session: *session,
                values: vec![None; self.metrics.len()],
                failure: Some(e.to_string()),
            };
        }
        let m = running.metrics(&Target::Uniform);
        let values = self
            .metrics
            .iter()
            .map(|spec| match *spec {
                MetricSpec::NormalizedEntropy => Some(m.normalized_entropy),
                MetricSpec::NormalizedEntropyLast1000 => Some(m.normalized_entropy_last_1000),
                MetricSpec::KlToTarget => Some(m.kl_to_target),
                MetricSpec::DistinctEffects => Some(m.distinct_effects as f64),
                MetricSpec::CumulativeReward(t) => running.cumulative_reward_at(t),
                MetricSpec::FirstRewardTrial => m.first_reward_trial.map(|t| t as f64),
            })
            .collect();
        SessionResult {
            session: *session,
            values,
            failure: None,
        }
    }

    /// How the outcomes of each scene will be obtained for `sessions` on
    /// `threads` threads (see [`ExecutionPlan::choose`]), without reading
    /// or building anything but the table folder's headers.
    pub fn workloads(&self, sessions: &[SessionSpec], threads: usize) -> Vec<Workload> {
        let mut work = vec![
            Workload {
                trials: 0,
                sessions: 0,
                threads: threads.max(1),
            };
            self.scenes.len()
        ];
        for s in sessions {
            let w = &mut work[self.cells[s.cell].scene];
            w.trials += self.spec.trials as u64;
            w.sessions += 1;
        }
        work
    }

    /// Runs `sessions` on a local pool of `threads` threads, calling
    /// `on_result` on the calling thread as each one finishes (in no
    /// particular order).
    ///
    /// Each scene's outcomes come from the cheapest of an outcome table,
    /// an outcome memo or live execution ([`Executor`]), shared by all
    /// threads; under the memo and live execution the scene's sessions run
    /// in lockstep groups, each group's new commands stepped together in
    /// multi-copy worlds where copies are exact. The results are the same,
    /// bit for bit, whatever is chosen and whatever the threads. Each
    /// choice is told to the notice callback ([`with_notices`](Self::with_notices)),
    /// and so is what a memo simulated and kept.
    /// An error from `on_result` or from a session stops the sweep and is
    /// returned.
    pub fn run_with(
        &self,
        sessions: &[SessionSpec],
        threads: usize,
        mut on_result: impl FnMut(SessionResult) -> Result<(), SweepError>,
    ) -> Result<(), SweepError> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.max(1))
            .build()
            .map_err(|e| SweepError::Other(format!("cannot start the threads: {e}")))?;
        let work = self.workloads(sessions, pool.current_num_threads());
        let executors: Vec<Option<Executor>> = pool.install(|| {
            self.scenes
                .iter()
                .zip(&work)
                .map(|(scene, w)| {
                    if w.sessions == 0 {
                        return Ok(None);
                    }
                    let e = Executor::new(scene, w, &self.exec)
                        .map_err(|e| SweepError::Other(e.to_string()))?;
                    self.notice(&e.plan().to_string());
                    Ok(Some(e))
                })
                .collect::<Result<_, SweepError>>()
        })?;
        // the units of work: one session on a table, or a lockstep group
        let mut units: Vec<Vec<SessionSpec>> = Vec::new();
        for (si, exec) in executors.iter().enumerate() {
            let Some(exec) = exec else { continue };
            let mine: Vec<SessionSpec> = sessions
                .iter()
                .filter(|s| self.cells[s.cell].scene == si)
                .copied()
                .collect();
            if exec.table().is_some() {
                units.extend(mine.into_iter().map(|s| vec![s]));
            } else {
                let size = mine.len().div_ceil(exec.plan().groups.max(1));
                units.extend(mine.chunks(size.max(1)).map(<[SessionSpec]>::to_vec));
            }
        }
        let (executors, units) = (&executors, &units);
        let outcome = std::thread::scope(|scope| {
            let (tx, rx) = std::sync::mpsc::channel::<Result<SessionResult, SweepError>>();
            let pool = &pool;
            scope.spawn(move || {
                pool.install(|| {
                    let _ = units.par_iter().try_for_each_with(tx, |tx, unit| {
                        let scene = self.cells[unit[0].cell].scene;
                        let exec = executors[scene].as_ref().expect("a scene with work");
                        // a panic inside the engine fails this unit's
                        // sessions, recorded so, not the whole sweep
                        let run = std::panic::AssertUnwindSafe(|| {
                            let mut world = exec.world(unit.len());
                            if unit.len() == 1 {
                                self.run_session(&unit[0], &mut *world).map(|r| vec![r])
                            } else {
                                self.run_sessions_lockstep(unit, &mut *world)
                            }
                        });
                        let results = std::panic::catch_unwind(run).unwrap_or_else(|p| {
                            let why = p
                                .downcast_ref::<String>()
                                .cloned()
                                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                                .unwrap_or_else(|| "no message".into());
                            Ok(unit
                                .iter()
                                .map(|s| SessionResult {
                                    session: *s,
                                    values: vec![None; self.metrics.len()],
                                    failure: Some(format!("the simulation panicked: {why}")),
                                })
                                .collect())
                        });
                        match results {
                            Ok(rs) => rs.into_iter().try_for_each(|r| tx.send(Ok(r))),
                            Err(e) => tx.send(Err(e)),
                        }
                        .map_err(|_| ())
                    });
                })
            });
            let mut outcome = Ok(());
            while let Ok(r) = rx.recv() {
                if let Err(e) = r.and_then(&mut on_result) {
                    outcome = Err(e);
                    break;
                }
            }
            drop(rx);
            outcome
        });
        for exec in executors.iter().flatten() {
            if let Some(line) = exec.finish() {
                self.notice(&line);
            }
        }
        outcome
    }

    /// Runs every session on `threads` threads and returns the results in
    /// canonical order.
    pub fn run(&self, threads: usize) -> Result<Vec<SessionResult>, SweepError> {
        let sessions = self.sessions();
        let mut out: Vec<Option<SessionResult>> = vec![None; sessions.len()];
        self.run_with(&sessions, threads, |r| {
            let i = r.session.index;
            out[i] = Some(r);
            Ok(())
        })?;
        Ok(out.into_iter().flatten().collect())
    }

    /// Runs the sweep (or one shard of it) into the folder `dir`, resumably.
    ///
    /// The folder receives `sweep.ron` (a copy of the file), `version.txt`,
    /// `journal.txt` (every finished session, one checksummed line each,
    /// appended as they finish) and, once every session of the shard is in
    /// the journal, `results.csv` (one row per session, canonical order)
    /// and, for a whole sweep, `summary.csv` (one row per cell). The final
    /// files are written atomically from the journal, so that a run killed
    /// at any moment and resumed gives the same bytes as an uninterrupted
    /// one.
    ///
    /// Without `options.resume`, a folder that exists and is not empty is
    /// refused. With it, the folder must hold the same sweep file (byte for
    /// byte), the same e3d version and the same shard; only the missing
    /// sessions run. `progress(done, total)` is called after each session.
    pub fn run_to_dir(
        &self,
        dir: &Path,
        options: &DirOptions,
        mut progress: impl FnMut(usize, usize),
    ) -> Result<DirReport, SweepError> {
        let shard = options.shard;
        let journal_path = dir.join(JOURNAL);
        let header = JournalHeader {
            sweep_hash: fnv1a64(self.text.as_bytes()),
            shard,
            total: self.num_sessions(),
            per_cell: self.spec.sessions,
            scenes: self
                .scenes
                .iter()
                .map(|s| (s.name.clone(), OutcomeTable::key(s)))
                .collect(),
            version: VERSION.to_string(),
            columns: self.results_header(),
        };
        if dir.exists() && !dir.is_dir() {
            return Err(SweepError::Output(format!(
                "{}: exists and is not a folder",
                dir.display()
            )));
        }
        // a folder that holds only temporary files of write_atomic (never
        // renamed, so never part of a sweep) was left by a run killed
        // while copying the sweep file: it counts as empty, and they go
        let mut non_empty = false;
        let mut temporaries = Vec::new();
        if dir.is_dir() {
            for entry in std::fs::read_dir(dir).map_err(io_err(dir))? {
                let entry = entry.map_err(io_err(dir))?;
                let name = entry.file_name().to_string_lossy().into_owned();
                if name == crate::io::LOCK_FILE {
                    continue;
                }
                if crate::io::is_temporary(&name) {
                    temporaries.push(entry.path());
                } else {
                    non_empty = true;
                }
            }
        }
        if !non_empty {
            for t in temporaries {
                let _ = std::fs::remove_file(t);
            }
        }
        if non_empty && !options.resume {
            return Err(SweepError::Output(format!(
                "{} exists and is not empty; pass --resume to complete the sweep it holds, or choose another --out",
                dir.display()
            )));
        }
        if non_empty && !dir.join(SWEEP_COPY).exists() {
            return Err(SweepError::Output(format!(
                "{}: holds no {SWEEP_COPY}, so no sweep to resume; choose another --out",
                dir.display()
            )));
        }
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        // the copy of the sweep and the version: the same, or refused
        for (name, bytes) in [
            (SWEEP_COPY, self.text.as_bytes().to_vec()),
            (VERSION_FILE, version_line().into_bytes()),
        ] {
            let p = dir.join(name);
            match std::fs::read(&p) {
                Ok(old) if old == bytes => {}
                Ok(_) => {
                    return Err(SweepError::Output(format!(
                        "{}: differs from this run's ({}); the folder holds another sweep or was made by another e3d version; choose another --out",
                        p.display(),
                        if name == SWEEP_COPY { self.file.clone() } else { format!("e3d {VERSION}") }
                    )))
                }
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                    crate::io::write_atomic(&p, &bytes).map_err(io_err(&p))?
                }
                Err(e) => return Err(io_err(&p)(e)),
            }
        }
        let (mut journal, mut done) = if journal_path.exists() {
            let read = journal::read(&journal_path)?;
            if let Some((name, now, then)) = header.changed_scene(&read.header) {
                if read.header.sweep_hash == header.sweep_hash {
                    return Err(SweepError::Output(format!(
                        "{}: scene `{name}` changed since this folder's sessions ran (content {then:016x}, now {now:016x}); one results file cannot mix two versions of a scene: restore it, or choose another --out",
                        journal_path.display()
                    )));
                }
            }
            if read.header != header {
                return Err(SweepError::Output(format!(
                    "{}: written by another run ({}); this run is shard {} of sweep {:016x} with {} sessions; choose another --out",
                    journal_path.display(),
                    read.header.describe(),
                    shard,
                    header.sweep_hash,
                    header.total
                )));
            }
            let j = Journal::append(&journal_path, read.valid_len)?;
            (j, read.rows)
        } else {
            (Journal::create(&journal_path, &header)?, BTreeMap::new())
        };
        let all = self.sessions();
        let mine: Vec<SessionSpec> = all
            .into_iter()
            .filter(|s| shard.contains(s.index))
            .collect();
        done.retain(|i, _| shard.contains(*i) && *i < header.total);
        let resumed = done.len();
        let todo: Vec<SessionSpec> = mine
            .iter()
            .filter(|s| !done.contains_key(&s.index))
            .copied()
            .collect();
        let total = mine.len();
        progress(done.len(), total);
        let mut count = done.len();
        self.run_with(&todo, options.threads, |r| {
            let row = self.result_row(&r);
            journal.push(r.session.index, &row)?;
            done.insert(r.session.index, row);
            count += 1;
            progress(count, total);
            Ok(())
        })?;
        journal.sync()?;
        drop(journal);
        write_final(dir, &header, &done)?;
        Ok(DirReport {
            sessions: total,
            resumed,
            ran: todo.len(),
        })
    }
}

/// What [`Sweep::run_to_dir`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DirReport {
    /// The sessions of the shard.
    pub sessions: usize,
    /// How many were already in the journal.
    pub resumed: usize,
    /// How many ran now.
    pub ran: usize,
}

/// How [`Sweep::run_to_dir`] runs.
#[derive(Debug, Clone, Copy)]
pub struct DirOptions {
    /// Threads of the local pool.
    pub threads: usize,
    /// Complete the sweep an existing folder holds.
    pub resume: bool,
    /// Which part of the sweep ([`Shard::ALL`]: all of it).
    pub shard: Shard,
}

/// The e3d version written into output folders.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
/// The journal's file name in an output folder.
pub const JOURNAL: &str = "journal.txt";
/// The copy of the sweep file in an output folder.
pub const SWEEP_COPY: &str = "sweep.ron";
/// The version file in an output folder.
pub const VERSION_FILE: &str = "version.txt";
/// The per-session results in an output folder.
pub const RESULTS: &str = "results.csv";
/// The per-cell summary in an output folder.
pub const SUMMARY: &str = "summary.csv";

fn version_line() -> String {
    format!("e3d {VERSION}\n")
}

/// Writes `results.csv` (and `summary.csv` for a whole sweep) from the
/// journal's rows, when every session of the shard is there.
fn write_final(
    dir: &Path,
    header: &JournalHeader,
    rows: &BTreeMap<usize, String>,
) -> Result<(), SweepError> {
    let expected = header.shard.count(header.total);
    if rows.len() != expected {
        return Err(SweepError::Output(format!(
            "{}: {} of {} sessions done; run again with --resume",
            dir.display(),
            rows.len(),
            expected
        )));
    }
    let mut csv = String::with_capacity(64 * (rows.len() + 1));
    csv.push_str(&header.columns);
    csv.push('\n');
    for row in rows.values() {
        csv.push_str(row);
        csv.push('\n');
    }
    let p = dir.join(RESULTS);
    crate::io::write_atomic(&p, csv.as_bytes()).map_err(io_err(&p))?;
    if header.shard.n == 1 {
        let s = summary::summarize(&header.columns, rows.values().map(String::as_str))?;
        let p = dir.join(SUMMARY);
        crate::io::write_atomic(&p, s.as_bytes()).map_err(io_err(&p))?;
    }
    Ok(())
}

/// Joins the output folders of the shards of one sweep into `out`, which
/// then holds the same files, byte for byte, as a one-process run
/// (`results.csv`, `summary.csv`, `sweep.ron`, `version.txt`, and a
/// journal in canonical order). Every shard `1..=N` must be given once and
/// be complete. `out` must not exist or be empty.
pub fn merge(inputs: &[PathBuf], out: &Path) -> Result<DirReport, SweepError> {
    if inputs.is_empty() {
        return Err(SweepError::Output(
            "nothing to merge: name the shards' folders".into(),
        ));
    }
    let mut first: Option<(JournalHeader, Vec<u8>, Vec<u8>)> = None;
    let mut seen: BTreeMap<usize, PathBuf> = BTreeMap::new();
    let mut rows: BTreeMap<usize, String> = BTreeMap::new();
    for dir in inputs {
        let jp = dir.join(JOURNAL);
        if !jp.exists() {
            return Err(SweepError::Output(format!(
                "{}: no {JOURNAL}; expected the --out folder of `e3d sweep --shard K/N`",
                dir.display()
            )));
        }
        let read = journal::read(&jp)?;
        let sweep_copy =
            std::fs::read(dir.join(SWEEP_COPY)).map_err(io_err(&dir.join(SWEEP_COPY)))?;
        let version =
            std::fs::read(dir.join(VERSION_FILE)).map_err(io_err(&dir.join(VERSION_FILE)))?;
        let h = &read.header;
        match &first {
            None => first = Some((h.clone(), sweep_copy, version)),
            Some((h0, s0, v0)) => {
                if let Some((name, here, there)) = h.changed_scene(h0) {
                    return Err(SweepError::Output(format!(
                        "{}: ran scene `{name}` with other content ({here:016x}) than {} ({there:016x}); the scene was edited between the shards, which cannot be merged: rerun them with one version",
                        dir.display(),
                        inputs[0].display()
                    )));
                }
                if h.sweep_hash != h0.sweep_hash
                    || h.shard.n != h0.shard.n
                    || h.total != h0.total
                    || h.columns != h0.columns
                    || &sweep_copy != s0
                {
                    return Err(SweepError::Output(format!(
                        "{}: holds {}, but {} holds {}; shards of different sweeps cannot be merged",
                        dir.display(),
                        h.describe(),
                        inputs[0].display(),
                        h0.describe()
                    )));
                }
                if &version != v0 || h.version != h0.version {
                    return Err(SweepError::Output(format!(
                        "{}: made by e3d {}, but {} by e3d {}; rerun the shards with one version",
                        dir.display(),
                        h.version,
                        inputs[0].display(),
                        h0.version
                    )));
                }
            }
        }
        if let Some(other) = seen.insert(h.shard.k, dir.clone()) {
            return Err(SweepError::Output(format!(
                "shard {} given twice: {} and {}",
                h.shard,
                other.display(),
                dir.display()
            )));
        }
        let expected = h.shard.count(h.total);
        let mine = read
            .rows
            .into_iter()
            .filter(|(i, _)| h.shard.contains(*i) && *i < h.total)
            .collect::<Vec<_>>();
        if mine.len() != expected {
            return Err(SweepError::Output(format!(
                "{}: shard {} is incomplete ({} of {} sessions); finish it with `e3d sweep ... --shard {} --resume`",
                dir.display(),
                h.shard,
                mine.len(),
                expected,
                h.shard
            )));
        }
        rows.extend(mine);
    }
    let (h0, sweep_copy, version) = first.expect("at least one input");
    let missing: Vec<String> = (1..=h0.shard.n)
        .filter(|k| !seen.contains_key(k))
        .map(|k| format!("{k}/{}", h0.shard.n))
        .collect();
    if !missing.is_empty() {
        return Err(SweepError::Output(format!(
            "missing shard(s) {}; give the folders of all {} shards",
            missing.join(", "),
            h0.shard.n
        )));
    }
    if out.exists()
        && (!out.is_dir()
            || std::fs::read_dir(out)
                .map_err(io_err(out))?
                .next()
                .is_some())
    {
        return Err(SweepError::Output(format!(
            "{} exists and is not empty; choose another --out",
            out.display()
        )));
    }
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let header = JournalHeader {
        shard: Shard::ALL,
        ..h0
    };
    for (name, bytes) in [(SWEEP_COPY, &sweep_copy), (VERSION_FILE, &version)] {
        let p = out.join(name);
        crate::io::write_atomic(&p, bytes).map_err(io_err(&p))?;
    }
    journal::write_whole(&out.join(JOURNAL), &header, &rows)?;
    write_final(out, &header, &rows)?;
    Ok(DirReport {
        sessions: rows.len(),
        resumed: rows.len(),
        ran: 0,
    })
}

enum SceneResolve {
    NotFound(String),
    Scene(SceneError),
}

/// A scene named in a sweep: a path relative to `base` (or absolute), or a
/// built-in name.
fn resolve_scene(name: &str, base: Option<&Path>) -> Result<Scene, SceneResolve> {
    let p = Path::new(name);
    let path = match base {
        Some(b) if p.is_relative() => b.join(p),
        _ => p.to_path_buf(),
    };
    if path.exists() {
        return Scene::load(&path).map_err(SceneResolve::Scene);
    }
    if let Some(s) = Scene::builtin(name) {
        return Ok(s);
    }
    let names: Vec<&str> = crate::scene::BUILTIN.iter().map(|(n, _)| *n).collect();
    Err(SceneResolve::NotFound(format!(
        "a scene file (relative to the sweep file) or a built-in scene ({}), found `{name}`: no file {}{}",
        names.join(", "),
        path.display(),
        crate::scene::did_you_mean(name, &names)
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_hit_their_ends() {
        let v = Values::Range {
            scale: Scale::Log,
            from: 1.0,
            to: 1000.0,
            steps: 4,
        }
        .values();
        assert_eq!(v, vec![1.0, 10.0, 100.0, 1000.0]);
        let v = Values::Range {
            scale: Scale::Linear,
            from: 0.0,
            to: 1.0,
            steps: 5,
        }
        .values();
        assert_eq!(v, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
    }

    #[test]
    fn shards_partition_the_sessions() {
        let total = 17;
        let shards: Vec<Shard> = (1..=3).map(|k| Shard { k, n: 3 }).collect();
        for i in 0..total {
            assert_eq!(shards.iter().filter(|s| s.contains(i)).count(), 1);
        }
        let counts: usize = shards.iter().map(|s| s.count(total)).sum();
        assert_eq!(counts, total);
        assert_eq!(shards[0].count(total), 6);
        assert_eq!(shards[2].count(total), 5);
        assert_eq!("2/3".parse::<Shard>().unwrap(), shards[1]);
        assert!("0/3".parse::<Shard>().is_err());
        // no overflow with the largest N
        let huge: Shard = "1/18446744073709551615".parse().unwrap();
        assert_eq!(huge.count(total), 1);
        assert_eq!(huge.count(0), 0);
        let last = Shard {
            k: usize::MAX,
            n: usize::MAX,
        };
        assert_eq!(last.count(total), 0);
        assert_eq!(last.count(usize::MAX), 1);
        assert_eq!(Shard { k: 3, n: 3 }.count(2), 0);
        assert!("4/3".parse::<Shard>().is_err());
    }

    #[test]
    fn seeds_are_fixed_by_identity() {
        // a documented, portable rule: these numbers must never change
        assert_eq!(splitmix64(1), 0x910a2dec89025cc1);
        let id = "scene=two_rooms;learner=e3d;use_reward=true;alpha=0.3;beta=100;lambda=0.03;eta=0.01;epsilon=-;session=0";
        assert_eq!(session_seed(0, id), session_seed(0, id));
        assert_ne!(session_seed(0, id), session_seed(1, id));
    }
}
