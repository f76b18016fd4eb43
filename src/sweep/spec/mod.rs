//! The sweep file: hyper-parameter values, metrics and the [`SweepSpec`]
//! as written, built in code, parsed, checked and written back.

use super::factory::Learners;
#[cfg(doc)]
use super::Sweep;
use super::SweepError;
#[cfg(doc)]
use crate::episode::run_episodes;
use crate::episode::Observe;
#[cfg(doc)]
use crate::learner::LearnerKind;
use crate::learner::Params;
#[cfg(doc)]
use crate::learner::{ClosedLoopE3d, QLearning};
use crate::scene::{ron_options, SceneError, SceneErrorKind};
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

mod check;
mod values;

pub(super) use check::invalid;
pub(crate) use values::set_param;
pub use values::{ParamValues, Scale, Values};

/// The largest number of sessions a sweep may hold: its plan keeps every
/// cell and session in memory (about 150 bytes each, so at most about
/// 1.5 GB), and is refused before any is made when it would be larger.
pub const MAX_SESSIONS: usize = 10_000_000;

/// The largest number of trials per session (the bound of `e3d run
/// --trials`).
pub const MAX_TRIALS: usize = 100_000_000;
const _: () = assert!(crate::episode::MAX_EPISODE_COMMANDS == MAX_TRIALS);

/// The largest number of steps of a range.
pub const MAX_STEPS: usize = 100_000;

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
    /// The fraction of the reachable cells reached by the last trial
    /// ([`Metrics::coverage`](crate::Metrics::coverage); the reachable
    /// cells when the sweep knows them, [`Sweep::with_reachable_effects`],
    /// else every cell).
    Coverage,
    /// The trial by which 50% of those cells were reached (empty when
    /// never; column `trials_to_50_percent`).
    #[serde(rename = "trials_to_50_percent")]
    TrialsTo50Percent,
    /// The same for 90% (column `trials_to_90_percent`).
    #[serde(rename = "trials_to_90_percent")]
    TrialsTo90Percent,
    /// The QD-score: the sum over the reached cells of their best effort
    /// quality ([`Metrics::qd_score`](crate::Metrics::qd_score); empty for
    /// episodes).
    QdScore,
    /// The normalised entropy (over every effect) of the terminal effects
    /// of the episodes started in start context `i`, 0-based in the
    /// scene's order (column `normalized_entropy_context_I`; empty for a
    /// scene of fewer contexts).
    NormalizedEntropyContext(usize),
    /// The total reward of the episodes started in start context `i`
    /// (column `cumulative_reward_context_I`; empty for a scene of fewer
    /// contexts).
    CumulativeRewardContext(usize),
    /// The first episode (1-based, over all the session's episodes) started
    /// in start context `i` with a reward (column
    /// `first_reward_trial_context_I`; empty when none, or for a scene of
    /// fewer contexts).
    FirstRewardTrialContext(usize),
    /// The reproducibility of the final policy under the scene's noise
    /// ([`session::reproducibility`](crate::session::reproducibility), its
    /// default 64 commands and 20 runs, seeded by the session's seed): the
    /// share of its likely commands whose effect holds in at least 90% of
    /// the runs (for episodes, of its likely episodes:
    /// [`session::episode_reproducibility`](crate::session::episode_reproducibility));
    /// 1 on a noise-free scene; empty for a policy that cannot be drawn
    /// from. Not a default (it costs 64 x 20 executions, or episodes, a
    /// session).
    Reproducibility,
}

impl MetricSpec {
    /// A per-context metric's name without its context (`name(I)` in a
    /// sweep file, `name_I` as a column), and its context.
    pub fn per_context(&self) -> Option<(&'static str, usize)> {
        match *self {
            MetricSpec::NormalizedEntropyContext(i) => Some(("normalized_entropy_context", i)),
            MetricSpec::CumulativeRewardContext(i) => Some(("cumulative_reward_context", i)),
            MetricSpec::FirstRewardTrialContext(i) => Some(("first_reward_trial_context", i)),
            _ => None,
        }
    }

    /// The column name.
    pub fn column(&self) -> String {
        match (self, self.per_context()) {
            (MetricSpec::CumulativeReward(t), _) => format!("cumulative_reward_at_{t}"),
            (_, Some((name, i))) => format!("{name}_{i}"),
            // the others: their name in a sweep file
            _ => ron::to_string(self).unwrap_or_default(),
        }
    }

