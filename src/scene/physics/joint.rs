//! The joints of the physics part of the scene format: hinges and
//! sliders between two bodies (or a body and ground), with their motors.

use super::limits::{MAX_ANGLE, MAX_LENGTH};
use serde::{Deserialize, Serialize};

/// A revolute joint (a hinge) between `parent` and `child`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct JointSpec {
    /// A unique name (actions refer to joints by name).
    pub name: String,
    /// The parent body, or `ground` (the fixed world frame).
    pub parent: String,
    /// The child body: dynamic, and the child of no other joint.
    pub child: String,
    /// The hinge in the parent's local frame (in world coordinates when the
    /// parent is `ground`), metres (default (0, 0)).
    #[serde(default)]
    pub parent_anchor: (f64, f64),
    /// The hinge in the child's local frame, metres (default (0, 0)). At
    /// the start pose both anchors must be the same point.
    #[serde(default)]
    pub child_anchor: (f64, f64),
    /// Joint limits `(min, max)` in radians, relative to the start pose
    /// (angle 0); default none.
    #[serde(default)]
    pub limits: Option<(f64, f64)>,
    /// Viscous damping in N·m·s/rad (default 0), integrated implicitly by
    /// the multibody solver.
    #[serde(default)]
    pub damping: f64,
    /// A position motor for [`Action::Target`](crate::scene::Action::Target): `(stiffness: N·m/rad,
    /// damping: N·m·s/rad)`. It holds angle 0 (the start pose) until a
    /// `Target` moves its set point; default none.
    #[serde(default)]
    pub motor: Option<MotorSpec>,
    /// Whether parent and child collide with each other (default false).
    /// Bodies not joined directly always collide (unless `collide: false`).
    #[serde(default)]
    pub contacts: bool,
    /// What the joint allows: a rotation (`Revolute`, the default) or a
    /// translation along an axis (`Prismatic(axis: (x, y))`, a slider).
    /// For a slider, `limits` are positions in m, `damping` is in N·s/m,
    /// the motor's gains are in N/m and N·s/m, and a `Target` is a
    /// position in m along the axis, 0 at the start pose.
    #[serde(default, skip_serializing_if = "JointKind::is_revolute")]
    pub kind: JointKind,
}

/// What a joint lets its child do relative to its parent.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum JointKind {
    /// A hinge: rotation about the anchor (the default).
    #[default]
    Revolute,
    /// A slider: translation along `axis` (in the parent's local frame,
    /// world coordinates for `ground`; any non-zero length, normalised),
    /// no relative rotation.
    Prismatic {
        /// The direction of travel `(x, y)`.
        axis: (f64, f64),
    },
}

impl JointKind {
    /// Whether this is the default, a hinge.
    pub fn is_revolute(&self) -> bool {
        matches!(self, JointKind::Revolute)
    }

    /// The unit of the joint's coordinate: `rad` for a hinge, `m` for a
    /// slider.
    pub fn unit(&self) -> &'static str {
        self.coordinate().1
    }

    /// The joint's coordinate, its unit and the bound of its magnitude:
    /// `angle` in `rad` up to [`MAX_ANGLE`] for a hinge, `position` in `m`
    /// up to [`MAX_LENGTH`] for a slider.
    pub(crate) fn coordinate(&self) -> (&'static str, &'static str, f64) {
        match self {
            JointKind::Revolute => ("angle", "rad", MAX_ANGLE),
            JointKind::Prismatic { .. } => ("position", "m", MAX_LENGTH),
        }
    }
}

impl JointSpec {
    /// The joint's unit axis in its parent's frame (a slider's), `None`
    /// for a hinge.
    pub fn axis(&self) -> Option<(f64, f64)> {
        match self.kind {
            JointKind::Revolute => None,
            JointKind::Prismatic { axis } => {
                let n = axis.0.hypot(axis.1);
                Some((axis.0 / n, axis.1 / n))
            }
        }
    }
}

/// A position motor's gains.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotorSpec {
    /// Stiffness in N·m/rad (> 0).
    pub stiffness: f64,
    /// Damping in N·m·s/rad (>= 0).
    #[serde(default)]
    pub damping: f64,
}

/// Viscous drag, anisotropic like a slender body's in a fluid (MuJoCo's
/// fluid model for a capsule): with `u` the body's local x axis in the
/// world, `n` its normal and `v` the velocity of its centre of mass, the
/// force `-(along (v·u) u + across (v·n) n)` and the torque `-turn ω` act
/// at the centre of mass, set from the velocity at the start of each step.
///
/// ```ron
/// drag: (along: 0.05, across: 1.0, turn: 0.01),
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DragSpec {
    /// N·s/m against the velocity along the body's local x axis.
    pub along: f64,
    /// N·s/m against the velocity across it (its local y axis).
    pub across: f64,
    /// N·m·s/rad against its spin (default 0).
    #[serde(default)]
    pub turn: f64,
}

impl DragSpec {
    /// The drag force (N) on a body at `angle` moving at `v` (m/s), and
    /// the torque (N·m) at spin `w` (rad/s).
    pub fn force(&self, angle: f64, v: (f64, f64), w: f64) -> ((f64, f64), f64) {
        let (s, c) = angle.sin_cos();
        let along = c * v.0 + s * v.1;
        let across = -s * v.0 + c * v.1;
        let (fa, fn_) = (-self.along * along, -self.across * across);
        ((c * fa - s * fn_, s * fa + c * fn_), -self.turn * w)
    }
}
