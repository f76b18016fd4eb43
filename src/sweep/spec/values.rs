//! The values of the hyper-parameters in a sweep file: a number, a list
//! or a range of each.

use super::*;

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

    /// The values given, in order.
    pub fn list(values: impl IntoIterator<Item = f64>) -> Values {
        Values::List(values.into_iter().collect())
    }

    /// `steps` values from `from` to `to`, evenly spaced.
    pub fn linear(from: f64, to: f64, steps: usize) -> Values {
        Values::Range {
            scale: Scale::Linear,
            from,
            to,
            steps,
        }
    }

    /// `steps` values from `from` to `to`, evenly spaced in `log10`.
    pub fn log(from: f64, to: f64, steps: usize) -> Values {
        Values::Range {
            scale: Scale::Log,
            from,
            to,
            steps,
        }
    }

    /// The values as written in a sweep file (numbers in Rust's shortest
    /// round-trip form, with a `.0` or an exponent, so that they read back
    /// exactly).
    ///
    /// ```
    /// use e3d::sweep::Values;
    /// assert_eq!(Values::list([0.1, 100.0]).to_ron(), "[0.1, 100.0]");
    /// assert_eq!(Values::log(1.0, 1e3, 4).to_ron(), "(scale: Log, from: 1.0, to: 1000.0, steps: 4)");
    /// ```
    pub fn to_ron(&self) -> String {
        match self {
            Values::List(v) => {
                let v: Vec<String> = v.iter().map(|x| format!("{x:?}")).collect();
                format!("[{}]", v.join(", "))
            }
            Values::Range {
                scale,
                from,
                to,
                steps,
            } => format!("(scale: {scale:?}, from: {from:?}, to: {to:?}, steps: {steps})"),
        }
    }
}

impl From<f64> for Values {
    /// One value.
    fn from(v: f64) -> Values {
        Values::List(vec![v])
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
            fn visit_seq<A: SeqAccess<'de>>(self, s: A) -> Result<Values, A::Error> {
                Vec::deserialize(de::value::SeqAccessDeserializer::new(s)).map(Values::List)
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
    /// Slots a mutation resamples (goal babbling, archive). One value for
    /// the whole sweep, not a grid axis: `results.csv` has no column for
    /// it and the sessions' seeds do not depend on it.
    #[serde(default)]
    pub k: Option<usize>,
    /// Noise of a mutation of continuous values (one value, as `k`).
    #[serde(default)]
    pub sigma: Option<f64>,
    /// The archive's preference for rarely chosen cells (one value, as `k`).
    #[serde(default)]
    pub rarity: Option<f64>,
    /// Goal babbling's share of goals by learning progress (one value, as `k`).
    #[serde(default)]
    pub goal_progress: Option<f64>,
    /// Per-move Q-learning's initial action-value (one value, as `k`).
    #[serde(default)]
    pub initial: Option<f64>,
}

impl ParamValues {
    /// `base` with the fixed parameters (`k`, `sigma`, `rarity`,
    /// `goal_progress`, `initial`) that are given set.
    pub fn fixed(&self, base: Params) -> Params {
        Params {
            k: self.k.unwrap_or(base.k),
            sigma: self.sigma.unwrap_or(base.sigma),
            rarity: self.rarity.unwrap_or(base.rarity),
            goal_progress: self.goal_progress.unwrap_or(base.goal_progress),
            initial: self.initial.unwrap_or(base.initial),
            ..base
        }
    }

    /// Each parameter given, as a sweep file writes it: the swept ones,
    /// then the fixed ones.
    pub(super) fn given_text(&self) -> Vec<(&'static str, String)> {
        let swept = (Params::SWEPT.into_iter()).filter_map(|n| Some((n, self.get(n)?.to_ron())));
        let k = self.k.map(|k| ("k", k.to_string()));
        let f = [self.sigma, self.rarity, self.goal_progress, self.initial];
        let floats = ["sigma", "rarity", "goal_progress", "initial"]
            .into_iter()
            .zip(f);
        (swept.chain(k))
            .chain(floats.filter_map(|(name, v)| Some((name, format!("{:?}", v?)))))
            .collect()
    }

    pub(crate) fn get(&self, name: &str) -> Option<&Values> {
        match name {
            "alpha" => self.alpha.as_ref(),
            "beta" => self.beta.as_ref(),
            "lambda" => self.lambda.as_ref(),
            "eta" => self.eta.as_ref(),
            _ => self.epsilon.as_ref(),
        }
    }
}

pub(crate) fn set_param(p: &mut Params, i: usize, v: f64) {
    *[
        &mut p.alpha,
        &mut p.beta,
        &mut p.lambda,
        &mut p.eta,
        &mut p.epsilon,
    ][i] = v;
}