    /// The metrics kept when a sweep names none: all of them, with the
    /// cumulative reward at the last trial (the coverage measures, then
    /// the QD-score last, so that the columns before them are those of
    /// earlier versions).
    pub fn defaults(trials: usize) -> Vec<MetricSpec> {
        vec![
            MetricSpec::NormalizedEntropy,
            MetricSpec::NormalizedEntropyLast1000,
            MetricSpec::KlToTarget,
            MetricSpec::DistinctEffects,
            MetricSpec::CumulativeReward(trials),
            MetricSpec::FirstRewardTrial,
            MetricSpec::Coverage,
            MetricSpec::TrialsTo50Percent,
            MetricSpec::TrialsTo90Percent,
            MetricSpec::QdScore,
        ]
    }
}

fn default_use_reward() -> Vec<bool> {
    vec![true]
}

/// A sweep, as data: what to run (see `docs/sweeps.md` for its RON form).
///
/// Parse one from a sweep file ([`SweepSpec::parse`]), or build one in
/// code ([`SweepSpec::new`] and the `with_` methods, whose defaults are
/// those of a file); [`to_ron`](SweepSpec::to_ron) writes it back as a
/// sweep file that parses to an equal spec. A [`Sweep`] is a spec checked
/// and resolved by factories of worlds and learners.
///
/// ```
/// use e3d::sweep::{MetricSpec, ParamValues, SweepSpec, Values};
/// let spec = SweepSpec::new(["two_rooms"], ["e3d", "uniform"], 3, 500)
///     .with_use_reward([false])
///     .with_params(ParamValues { beta: Some(Values::log(1.0, 1000.0, 4)), ..Default::default() })
///     .with_seed(2020)
///     .with_metrics([MetricSpec::NormalizedEntropy, MetricSpec::CumulativeReward(500)]);
/// let text = spec.to_ron();
/// assert!(text.contains("beta: (scale: Log, from: 1.0, to: 1000.0, steps: 4)"));
/// assert_eq!(SweepSpec::parse(&text, "spec.ron").unwrap(), spec);
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, rename = "Sweep")]
pub struct SweepSpec {
    /// A name, for people.
    #[serde(default)]
    pub name: String,
    /// A sentence or two, for people.
    #[serde(default)]
    pub description: String,
    /// The scenes, as the world factory knows them: with the built-in one,
    /// scene files (relative to the sweep file's folder) or built-in names.
    pub scenes: Vec<String>,
    /// The learners' names (`e3d`, `uniform`, `egreedy`, or those of a
    /// custom [`Learners`]); in a file, bare identifiers.
    #[serde(deserialize_with = "learner_names")]
    pub learners: Vec<String>,
    /// Whether the learners see the reward: `[true]`, `[false]` or both
    /// (default `[true]`).
    #[serde(default = "default_use_reward")]
    pub use_reward: Vec<bool>,
    /// The values of each hyper-parameter.
    #[serde(default)]
    pub params: ParamValues,
    /// Scene fields to vary, each by its path in the scene's serde form
    /// ([`Scene::with_paths`](crate::Scene::with_paths)) with its values,
    /// in the file's order: `axes: {"joints.j1.damping": [0.1, 1.0]}`.
    /// Each combination of values makes a derived scene of every scene.
    #[serde(default, with = "axes_map", skip_serializing_if = "Vec::is_empty")]
    pub axes: Vec<(String, Values)>,
    /// Sessions (seeds) per cell, >= 1.
    pub sessions: usize,
    /// Trials per session, >= 1.
    pub trials: usize,
    /// The base seed every session's seed is derived from.
    #[serde(default)]
    pub seed: u64,
    /// The metrics to keep (default: [`MetricSpec::defaults`], and on
    /// scenes with start contexts the normalised entropy per context).
    #[serde(default)]
    pub metrics: Option<Vec<MetricSpec>>,
    /// The commands of an episode, `K` in `1..=64` (default 1): above 1,
    /// every session runs episodes of `K` commands, each starting where
    /// the last one left the world ([`run_episodes`]), and a trial of the
    /// metrics is an episode.
    #[serde(default = "default_commands")]
    pub commands: usize,
    /// What the learners observe before each command (default: the
    /// current state with several commands per episode or a closed loop,
    /// else the start context). Set, every session runs episodes.
    #[serde(default)]
    pub observe: Option<Observe>,
    /// Whether `e3d` is closed-loop E3D ([`ClosedLoopE3d`]: the policy
    /// guided by `Q_ref`) and `egreedy` Q-learning ([`QLearning`]); the
    /// other learners run their contextual form. True, every session runs
    /// episodes.
    #[serde(default)]
    pub closed_loop: bool,
    /// The discount of `Q_ref` and of Q-learning, in `[0, 1]` (default
    /// [`ClosedLoopE3d::GAMMA`]); only with `closed_loop`.
    #[serde(default)]
    pub gamma: Option<f64>,
}

