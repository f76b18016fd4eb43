//! Start contexts of a physics world: named start states, each the
//! scene's start state with some free bodies placed or set moving, fixed
//! or drawn from a seeded range.

use super::{BodyKind, PhysicsSpec};
use crate::scene::Invalid;
use serde::{Deserialize, Serialize};

/// One start context of a physics world: a name and the bodies whose
/// start differs from the scene's.
///
/// ```ron
/// contexts: [
///     (name: "room_a", bodies: [(body: "puck", position: (0.5, 2.5))]),
///     (name: "room_b", bodies: [(body: "puck", position: (3.5, 0.5), to: (5.5, 2.5))]),
/// ]
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartState {
    /// The context's name (results and pictures).
    pub name: String,
    /// The bodies placed or set moving (the others start as the scene
    /// says).
    #[serde(default)]
    pub bodies: Vec<BodyStart>,
}

/// Where one free body starts in a context, and how it moves. A field left
/// out keeps the scene's value (velocities: 0).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyStart {
    /// The body: a dynamic body that is no joint's child.
    pub body: String,
    /// Its position `(x, y)`, metres; with `to`, a corner of a rectangle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<(f64, f64)>,
    /// The opposite corner of a rectangle of start positions: each start
    /// draws x, then y, uniformly in it (a seeded range; needs `position`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<(f64, f64)>,
    /// Its angle, radians.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<f64>,
    /// Its linear velocity `(vx, vy)`, m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<(f64, f64)>,
    /// Its angular velocity, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angular_velocity: Option<f64>,
}

impl StartState {
    /// Whether a start is drawn (some body has a range `to`): such a
    /// context runs live, never from a table or the memo.
    pub fn is_sampled(&self) -> bool {
        self.bodies.iter().any(|b| b.to.is_some())
    }
}

impl PhysicsSpec {
    /// The number of start contexts: the declared ones, or 1 (the scene's
    /// start).
    pub fn num_contexts(&self) -> usize {
        self.contexts.len().max(1)
    }

    /// The contexts' names (`["start"]` for a scene without contexts).
    pub fn context_names(&self) -> Vec<String> {
        if self.contexts.is_empty() {
            return vec!["start".into()];
        }
        self.contexts.iter().map(|c| c.name.clone()).collect()
    }

    /// Checks the contexts: distinct non-empty names, known free bodies
    /// (dynamic, no joint's child: joint angles are not context fields),
    /// finite numbers, speeds under `max_speed`, `to` only with `position`.
    pub(crate) fn check_contexts(&self) -> Result<(), Invalid> {
        for (k, c) in self.contexts.iter().enumerate() {
            let here = |field: &str, expected: String| Invalid {
                within: Some(("contexts", k)),
                ..Invalid::at(field, None, &format!("context `{}`: {expected}", c.name))
            };
            if c.name.trim().is_empty() || self.contexts[..k].iter().any(|o| o.name == c.name) {
                return Err(here(
                    "name",
                    "a distinct, non-empty name for every context".into(),
                ));
            }
            for (j, b) in c.bodies.iter().enumerate() {
                if c.bodies[..j].iter().any(|o| o.body == b.body) {
                    return Err(here("body", format!("body `{}` listed once", b.body)));
                }
                let Some(spec) = self.bodies.iter().find(|s| s.name == b.body) else {
                    return Err(here(
                        "body",
                        format!("a body of the scene, found `{}`", b.body),
                    ));
                };
                if spec.kind != BodyKind::Dynamic || self.joints.iter().any(|j| j.child == b.body) {
                    return Err(here(
                        "body",
                        format!(
                            "a free dynamic body (no joint's child), found `{}` (joint angles are not context fields)",
                            b.body
                        ),
                    ));
                }
                self.check_body_start(b, &here)?;
            }
        }
        Ok(())
    }

    /// The numbers of one body's start in a context.
    fn check_body_start(
        &self,
        b: &BodyStart,
        here: &dyn Fn(&str, String) -> Invalid,
    ) -> Result<(), Invalid> {
        let fin = |p: (f64, f64)| p.0.is_finite() && p.1.is_finite();
        for (field, p) in [("position", b.position), ("to", b.to)] {
            if p.is_some_and(|p| !fin(p) || p.0.abs() > 1e6 || p.1.abs() > 1e6) {
                return Err(here(
                    field,
                    format!("body `{}`: a finite position within 1e6 m", b.body),
                ));
            }
        }
        if b.to.is_some() && b.position.is_none() {
            return Err(here(
                "to",
                format!(
                    "body `{}`: `to` with a `position` (the range's other corner)",
                    b.body
                ),
            ));
        }
        if b.angle.is_some_and(|a| !a.is_finite() || a.abs() > 1e3) {
            return Err(here(
                "angle",
                format!("body `{}`: a finite angle (rad)", b.body),
            ));
        }
        if let Some(v) = b.velocity {
            if !fin(v) || v.0.hypot(v.1) >= self.max_speed {
                return Err(here(
                    "velocity",
                    format!(
                        "body `{}`: a finite velocity slower than max_speed ({} m/s), found {v:?}",
                        b.body, self.max_speed
                    ),
                ));
            }
        }
        if b.angular_velocity
            .is_some_and(|w| !w.is_finite() || w.abs() > 1e3)
        {
            return Err(here(
                "angular_velocity",
                format!(
                    "body `{}`: a finite angular velocity within 1000 rad/s",
                    b.body
                ),
            ));
        }
        Ok(())
    }
}
