//! The physics part of the scene format: `world: Physics(...)`.
//!
//! A physics scene lists rigid bodies, revolute joints between them, a
//! schedule (how long each slot acts, how long the world settles), the
//! tracked point whose terminal position is the effect, and the effect grid.
//! Every field is in SI units (metres, kilograms, seconds, radians, newtons);
//! y points up. `docs/scenes.md` ("Physics worlds") documents every field and its
//! default.
//!
//! ```ron
//! world: Physics(
//!     bodies: [
//!         (name: "puck", shape: Ball(radius: 0.2), mass: 1.0, position: (0.5, 2.5)),
//!     ],
//!     schedule: Sequential(phase: 1.0, settle: 2.0),
//!     effect: (body: "puck", grid: (rows: 3, cols: 6, min: (0.0, 0.0), max: (6.0, 3.0))),
//! ),
//! ```

use super::symmetry::Symmetry;
use super::{Action, Invalid, Scene};
use crate::effect::EffectGrid;
use serde::{Deserialize, Serialize};

/// The name that stands for the fixed world frame in joints (`parent:
/// "ground"`). No body may take it.
pub const GROUND: &str = "ground";

/// The largest number of steps one command may take (about 2.8 hours at
/// 1/60 s): a guard against a mistyped duration.
pub const MAX_STEPS: u64 = 600_000;

/// A rigid-body world simulated by Rapier (see [`PhysicsWorld`](crate::world::PhysicsWorld)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicsSpec {
    /// Gravity `(x, y)` in m/s² (default `(0, 0)`: a table seen from above;
    /// `(0, -9.81)` for a vertical plane).
    #[serde(default)]
    pub gravity: (f64, f64),
    /// The time step in seconds (default 1/60).
    #[serde(default = "default_dt")]
    pub dt: f64,
    /// Solver iterations per step (default: Rapier's, 4).
    #[serde(default)]
    pub solver_iterations: Option<usize>,
    /// The largest linear speed, in m/s, a dynamic body may reach before
    /// the command is reported as a blown-up simulation (default 100).
    #[serde(default = "default_max_speed")]
    pub max_speed: f64,
    /// The bodies, in the order they are built.
    pub bodies: Vec<BodySpec>,
    /// Revolute joints between bodies (or a body and `ground`). They must
    /// form trees: every body is the `child` of at most one joint.
    #[serde(default)]
    pub joints: Vec<JointSpec>,
    /// When the slots act, and how long the world runs.
    pub schedule: Schedule,
    /// The tracked point and the grid its terminal position is binned on.
    pub effect: EffectSpec,
    /// A reflection that leaves the scene unchanged (default none): then
    /// of each pair of mirror-image commands only one is simulated, the
    /// other's outcome is its reflection (see [`Symmetry`]). Exact in real
    /// arithmetic, not bit for bit in Rapier.
    #[serde(default)]
    pub symmetry: Option<Symmetry>,
}

fn default_dt() -> f64 {
    1.0 / 60.0
}

fn default_max_speed() -> f64 {
    100.0
}

fn yes() -> bool {
    true
}

/// How a body moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum BodyKind {
    /// Moved by forces, contacts and joints (the default).
    #[default]
    Dynamic,
    /// Moved only by its own velocity (zero here: it stays where it is, but
    /// unlike a fixed body it may be the root of a chain that can be moved by
    /// code).
    Kinematic,
    /// Never moves: walls, floors, bases.
    Fixed,
}

/// A collision shape, in the body's local frame (x along the body's angle).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeSpec {
    /// A disc centred on the body.
    Ball {
        /// Radius in metres.
        radius: f64,
    },
    /// A rectangle centred on the body: full `width` along the local x axis
    /// and full `height` along y (not half extents).
    Cuboid {
        /// Full width in metres.
        width: f64,
        /// Full height in metres.
        height: f64,
    },
    /// A rounded segment from `a` to `b` with the given `radius`.
    Capsule {
        /// One end, local coordinates.
        a: (f64, f64),
        /// The other end.
        b: (f64, f64),
        /// Radius in metres.
        radius: f64,
    },
    /// A segment from `a` to `b` (no thickness: use on fixed bodies).
    Segment {
        /// One end, local coordinates.
        a: (f64, f64),
        /// The other end.
        b: (f64, f64),
    },
    /// An open chain of segments through `points` (no thickness: use on
    /// fixed bodies, for walls).
    Polyline {
        /// At least two points, local coordinates.
        points: Vec<(f64, f64)>,
    },
}