fn default_commands() -> usize {
    1
}

/// The most commands an episode of a sweep may have (as `e3d
/// closed-loop --commands`).
pub const MAX_COMMANDS: usize = 64;

/// The built-in learners' names, in the order of [`LearnerKind::ALL`].
const BUILTIN_LEARNERS: &[&str] = &[
    "e3d",
    "uniform",
    "egreedy",
    "e3d_relax",
    "count",
    "smm",
    "goal_babbling",
    "archive",
    "archive_reached",
    "map_elites",
    "qlearning_moves",
];

#[cfg(test)]
#[test]
fn builtin_learners_are_every_learner_kind() {
    let names: Vec<&str> = crate::LearnerKind::ALL.iter().map(|k| k.as_str()).collect();
    assert_eq!(names, BUILTIN_LEARNERS);
}

thread_local! {
    /// The learner names a sweep file being parsed may use (`None`: the
    /// built-in ones).
    static KNOWN_LEARNERS: std::cell::RefCell<Option<Vec<String>>> =
        const { std::cell::RefCell::new(None) };
}

/// Sets the learner names a parse on this thread accepts, until dropped.
struct KnownLearners(Option<Vec<String>>);

impl KnownLearners {
    fn set(names: Vec<String>) -> KnownLearners {
        KnownLearners(KNOWN_LEARNERS.with(|k| k.replace(Some(names))))
    }
}

impl Drop for KnownLearners {
    fn drop(&mut self) {
        let previous = self.0.take();
        KNOWN_LEARNERS.with(|k| *k.borrow_mut() = previous);
    }
}

/// A learner name in a sweep file: a bare identifier, read as a variant
/// of `LearnerKind` was (so that a mistake is reported at the name, with
/// the same words), and checked against the known names.
struct LearnerName(String);

impl<'de> Deserialize<'de> for LearnerName {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<LearnerName, D::Error> {
        struct Ident;
        impl<'de> de::DeserializeSeed<'de> for Ident {
            type Value = String;
            fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<String, D::Error> {
                d.deserialize_identifier(self)
            }
        }
        impl Visitor<'_> for Ident {
            type Value = String;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a learner name")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<String, E> {
                KNOWN_LEARNERS.with(|k| match &*k.borrow() {
                    None if BUILTIN_LEARNERS.contains(&v) => Ok(v.to_string()),
                    Some(known) if known.iter().any(|n| n == v) => Ok(v.to_string()),
                    Some(known)
                        if known
                            .iter()
                            .map(String::as_str)
                            .ne(BUILTIN_LEARNERS.iter().copied()) =>
                    {
                        let names: Vec<&str> = known.iter().map(String::as_str).collect();
                        Err(E::custom(format_args!(
                            "unknown learner `{v}`{}; expected one of: {}",
                            crate::scene::did_you_mean(v, &names),
                            names.join(", ")
                        )))
                    }
                    _ => Err(E::unknown_variant(v, BUILTIN_LEARNERS)),
                })
            }
        }
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = LearnerName;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a learner name")
            }
            fn visit_enum<A: de::EnumAccess<'de>>(self, a: A) -> Result<LearnerName, A::Error> {
                let (name, variant) = a.variant_seed(Ident)?;
                de::VariantAccess::unit_variant(variant)?;
                Ok(LearnerName(name))
            }
        }
        d.deserialize_enum("LearnerKind", BUILTIN_LEARNERS, V)
    }
}

fn learner_names<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<String>, D::Error> {
    Ok(Vec::<LearnerName>::deserialize(d)?
        .into_iter()
        .map(|n| n.0)
        .collect())
}

/// The file name errors give a sweep built in code.
pub(super) const CODE_FILE: &str = "<SweepSpec>";

