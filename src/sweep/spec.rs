//! The sweep file: hyper-parameter values, metrics, the [`SweepSpec`] as
//! written, and its parsing and checking into a [`Sweep`].

use super::plan::{uses_param, Cell, Sweep};
use super::SweepError;
use crate::learner::{LearnerKind, Params};
use crate::scene::{ron_options, Invalid, Scene, SceneError};
use crate::world::ExecOptions;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::Path;

/// The names of the hyper-parameters, in the order of the cells and columns.
pub const PARAM_NAMES: [&str; 5] = ["alpha", "beta", "lambda", "eta", "epsilon"];

/// The largest number of sessions a sweep may hold: its plan keeps every
/// cell and session in memory (about 150 bytes each, so at most about
/// 1.5 GB), and is refused before any is made when it would be larger.
pub const MAX_SESSIONS: usize = 10_000_000;

/// The largest number of trials per session (the bound of `e3d run
/// --trials`).
pub const MAX_TRIALS: usize = 100_000_000;

/// The largest number of steps of a range.
pub const MAX_STEPS: usize = 100_000;

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

pub(super) fn param_of(p: &Params, i: usize) -> f64 {
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
            return Err(SceneError::new(
                file,
                None,
                "the file is empty; expected `Sweep(scenes: [...], learners: [...], sessions: N, trials: T)`"
                    .into(),
            )
            .into());
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
}