/// A rigid body.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// A unique name (not `ground`).
    pub name: String,
    /// Dynamic (default), Kinematic or Fixed.
    #[serde(default)]
    pub kind: BodyKind,
    /// The collision shape.
    pub shape: ShapeSpec,
    /// Mass in kg. Give `mass` or `density`, not both; default: density 1.
    #[serde(default)]
    pub mass: Option<f64>,
    /// Surface density in kg/m² (the mass is density x area).
    #[serde(default)]
    pub density: Option<f64>,
    /// Start position `(x, y)` of the body's origin, metres (default (0, 0)).
    #[serde(default)]
    pub position: (f64, f64),
    /// Start angle in radians, counter-clockwise (default 0).
    #[serde(default)]
    pub angle: f64,
    /// Linear damping in 1/s (default 0): the speed decays as
    /// `v / (1 + dt * damping)` per step.
    #[serde(default)]
    pub linear_damping: f64,
    /// Angular damping in 1/s (default 0).
    #[serde(default)]
    pub angular_damping: f64,
    /// Contact friction coefficient (default 0.5; pairs take the mean).
    #[serde(default = "half")]
    pub friction: f64,
    /// Restitution in [0, 1] (default 0; pairs take the mean).
    #[serde(default)]
    pub restitution: f64,
    /// Keep the body from rotating (default false).
    #[serde(default)]
    pub lock_rotation: bool,
    /// Whether the body has contacts at all (default true). A body with
    /// `collide: false` passes through everything.
    #[serde(default = "yes")]
    pub collide: bool,
    /// Let the body spin faster than Rapier's cap of 45° per step (default
    /// false). Without it, a body reaching the cap makes the command fail
    /// as diverged rather than silently slowing it down.
    #[serde(default)]
    pub fast_rotation: bool,
}

fn half() -> f64 {
    0.5
}

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
    /// A position motor for [`Action::Target`]: `(stiffness: N·m/rad,
    /// damping: N·m·s/rad)`. It holds angle 0 (the start pose) until a
    /// `Target` moves its set point; default none.
    #[serde(default)]
    pub motor: Option<MotorSpec>,
    /// Whether parent and child collide with each other (default false).
    /// Bodies not joined directly always collide (unless `collide: false`).
    #[serde(default)]
    pub contacts: bool,
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

/// When the slots act. Durations in seconds; steps = round(seconds / dt).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Schedule {
    /// Slot `i` acts at the start of phase `i`, then the world runs `phase`
    /// seconds (forces and torques held during the phase), then `settle`.
    Sequential {
        /// Duration of each slot's phase, seconds.
        phase: f64,
        /// Time the world runs after the last phase, seconds.
        settle: f64,
    },
    /// Every slot acts together during `push` seconds, then the world runs
    /// `settle` seconds with no input.
    Simultaneous {
        /// Duration of the push phase, seconds.
        push: f64,
        /// Time the world runs after the push, seconds.
        settle: f64,
    },
}

/// The tracked point and its binning.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectSpec {
    /// The tracked body.
    pub body: String,
    /// The tracked point in the body's local frame (default (0, 0), its origin).
    #[serde(default)]
    pub point: (f64, f64),
    /// The grid the terminal position is binned on (row 0 at the top);
    /// points outside it count in the nearest border cell.
    pub grid: EffectGrid,
}

/// The number of steps of a duration, `round(seconds / dt)`.
pub fn steps_of(seconds: f64, dt: f64) -> u64 {
    (seconds / dt).round() as u64
}