impl SweepSpec {
    /// A spec of the `scenes` x `learners` grid, `sessions` sessions of
    /// `trials` trials per cell, with the defaults of a sweep file: no name
    /// or description, `use_reward: [true]`, every hyper-parameter at the
    /// default of `e3d run` ([`Params::TASK1`]), base seed 0 and every
    /// metric ([`MetricSpec::defaults`]).
    ///
    /// ```
    /// use e3d::sweep::SweepSpec;
    /// let spec = SweepSpec::new(["two_rooms"], ["e3d"], 10, 5000);
    /// assert_eq!(spec.use_reward, [true]);
    /// assert_eq!((spec.seed, spec.metrics.clone()), (0, None));
    /// assert_eq!(spec, SweepSpec::parse(
    ///     r#"Sweep(scenes: ["two_rooms"], learners: [e3d], sessions: 10, trials: 5000)"#,
    ///     "min.ron",
    /// ).unwrap());
    /// ```
    pub fn new<S, L>(
        scenes: impl IntoIterator<Item = S>,
        learners: impl IntoIterator<Item = L>,
        sessions: usize,
        trials: usize,
    ) -> SweepSpec
    where
        S: Into<String>,
        L: Into<String>,
    {
        SweepSpec {
            name: String::new(),
            description: String::new(),
            scenes: scenes.into_iter().map(Into::into).collect(),
            learners: learners.into_iter().map(Into::into).collect(),
            use_reward: default_use_reward(),
            params: ParamValues::default(),
            axes: Vec::new(),
            sessions,
            trials,
            seed: 0,
            metrics: None,
            commands: 1,
            observe: None,
            closed_loop: false,
            gamma: None,
        }
    }

    /// Sets the name.
    pub fn with_name(mut self, name: impl Into<String>) -> SweepSpec {
        self.name = name.into();
        self
    }

    /// Sets the description.
    pub fn with_description(mut self, description: impl Into<String>) -> SweepSpec {
        self.description = description.into();
        self
    }

    /// Sets whether the learners see the reward (`[false, true]`: both).
    pub fn with_use_reward(mut self, use_reward: impl IntoIterator<Item = bool>) -> SweepSpec {
        self.use_reward = use_reward.into_iter().collect();
        self
    }

    /// Sets the values of the hyper-parameters.
    pub fn with_params(mut self, params: ParamValues) -> SweepSpec {
        self.params = params;
        self
    }

    /// Adds a scene axis: the field at `path` of every scene takes each
    /// of `values` (see [`axes`](Self::axes)).
    pub fn with_axis(mut self, path: impl Into<String>, values: Values) -> SweepSpec {
        self.axes.push((path.into(), values));
        self
    }

    /// Sets the base seed.
    pub fn with_seed(mut self, seed: u64) -> SweepSpec {
        self.seed = seed;
        self
    }

    /// Whether every session runs episodes, whatever its scene: several
    /// commands per episode, an observation or a closed loop set. (A
    /// scene with start contexts runs episodes anyway.)
    pub fn runs_episodes(&self) -> bool {
        self.commands > 1 || self.observe.is_some() || self.closed_loop
    }

    /// Sets the metrics kept, in order.
    pub fn with_metrics(mut self, metrics: impl IntoIterator<Item = MetricSpec>) -> SweepSpec {
        self.metrics = Some(metrics.into_iter().collect());
        self
    }

    /// Parses and checks the text of a sweep file whose learners are the
    /// built-in ones; `file` names it in errors. The scenes are not looked
    /// at (a [`Sweep`] resolves them).
    pub fn parse(text: &str, file: &str) -> Result<SweepSpec, SweepError> {
        SweepSpec::parse_with(text, file, &Learners::builtin())
    }

    /// [`parse`](Self::parse) for a sweep file whose learners are those of
    /// `learners`: a name it does not make is refused at its place.
    pub fn parse_with(
        text: &str,
        file: &str,
        learners: &Learners,
    ) -> Result<SweepSpec, SweepError> {
        let (spec, text) = SweepSpec::from_text(text, file, learners)?;
        spec.check_in(file, text)?;
        Ok(spec)
    }

