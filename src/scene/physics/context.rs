//! Start contexts of a physics world: named start states, each the
//! scene's start state with some free bodies placed or set moving and some
//! joints turned or set turning, fixed or drawn from a seeded range.

use serde::{Deserialize, Serialize};

/// One start context of a physics world: a name, and the bodies and
/// joints whose start differs from the scene's.
///
/// ```ron
/// contexts: [
///     (name: "room_a", bodies: [(body: "puck", position: (0.5, 2.5))]),
///     (name: "room_b", bodies: [(body: "puck", position: (3.5, 0.5), to: (5.5, 2.5))]),
///     (name: "bent", joints: [(joint: "shoulder", angle: 0.6), (joint: "elbow", angle: -0.3, to: 0.3)]),
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
    /// The joints turned or set turning (the others keep their start
    /// coordinate, 0, and rate, 0). The bodies a joint carries follow it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<JointStart>,
}

/// A joint's coordinate and rate in a context: a hinge's angle from the
/// scene's start pose (rad) and its rate (rad/s), a slider's position along
/// its axis from the start pose (m) and its rate (m/s). A field left out
/// keeps the start's value, 0.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointStart {
    /// The joint, by name.
    pub joint: String,
    /// Its coordinate (rad for a hinge, m for a slider); with `to`, one
    /// end of a range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<f64>,
    /// The other end of a range of coordinates: each start draws the
    /// coordinate uniformly in it (a seeded range; needs `angle`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<f64>,
    /// Its rate (rad/s for a hinge, m/s for a slider).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<f64>,
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
    /// Whether a start is drawn (some body or joint has a range `to`):
    /// such a context runs live, never from a table or the memo.
    pub fn is_sampled(&self) -> bool {
        self.bodies.iter().any(|b| b.to.is_some()) || self.joints.iter().any(|j| j.to.is_some())
    }
}