impl Schedule {
    /// `(steps of one phase, settle steps)` for `dt`, and whether all slots
    /// act together.
    pub fn steps(&self, dt: f64) -> (u64, u64, bool) {
        match *self {
            Schedule::Sequential { phase, settle } => {
                (steps_of(phase, dt), steps_of(settle, dt), false)
            }
            Schedule::Simultaneous { push, settle } => {
                (steps_of(push, dt), steps_of(settle, dt), true)
            }
        }
    }

    /// The total number of steps of a command of `slots` slots.
    pub fn total_steps(&self, dt: f64, slots: usize) -> u64 {
        let (phase, settle, together) = self.steps(dt);
        if together {
            phase + settle
        } else {
            phase * slots as u64 + settle
        }
    }
}

impl BodySpec {
    /// The body's mass in kg, from `mass` or `density` x area.
    pub fn mass_kg(&self) -> f64 {
        match (self.mass, self.density) {
            (Some(m), _) => m,
            (None, d) => d.unwrap_or(1.0) * self.shape.area(),
        }
    }
}

impl ShapeSpec {
    /// The area in m² (0 for segments and polylines).
    pub fn area(&self) -> f64 {
        match self {
            ShapeSpec::Ball { radius } => std::f64::consts::PI * radius * radius,
            ShapeSpec::Cuboid { width, height } => width * height,
            ShapeSpec::Capsule { a, b, radius } => {
                let l = ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt();
                std::f64::consts::PI * radius * radius + 2.0 * radius * l
            }
            ShapeSpec::Segment { .. } | ShapeSpec::Polyline { .. } => 0.0,
        }
    }

    fn numbers(&self) -> Vec<f64> {
        match self {
            ShapeSpec::Ball { radius } => vec![*radius],
            ShapeSpec::Cuboid { width, height } => vec![*width, *height],
            ShapeSpec::Capsule { a, b, radius } => vec![a.0, a.1, b.0, b.1, *radius],
            ShapeSpec::Segment { a, b } => vec![a.0, a.1, b.0, b.1],
            ShapeSpec::Polyline { points } => points.iter().flat_map(|p| [p.0, p.1]).collect(),
        }
    }
}

/// `"name"`, the text that anchors an error on a named item.
fn quoted(name: &str) -> String {
    format!("\"{name}\"")
}