    /// The spec of `text`, read but not checked, and the text as read.
    pub(super) fn from_text<'t>(
        text: &'t str,
        file: &str,
        learners: &Learners,
    ) -> Result<(SweepSpec, &'t str), SweepError> {
        let text = crate::scene::prepare_text(text, file, "sweep")?;
        if text.trim().is_empty() {
            return Err(SceneError::new(file, "sweep", SceneErrorKind::Empty).into());
        }
        let _known = KnownLearners::set(learners.names());
        let spec: SweepSpec = ron_options()
            .from_str(text)
            .map_err(|e| SceneError::from_ron(file, text, e))?;
        Ok((spec, text))
    }

    /// The spec as a sweep file: RON that [`parse`](Self::parse) (or
    /// [`parse_with`](Self::parse_with) for custom learners) reads back
    /// to an equal spec. Empty names, descriptions and parameters left
    /// to their default are left out; numbers are written exactly.
    pub fn to_ron(&self) -> String {
        let string = |s: &str| ron::to_string(s).unwrap_or_else(|_| format!("{s:?}"));
        let mut out = String::from("Sweep(\n");
        for (field, text) in [("name", &self.name), ("description", &self.description)] {
            if !text.is_empty() {
                out.push_str(&format!("    {field}: {},\n", string(text)));
            }
        }
        let scenes: Vec<String> = self.scenes.iter().map(|s| string(s)).collect();
        out.push_str(&format!("    scenes: [{}],\n", scenes.join(", ")));
        out.push_str(&format!("    learners: [{}],\n", self.learners.join(", ")));
        let use_reward: Vec<String> = self.use_reward.iter().map(bool::to_string).collect();
        out.push_str(&format!("    use_reward: [{}],\n", use_reward.join(", ")));
        let params: Vec<String> = (self.params.given_text().into_iter())
            .map(|(name, v)| format!("        {name}: {v},\n"))
            .collect();
        if !params.is_empty() {
            out.push_str(&format!("    params: (\n{}    ),\n", params.concat()));
        }
        if !self.axes.is_empty() {
            let axes: Vec<String> = (self.axes.iter())
                .map(|(path, v)| format!("        {}: {},\n", string(path), v.to_ron()))
                .collect();
            out.push_str(&format!("    axes: {{\n{}    }},\n", axes.concat()));
        }
        let (sessions, trials, seed) = (self.sessions, self.trials, self.seed);
        out.push_str(&format!(
            "    sessions: {sessions},\n    trials: {trials},\n    seed: {seed},\n"
        ));
        if let Some(metrics) = &self.metrics {
            let m: Vec<String> = metrics
                .iter()
                .map(|m| ron::to_string(m).unwrap_or_default())
                .collect();
            out.push_str(&format!("    metrics: [{}],\n", m.join(", ")));
        }
        if self.commands != 1 {
            out.push_str(&format!("    commands: {},\n", self.commands));
        }
        if let Some(o) = self.observe {
            out.push_str(&format!("    observe: {o:?},\n"));
        }
        if self.closed_loop {
            out.push_str("    closed_loop: true,\n");
        }
        if let Some(g) = self.gamma {
            out.push_str(&format!("    gamma: {g:?},\n"));
        }
        out.push_str(")\n");
        out
    }
}

/// The scene axes as a RON map of paths to values, in the file's order,
/// each path once.
mod axes_map {
    use super::Values;
    use serde::de::{self, Deserializer, MapAccess, Visitor};
    use serde::ser::{SerializeMap, Serializer};
    use std::fmt;

    pub(super) fn serialize<S: Serializer>(
        axes: &[(String, Values)],
        s: S,
    ) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(axes.len()))?;
        for (path, values) in axes {
            m.serialize_entry(path, values)?;
        }
        m.end()
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<(String, Values)>, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Vec<(String, Values)>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(
                    "a map of scene field paths to values, `{\"joints.j1.damping\": [0.1, 1.0]}`",
                )
            }
            fn visit_map<A: MapAccess<'de>>(self, mut m: A) -> Result<Self::Value, A::Error> {
                let mut axes: Vec<(String, Values)> = Vec::new();
                while let Some(path) = m.next_key::<String>()? {
                    if axes.iter().any(|(p, _)| *p == path) {
                        return Err(de::Error::custom(format_args!(
                            "each path once, but `{path}` appears twice"
                        )));
                    }
                    axes.push((path, m.next_value()?));
                }
                Ok(axes)
            }
        }
        d.deserialize_map(V)
    }
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
}
