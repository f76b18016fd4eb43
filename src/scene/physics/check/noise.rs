//! The checks of a physics world's `noise` section: spreads that are
//! finite, >= 0 and within bounds (an action's factor stays positive), and
//! start offsets on free dynamic bodies only.

use crate::scene::physics::limits::{MAX_ANGLE_NOISE, MAX_POSITION_NOISE};
use crate::scene::physics::{BodyKind, Per, PhysicsSpec, Spread, StartNoise};
use crate::scene::Invalid;

/// `Err(expected)` unless the spread is finite, >= 0 and reaches at most
/// `max` (below `max` when `below`), `unit` for the message.
fn check_spread(s: Spread, max: f64, below: bool, unit: &str) -> Result<(), String> {
    let (field, v, cut) = match s {
        Spread::Gaussian { sd } => ("sd", sd, 3.0),
        Spread::Uniform { half_width } => ("half_width", half_width, 1.0),
    };
    let r = s.reach();
    if v.is_finite() && v >= 0.0 && (r < max || (!below && r == max)) {
        return Ok(());
    }
    let (close, bound) = (if below { ")" } else { "]" }, max / cut);
    let why = match s {
        Spread::Gaussian { .. } => " (draws are cut at 3 sd)",
        Spread::Uniform { .. } => "",
    };
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    Err(format!(
        "{field} in [0, {bound}{close}{unit}{why}, found {v}"
    ))
}

impl PhysicsSpec {
    /// The `noise` section: the action spread keeps every factor `1 + x`
    /// above 0 (a Gaussian's `sd` at most 1/3, a uniform `half_width`
    /// below 1); start offsets name distinct free dynamic bodies (no
    /// joint's child), with position spreads within
    /// [`MAX_POSITION_NOISE`] m and angle spreads within
    /// [`MAX_ANGLE_NOISE`] rad; body numbers' factors keep a mass above
    /// 0 and a damping or friction at least 0; a body is listed once per
    /// `per` there, and each of its numbers in one entry only.
    pub(super) fn check_noise(&self) -> Result<(), Invalid> {
        let Some(noise) = &self.noise else {
            return Ok(());
        };
        if let Some(e) = noise
            .actions
            .and_then(|a| check_spread(a, 1.0, true, "").err())
        {
            return Err(Invalid::at(
                "actions",
                Some("noise:"),
                &format!("noise on actions: {e}: each action is multiplied by 1 + x, which must stay above 0"),
            ));
        }
        // a free dynamic body (no joint's child), listed once per list
        let free = |name: &str| {
            self.body(name).is_some_and(|b| {
                b.kind == BodyKind::Dynamic && !self.joints.iter().any(|j| j.child == name)
            })
        };
        let mut seen = std::collections::HashSet::new();
        // a body may be listed once per `per` in `body_numbers`
        let mut body = |list: &'static str, k: usize, name: &str, per: Per| {
            let body = crate::text::echo(name);
            let what = if list == "starts" {
                "the start of"
            } else {
                "the numbers of"
            };
            let here = move |field: &str, expected: String| {
                Invalid::new(field, format!("noise on {what} body `{body}`: {expected}"))
                    .within(list, k)
            };
            if !free(name) {
                let expected = "a free dynamic body of the scene (no joint's child)";
                return Err(here("body", expected.into()));
            }
            if !seen.insert((list, name.to_string(), per)) {
                let expected = match list {
                    "starts" => "each body listed once",
                    _ => "each body listed once per `per` (Execution, Session)",
                };
                return Err(here("body", expected.into()));
            }
            Ok(here)
        };
        let mut joints = std::collections::HashSet::new();
        for (k, s) in noise.starts.iter().enumerate() {
            if !s.joint.is_empty() {
                self.check_joint_noise(k, s, joints.insert(s.joint.as_str()))?;
                continue;
            }
            let here = body("starts", k, &s.body, Per::Execution)?;
            for (field, spread, max, unit) in [
                ("position", s.position, MAX_POSITION_NOISE, "m"),
                ("angle", s.angle, MAX_ANGLE_NOISE, "rad"),
            ] {
                if let Some(e) = spread.and_then(|p| check_spread(p, max, false, unit).err()) {
                    return Err(here(field, e));
                }
            }
        }
        let mut numbers = std::collections::HashSet::new();
        for (k, b) in noise.body_numbers.iter().enumerate() {
            let here = body("body_numbers", k, &b.body, b.per)?;
            for (field, spread) in b.spreads() {
                if spread.is_some() && !numbers.insert((b.body.as_str(), field)) {
                    let e = format!("the `{field}` of a body drawn in one entry only (per execution or per session, not both)");
                    return Err(here(field, e));
                }
                // a mass stays above 0, a damping or friction at least 0
                let below = field == "mass";
                if let Some(e) = spread.and_then(|p| check_spread(p, 1.0, below, "").err()) {
                    let e = format!("{e}: the `{field}` is multiplied by 1 + x");
                    return Err(here(field, e));
                }
            }
        }
        Ok(())
    }

    /// A joint's start noise (entry `k` of `starts`, `first`: its joint
    /// not listed before): no `body` nor `position` with it, a known joint,
    /// offsets that stay within its limits (its coordinate is 0 at the
    /// start) and within [`MAX_ANGLE_NOISE`].
    fn check_joint_noise(&self, k: usize, s: &StartNoise, first: bool) -> Result<(), Invalid> {
        let name = crate::text::echo(&s.joint);
        let here = |field: &str, expected: String| {
            Invalid::new(
                field,
                format!("noise on the start of joint `{name}`: {expected}"),
            )
            .within("starts", k)
        };
        let Some(j) = self.joint(&s.joint) else {
            return Err(here("joint", "a joint of the scene".into()));
        };
        if !first {
            return Err(here("joint", "each joint listed once".into()));
        }
        if !s.body.is_empty() || s.position.is_some() {
            let field = if s.body.is_empty() {
                "position"
            } else {
                "body"
            };
            let expected = "a `joint` alone, with its `angle` (its coordinate); a body's start is another entry";
            return Err(here(field, expected.into()));
        }
        let Some(a) = s.angle else { return Ok(()) };
        let unit = j.kind.unit();
        let max = match j.limits {
            Some((lo, hi)) => MAX_ANGLE_NOISE.min(-lo).min(hi),
            None => MAX_ANGLE_NOISE,
        };
        check_spread(a, max, false, unit).map_err(|e| {
            let why = j.limits.map_or(String::new(), |(lo, hi)| {
                format!(" (its limits [{lo}, {hi}] {unit} hold every draw from 0)")
            });
            here("angle", format!("{e}{why}"))
        })
    }
}