fn finite2(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

/// The world position of local point `p` on a body at `pos`, `angle`.
pub fn to_world_point(pos: (f64, f64), angle: f64, p: (f64, f64)) -> (f64, f64) {
    to_world(pos, angle, p)
}

pub(crate) fn to_world(pos: (f64, f64), angle: f64, p: (f64, f64)) -> (f64, f64) {
    let (s, c) = angle.sin_cos();
    (pos.0 + c * p.0 - s * p.1, pos.1 + s * p.0 + c * p.1)
}

impl PhysicsSpec {
    /// The body named `name`, if any.
    pub fn body(&self, name: &str) -> Option<&BodySpec> {
        self.bodies.iter().find(|b| b.name == name)
    }

    /// The joint named `name`, if any.
    pub fn joint(&self, name: &str) -> Option<&JointSpec> {
        self.joints.iter().find(|j| j.name == name)
    }

    /// Whether copies of this world in one Rapier world (see
    /// [`PhysicsWorld::with_copies`](crate::world::PhysicsWorld::with_copies))
    /// give exactly, bit for bit, the outcomes of one world per command:
    /// when at most one non-fixed body has contacts. With several (arm7's
    /// links touching each other), Rapier's contact ordering differs
    /// between the worlds and the last bits of the terminal points do
    /// too (measured: about 1e-5 m on arm7).
    pub fn copies_are_exact(&self) -> bool {
        self.bodies
            .iter()
            .filter(|b| b.kind != BodyKind::Fixed && b.collide)
            .count()
            <= 1
    }

    /// The effect grid.
    pub fn effect_grid(&self) -> EffectGrid {
        self.effect.grid.clone()
    }

    pub(crate) fn validate(&self, scene: &Scene) -> Result<(), Invalid> {
        let g = self.gravity;
        if !finite2(g) {
            return Err(Invalid::at("gravity", None, "finite numbers (m/s²)"));
        }
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= 1.0) {
            return Err(Invalid::at(
                "dt",
                None,
                &format!("a time step in (0, 1] seconds, found {}", self.dt),
            ));
        }
        if let Some(n) = self.solver_iterations {
            if n == 0 || n > 1000 {
                return Err(Invalid::at(
                    "solver_iterations",
                    None,
                    &format!("between 1 and 1000 iterations, found {n}"),
                ));
            }
        }
        if !(self.max_speed.is_finite() && self.max_speed > 0.0) {
            return Err(Invalid::at(
                "max_speed",
                None,
                &format!("a speed > 0 in m/s, found {}", self.max_speed),
            ));
        }
        if self.bodies.is_empty() {
            return Err(Invalid::at("bodies", None, "at least one body"));
        }
        for (i, b) in self.bodies.iter().enumerate() {
            self.validate_body(b, i)?;
        }
        let mut parent_of: Vec<Option<usize>> = vec![None; self.bodies.len()];
        for (i, j) in self.joints.iter().enumerate() {
            let at = quoted(&j.name);
            if j.name.trim().is_empty() {
                return Err(Invalid::at("name", None, "a non-empty joint name"));
            }
            if self.joints[..i].iter().any(|o| o.name == j.name) {
                return Err(Invalid {
                    nth: 1,
                    ..Invalid::at(
                        "name",
                        Some(&at),
                        &format!("distinct joint names, but `{}` is used twice", j.name),
                    )
                });
            }
            let pb = if j.parent == GROUND {
                None
            } else {
                match self.bodies.iter().position(|b| b.name == j.parent) {
                    Some(p) => Some(p),
                    None => {
                        return Err(self.unknown_body(
                            "parent",
                            &j.parent,
                            &format!("joint `{}`", j.name),
                        ))
                    }
                }
            };
            if j.child == GROUND {
                return Err(Invalid::at(
                    "child",
                    Some(&at),
                    &format!(
                        "joint `{}`: a body as child; `ground` can only be a parent",
                        j.name
                    ),
                ));
            }
            let cb = match self.bodies.iter().position(|b| b.name == j.child) {
                Some(c) => c,
                None => {
                    return Err(self.unknown_body(
                        "child",
                        &j.child,
                        &format!("joint `{}`", j.name),
                    ))
                }
            };
            if pb == Some(cb) {
                return Err(Invalid::at(
                    "child",
                    Some(&at),
                    &format!(
                        "joint `{}`: two different bodies, but it joins `{}` to itself",
                        j.name, j.child
                    ),
                ));
            }
            if self.bodies[cb].kind != BodyKind::Dynamic {
                return Err(Invalid::at(
                    "child",
                    Some(&at),
                    &format!(
                        "joint `{}`: a dynamic child body, but `{}` is {:?}",
                        j.name, j.child, self.bodies[cb].kind
                    ),
                ));
            }
            if let Some(p) = parent_of[cb] {
                return Err(Invalid::at(
                    "child",
                    Some(&at),
                    &format!(
                        "joint `{}`: a body that is the child of one joint only (joints form trees), but `{}` is already the child of `{}`",
                        j.name, j.child, self.joints[p].name
                    ),
                ));
            }
            parent_of[cb] = Some(i);
            // no loops: walk up from the parent
            let mut up = pb;
            let mut hops = 0;
            while let Some(b) = up {
                if b == cb || hops > self.bodies.len() {
                    return Err(Invalid::at(
                        "parent",
                        Some(&at),
                        &format!(
                            "joint `{}`: joints that form trees, but this one closes a loop",
                            j.name
                        ),
                    ));
                }
                hops += 1;
                up = parent_of[b].and_then(|k| {
                    let p = &self.joints[k].parent;
                    self.bodies.iter().position(|x| &x.name == p)
                });
            }
            for (field, v) in [
                ("parent_anchor", j.parent_anchor),
                ("child_anchor", j.child_anchor),
            ] {
                if !finite2(v) {
                    return Err(Invalid::at(
                        field,
                        Some(&at),
                        &format!("joint `{}`: finite coordinates", j.name),
                    ));
                }
            }
            if let Some((lo, hi)) = j.limits {
                if !(lo.is_finite() && hi.is_finite() && lo <= 0.0 && 0.0 <= hi && lo < hi) {
                    return Err(Invalid::at(
                        "limits",
                        Some(&at),
                        &format!(
                            "joint `{}`: finite limits (min, max) with min <= 0 <= max and min < max (angle 0 is the start pose), found ({lo}, {hi})",
                            j.name
                        ),
                    ));
                }
            }
            if !(j.damping.is_finite() && j.damping >= 0.0) {
                return Err(Invalid::at(
                    "damping",
                    Some(&at),
                    &format!(
                        "joint `{}`: a damping >= 0 in N·m·s/rad, found {}",
                        j.name, j.damping
                    ),
                ));
            }
            if let Some(m) = j.motor {
                if !(m.stiffness.is_finite()
                    && m.stiffness > 0.0
                    && m.damping.is_finite()
                    && m.damping >= 0.0)
                {
                    return Err(Invalid::at(
                        "motor",
                        Some(&at),
                        &format!(
                            "joint `{}`: a motor with stiffness > 0 and damping >= 0, found ({}, {})",
                            j.name, m.stiffness, m.damping
                        ),
                    ));
                }
            }
            // the anchors must meet at the start pose
            let pa = match pb {
                None => j.parent_anchor,
                Some(p) => to_world(
                    self.bodies[p].position,
                    self.bodies[p].angle,
                    j.parent_anchor,
                ),
            };
            let c = &self.bodies[cb];
            let ca = to_world(c.position, c.angle, j.child_anchor);
            let gap = ((pa.0 - ca.0).powi(2) + (pa.1 - ca.1).powi(2)).sqrt();
            if gap > 1e-6 {
                return Err(Invalid::at(
                    "child_anchor",
                    Some(&at),
                    &format!(
                        "joint `{}`: anchors that meet at the start pose, but the parent's is at ({:.4}, {:.4}) and the child's at ({:.4}, {:.4})",
                        j.name, pa.0, pa.1, ca.0, ca.1
                    ),
                ));
            }
        }
        // the schedule
        let (field, values) = match self.schedule {
            Schedule::Sequential { phase, settle } => ("phase", [phase, settle]),
            Schedule::Simultaneous { push, settle } => ("push", [push, settle]),
        };
        for (f, v) in [(field, values[0]), ("settle", values[1])] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Invalid::at(
                    f,
                    None,
                    &format!("a duration >= 0 in seconds, found {v}"),
                ));
            }
            let steps = v / self.dt;
            if (steps - steps.round()).abs() > 1e-6 * steps.max(1.0) {
                return Err(Invalid::at(
                    f,
                    None,
                    &format!(
                        "a whole number of time steps ({v} s / dt {} = {steps:.4} steps)",
                        self.dt
                    ),
                ));
            }
        }
        let (phase, _, _) = self.schedule.steps(self.dt);
        if phase == 0 {
            return Err(Invalid::at(
                field,
                None,
                "at least one time step in which the slots act",
            ));
        }
        let n = scene.slots().count();
        let total = self.schedule.total_steps(self.dt, n);
        if total > MAX_STEPS {
            return Err(Invalid::at(
                field,
                None,
                &format!("at most {MAX_STEPS} steps per command, found {total}"),
            ));
        }
        // the effect
        if self.body(&self.effect.body).is_none() {
            return Err(self.unknown_body("body", &self.effect.body, "the effect's tracked point"));
        }
        if !finite2(self.effect.point) {
            return Err(Invalid::at(
                "point",
                None,
                "a tracked point with finite coordinates",
            ));
        }
        self.effect
            .grid
            .validate()
            .map_err(|e| Invalid::at("grid", None, &format!("a valid grid: {e}")))?;
        // the actions
        let mut seen: Vec<char> = Vec::new();
        for alphabet in scene.slots() {
            for s in alphabet {
                let nth = seen.iter().filter(|&&c| c == s.symbol).count();
                seen.push(s.symbol);
                let at = format!("'{}'", s.symbol);
                let bad = |what: String| Invalid {
                    nth,
                    ..Invalid::at(
                        "action",
                        Some(&at),
                        &format!("symbol '{}': {what}", s.symbol),
                    )
                };
                match &s.action {
                    Action::Idle => {}
                    Action::Move { .. } => {
                        return Err(bad(
                            "Torque, Impulse, Force, Target or Idle in a Physics world (Move is for Grid worlds)".into(),
                        ))
                    }
                    Action::Torque { joint, torque } => {
                        self.known_joint(joint, &bad)?;
                        if !torque.is_finite() {
                            return Err(bad(format!("a finite torque in N·m, found {torque}")));
                        }
                    }
                    Action::Target { joint, angle } => {
                        let j = self.known_joint(joint, &bad)?;
                        if j.motor.is_none() {
                            return Err(bad(format!(
                                "a Target on a joint with a `motor: (stiffness: ..., damping: ...)`, but joint `{joint}` has none"
                            )));
                        }
                        if !angle.is_finite() {
                            return Err(bad(format!("a finite angle in radians, found {angle}")));
                        }
                        if let Some((lo, hi)) = j.limits {
                            if *angle < lo || *angle > hi {
                                return Err(bad(format!(
                                    "a target within joint `{joint}`'s limits ({lo}, {hi}), found {angle}"
                                )));
                            }
                        }
                    }
                    Action::Impulse { body, impulse: v } | Action::Force { body, force: v } => {
                        let b = match self.body(body) {
                            Some(b) => b,
                            None => {
                                return Err(bad(format!(
                                    "a known body, but there is no body `{body}`; bodies: {}",
                                    self.body_names()
                                )))
                            }
                        };
                        if b.kind != BodyKind::Dynamic {
                            return Err(bad(format!("a dynamic body, but `{body}` is {:?}", b.kind)));
                        }
                        if !finite2(*v) {
                            return Err(bad("finite components".into()));
                        }
                    }
                }
            }
        }
        if let Some(sym) = self.symmetry {
            sym.validate(self, scene)?;
        }
        Ok(())
    }

    fn body_names(&self) -> String {
        let names: Vec<&str> = self.bodies.iter().map(|b| b.name.as_str()).collect();
        names.join(", ")
    }

    fn unknown_body(&self, field: &str, name: &str, whose: &str) -> Invalid {
        let names: Vec<&str> = self.bodies.iter().map(|b| b.name.as_str()).collect();
        Invalid::at(
            field,
            Some(&quoted(name)),
            &format!(
                "{whose}: a known body{}, but there is no body `{name}`{}; bodies: {}",
                if field == "parent" {
                    " or `ground`"
                } else {
                    ""
                },
                super::error::did_you_mean(name, &names),
                names.join(", ")
            ),
        )
    }

    fn known_joint(
        &self,
        name: &str,
        bad: &dyn Fn(String) -> Invalid,
    ) -> Result<&JointSpec, Invalid> {
        self.joint(name).ok_or_else(|| {
            let names: Vec<&str> = self.joints.iter().map(|j| j.name.as_str()).collect();
            bad(format!(
                "a known joint, but there is no joint `{name}`{}; joints: {}",
                super::error::did_you_mean(name, &names),
                if names.is_empty() {
                    "none".to_string()
                } else {
                    names.join(", ")
                }
            ))
        })
    }

    fn validate_body(&self, b: &BodySpec, i: usize) -> Result<(), Invalid> {
        let at = quoted(&b.name);
        if b.name.trim().is_empty() {
            return Err(Invalid::at("name", None, "a non-empty body name"));
        }
        if b.name == GROUND {
            return Err(Invalid::at(
                "name",
                Some(&at),
                "a body name other than `ground` (it stands for the fixed world frame)",
            ));
        }
        if self.bodies[..i].iter().any(|o| o.name == b.name) {
            return Err(Invalid {
                nth: 1,
                ..Invalid::at(
                    "name",
                    Some(&at),
                    &format!("distinct body names, but `{}` is used twice", b.name),
                )
            });
        }
        let who = format!("body `{}`", b.name);
        if !b.shape.numbers().iter().all(|v| v.is_finite()) {
            return Err(Invalid::at(
                "shape",
                Some(&at),
                &format!("{who}: finite numbers in its shape"),
            ));
        }
        match &b.shape {
            ShapeSpec::Ball { radius } | ShapeSpec::Capsule { radius, .. } if *radius <= 0.0 => {
                return Err(Invalid::at(
                    "radius",
                    Some(&at),
                    &format!("{who}: a radius > 0, found {radius}"),
                ))
            }
            ShapeSpec::Cuboid { width, height } if *width <= 0.0 || *height <= 0.0 => {
                return Err(Invalid::at(
                    "shape",
                    Some(&at),
                    &format!("{who}: a width and height > 0, found {width} x {height}"),
                ))
            }
            ShapeSpec::Segment { a, b: e } if a == e => {
                return Err(Invalid::at(
                    "shape",
                    Some(&at),
                    &format!("{who}: a segment of two distinct points"),
                ))
            }
            ShapeSpec::Polyline { points } if points.len() < 2 => {
                return Err(Invalid::at(
                    "points",
                    Some(&at),
                    &format!("{who}: at least two points"),
                ))
            }
            _ => {}
        }
        if b.mass.is_some() && b.density.is_some() {
            return Err(Invalid::at(
                "mass",
                Some(&at),
                &format!("{who}: `mass` or `density`, not both"),
            ));
        }
        if let Some(m) = b.mass {
            if !(m.is_finite() && m > 0.0) {
                return Err(Invalid::at(
                    "mass",
                    Some(&at),
                    &format!("{who}: a mass > 0 in kg, found {m}"),
                ));
            }
        }
        if let Some(d) = b.density {
            if !(d.is_finite() && d > 0.0) {
                return Err(Invalid::at(
                    "density",
                    Some(&at),
                    &format!("{who}: a density > 0 in kg/m², found {d}"),
                ));
            }
        }
        if b.kind == BodyKind::Dynamic {
            if b.shape.area() <= 0.0 && b.mass.is_none() {
                return Err(Invalid::at(
                    "mass",
                    Some(&at),
                    &format!("{who}: a `mass` (a dynamic segment or polyline has no area, so no mass from its density)"),
                ));
            }
            if b.mass_kg().is_nan() || b.mass_kg() <= 0.0 {
                return Err(Invalid::at(
                    "mass",
                    Some(&at),
                    &format!("{who}: a mass > 0"),
                ));
            }
            if b.shape.area() <= 0.0 && !b.lock_rotation {
                return Err(Invalid::at(
                    "shape",
                    Some(&at),
                    &format!("{who}: a shape with an area (Ball, Cuboid, Capsule) for a dynamic body that rotates"),
                ));
            }
        }
        if !finite2(b.position) || !b.angle.is_finite() {
            return Err(Invalid::at(
                "position",
                Some(&at),
                &format!("{who}: a finite start pose"),
            ));
        }
        for (f, v) in [
            ("linear_damping", b.linear_damping),
            ("angular_damping", b.angular_damping),
            ("friction", b.friction),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Invalid::at(
                    f,
                    Some(&at),
                    &format!("{who}: a finite number >= 0, found {v}"),
                ));
            }
        }
        if !(b.restitution.is_finite() && (0.0..=1.0).contains(&b.restitution)) {
            return Err(Invalid::at(
                "restitution",
                Some(&at),
                &format!("{who}: a restitution in [0, 1], found {}", b.restitution),
            ));
        }
        Ok(())
    }
}
