//! Checking a sweep spec: everything that does not depend on the scenes,
//! each mistake placed in the sweep's text.

use super::{set_param, MetricSpec, Scale, SweepSpec, Values, MAX_COMMANDS, MAX_STEPS, MAX_TRIALS};
use crate::learner::Params;
use crate::scene::{Invalid, SceneError};
use crate::sweep::SweepError;

/// What checking a spec finds: the values of each parameter and the
/// metrics kept.
pub(in crate::sweep) struct Checked {
    pub(in crate::sweep) axes: Vec<Vec<f64>>,
    /// The values of each scene axis, in the spec's order.
    pub(in crate::sweep) scene_axes: Vec<Vec<f64>>,
    pub(in crate::sweep) metrics: Vec<MetricSpec>,
}

/// The error at a field (and an anchor in it) of the sweep's text: what
/// was expected.
type Bad<'a> = dyn Fn(&str, Option<&str>, &str) -> SweepError + 'a;

impl SweepSpec {
    /// Checks everything that does not depend on the scenes, placing
    /// mistakes in `text` (`""`: nowhere).
    pub(in crate::sweep) fn check_in(&self, file: &str, text: &str) -> Result<Checked, SweepError> {
        let bad = |field: &str, anchor: Option<&str>, expected: &str| {
            invalid(file, text, field, anchor, expected)
        };
        self.check_fields(&bad)?;
        let axes = self.param_axes(&bad)?;
        let scene_axes = self.scene_axes(&bad)?;
        let metrics = self.checked_metrics(&bad)?;
        Ok(Checked {
            axes,
            scene_axes,
            metrics,
        })
    }

    /// Scenes and learners (each learner once), each of true and false
    /// once in `use_reward`, sessions, trials and commands within their
    /// bounds, a gamma only in closed loop, in [0, 1]: the first mistake,
    /// in this order.
    fn check_fields(&self, bad: &Bad) -> Result<(), SweepError> {
        let spec = self;
        let twice =
            (spec.learners.iter().enumerate()).find(|(i, l)| spec.learners[..*i].contains(l));
        let reward = &spec.use_reward;
        let gamma = spec.gamma.filter(|_| spec.closed_loop);
        let checks: [(bool, &str, String); 12] = [
            (spec.scenes.is_empty(), "scenes", "at least one scene, found none".into()),
            (
                spec.learners.is_empty(),
                "learners",
                "at least one learner (e3d, uniform, egreedy, e3d_relax, count, smm, goal_babbling, archive, qlearning_moves), found none".into(),
            ),
            (
                twice.is_some(),
                "learners",
                format!("each learner once, but `{}` appears twice", twice.map_or("", |t| t.1)),
            ),
            (reward.is_empty(), "use_reward", "[true], [false] or [false, true], found []".into()),
            (
                reward.len() > 2 || (reward.len() == 2 && reward[0] == reward[1]),
                "use_reward",
                "each of true and false once".into(),
            ),
            (spec.sessions == 0, "sessions", "at least 1 session per cell, found 0".into()),
            (spec.trials == 0, "trials", "at least 1 trial per session, found 0".into()),
            (
                spec.trials > MAX_TRIALS,
                "trials",
                format!(
                    "at most {MAX_TRIALS} trials per session (as `e3d run --trials`), found {}",
                    spec.trials
                ),
            ),
            (
                !(1..=MAX_COMMANDS).contains(&spec.commands),
                "commands",
                format!("1 to {MAX_COMMANDS} commands per episode, found {}", spec.commands),
            ),
            {
                let size = crate::episode::check_size(spec.trials, spec.commands);
                (size.is_err(), "commands", size.err().unwrap_or_default())
            },
            (
                spec.gamma.is_some() && !spec.closed_loop,
                "gamma",
                "closed_loop: true with a gamma (the discount of Q_ref and of Q-learning)".into(),
            ),
            (
                gamma.is_some_and(|g| !(0.0..=1.0).contains(&g)),
                "gamma",
                format!("a discount in [0, 1], found {}", gamma.unwrap_or_default()),
            ),
        ];
        match checks.into_iter().find(|c| c.0) {
            Some((_, field, expected)) => Err(bad(field, None, &expected)),
            None => Ok(()),
        }
    }

    /// The values of each hyper-parameter (task 1's where not swept),
    /// after checking the parameters fixed for every cell.
    fn param_axes(&self, bad: &Bad) -> Result<Vec<Vec<f64>>, SweepError> {
        let mut axes: Vec<Vec<f64>> = Vec::with_capacity(5);
        for (i, name) in Params::SWEPT.iter().enumerate() {
            let values = match self.params.get(name) {
                None => vec![Params::TASK1.named()[i].1],
                Some(v) => param_axis(name, i, v, bad)?,
            };
            axes.push(values);
        }
        // the parameters fixed for every cell
        if let Err(e) = self.params.fixed(Params::TASK1).validate() {
            let expected = format!("{}, found {}", e.expected, e.value);
            return Err(bad(e.name, None, &expected));
        }
        Ok(axes)
    }

    /// The values of each scene axis, after checking its path can name a
    /// column (the scenes check that it names a field).
    fn scene_axes(&self, bad: &Bad) -> Result<Vec<Vec<f64>>, SweepError> {
        let mut axes = Vec::with_capacity(self.axes.len());
        for (path, v) in &self.axes {
            let anchor = format!("{path:?}");
            let bad = |expected: &str| bad("axes", Some(&anchor), expected);
            let reserved = ["sessions", "failed"].contains(&path.as_str())
                || crate::sweep::KEY_COLUMNS.contains(&path.as_str());
            let odd = |c: char| !(c.is_ascii_alphanumeric() || "_.[]-".contains(c));
            if reserved || path.is_empty() || path.contains(odd) {
                let expected = format!("a scene field's path of ASCII letters, digits and `_.[]-` (dot-separated names, e.g. joints.j1.damping; it names a column of the results), not a column e3d writes, found `{}`", path.escape_debug());
                return Err(bad(&expected));
            }
            let values = axis_values(v, &bad)?;
            if let Some(x) = values.iter().find(|x| !x.is_finite()) {
                return Err(bad(&format!("finite numbers, found {x}")));
            }
            axes.push(values);
        }
        Ok(axes)
    }

    /// The metrics (the defaults if none are listed): at least one, each
    /// once, a cumulative reward within the trials.
    fn checked_metrics(&self, bad: &Bad) -> Result<Vec<MetricSpec>, SweepError> {
        let metrics = self
            .metrics
            .clone()
            .unwrap_or_else(|| MetricSpec::defaults(self.trials));
        if metrics.is_empty() {
            return Err(bad("metrics", None, "at least one metric, found none"));
        }
        for (i, m) in metrics.iter().enumerate() {
            if let MetricSpec::CumulativeReward(t) = *m {
                if t == 0 || t > self.trials {
                    let trials = self.trials;
                    let expected = format!(
                        "cumulative_reward(T) with T in 1..={trials} (the trials), found {t}"
                    );
                    return Err(bad("metrics", Some("cumulative_reward"), &expected));
                }
            }
            if metrics[..i].contains(m) {
                let twice = format!("each metric once, but `{}` appears twice", m.column());
                return Err(bad("metrics", None, &twice));
            }
        }
        Ok(metrics)
    }
}

/// The values `v` of parameter `name` (the `i`th): those of
/// [`axis_values`], each a valid value of the parameter.
fn param_axis(name: &str, i: usize, v: &Values, bad: &Bad) -> Result<Vec<f64>, SweepError> {
    let values = axis_values(v, &|expected| bad(name, None, expected))?;
    for x in &values {
        let mut p = Params::TASK1;
        set_param(&mut p, i, *x);
        if let Err(e) = p.validate() {
            return Err(bad(name, None, &format!("{}, found {x}", e.expected)));
        }
    }
    Ok(values)
}

/// The values `v` of an axis: a range of 1 to [`MAX_STEPS`] steps
/// between finite bounds (> 0 on a log scale), at least one value,
/// distinct; `bad(expected)` is the error.
fn axis_values(v: &Values, bad: &dyn Fn(&str) -> SweepError) -> Result<Vec<f64>, SweepError> {
    if let Values::Range {
        scale,
        from,
        to,
        steps,
    } = *v
    {
        let checks = [
            (steps == 0, "a range of at least 1 step, found steps: 0".into()),
            (
                steps > MAX_STEPS,
                format!("a range of at most {MAX_STEPS} steps, found steps: {steps}"),
            ),
            (
                !(from.is_finite() && to.is_finite()),
                "finite bounds `from` and `to`".into(),
            ),
            (
                scale == Scale::Log && (from <= 0.0 || to <= 0.0),
                format!(
                    "a log range between two numbers > 0, found from: {from}, to: {to} (a log range cannot reach or cross zero)"
                ),
            ),
        ];
        if let Some((_, expected)) = checks.into_iter().find(|c| c.0) {
            return Err(bad(&expected));
        }
    }
    let values = v.values();
    if values.is_empty() {
        return Err(bad("at least one value, found an empty list"));
    }
    // distinct: equal floats have equal bits once -0 is +0
    // (NaN equals nothing, and the parameters' or scenes' checks refuse it)
    let mut seen = std::collections::HashSet::with_capacity(values.len());
    for x in &values {
        if !x.is_nan() && !seen.insert((x + 0.0).to_bits()) {
            return Err(bad(&format!("distinct values, but {x} appears twice")));
        }
    }
    Ok(values)
}

/// The error at `field` (and `anchor` in it) of sweep `file`, whose text
/// is `text`: what was `expected`.
pub(in crate::sweep) fn invalid(
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
