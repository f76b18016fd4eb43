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

use super::shorthand::{ChainSpec, WallSpec};
use super::symmetry::Symmetry;
use super::{Action, Invalid, Scene};
use crate::effect::EffectGrid;
use serde::{Deserialize, Serialize};
use std::collections::{HashMap, HashSet};

/// The name that stands for the fixed world frame in joints (`parent:
/// "ground"`). No body may take it.
pub const GROUND: &str = "ground";

/// The largest number of steps one command may take (about 2.8 hours at
/// 1/60 s): a guard against a mistyped duration.
pub const MAX_STEPS: u64 = 600_000;

/// The bounds of the numbers of a physics scene: what Rapier, which
/// computes in `f32`, can hold, and what one step can carry. A value
/// outside is refused at load with the field, the value and the bound
/// (`docs/robustness.md`, "Numbers a physics scene may hold").
pub mod limits {
    /// Coordinates, anchors, tracked point, grid corners and sizes, in
    /// metres: `f32` still resolves 1 mm at this distance from the origin.
    pub const MAX_LENGTH: f64 = 1e4;
    /// Radius, width and height, in metres.
    pub const MIN_SIZE: f64 = 1e-4;
    /// A dynamic body's mass (given or from its density), kg.
    pub const MIN_MASS: f64 = 1e-6;
    /// A dynamic body's mass, kg.
    pub const MAX_MASS: f64 = 1e9;
    /// Densities, kg/m².
    pub const MIN_DENSITY: f64 = 1e-6;
    /// Densities, kg/m².
    pub const MAX_DENSITY: f64 = 1e9;
    /// Angles (start angles, joint limits, targets), radians.
    pub const MAX_ANGLE: f64 = 1e3;
    /// The magnitude of gravity, m/s².
    pub const MAX_GRAVITY: f64 = 1e6;
    /// `max_speed`, m/s: below Rapier's own cap of 400 m/s, which would
    /// otherwise slow a body down silently before the check sees it.
    pub const MAX_SPEED: f64 = 399.0;
    /// The speed (m/s) or spin (rad/s) one impulse, force or torque may add
    /// to a body in one step, computed on the body alone (its mass, its
    /// inertia about its centre): far above any `max_speed`, so such a
    /// command is reported as blown up, yet far below the 1.8e19 m/s whose
    /// square overflows `f32` (Rapier then stops the body silently, or
    /// panics in a motor constraint).
    pub const MAX_STEP_CHANGE: f64 = 1e6;
    /// Dampings and motor gains.
    pub const MAX_COEFFICIENT: f64 = 1e9;
    /// Friction coefficients.
    pub const MAX_FRICTION: f64 = 1e3;
    /// A non-zero number smaller in magnitude is 0 or subnormal in `f32`
    /// (`f32::MIN_POSITIVE`, about 1.2e-38): refused rather than read as 0.
    pub const MIN_MAGNITUDE: f64 = f32::MIN_POSITIVE as f64;
    /// Bodies in a scene.
    pub const MAX_BODIES: usize = 10_000;
    /// Joints in a scene.
    pub const MAX_JOINTS: usize = 10_000;
    /// Points of one polyline.
    pub const MAX_POINTS: usize = 100_000;
}

use limits::*;

/// `Err` unless `v` is finite, in `[lo, hi]` (magnitude `|v|` when
/// `signed`), and 0 or at least [`MIN_MAGNITUDE`] in magnitude.
fn in_range(v: f64, lo: f64, hi: f64, signed: bool) -> bool {
    let m = if signed { v.abs() } else { v };
    v.is_finite() && m >= lo && m <= hi && (v == 0.0 || v.abs() >= MIN_MAGNITUDE)
}

/// A number's bounds, for messages: `"in [lo, hi] UNIT"`, `"|v| <= hi UNIT"`.
fn bounds(lo: f64, hi: f64, signed: bool, unit: &str) -> String {
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    let tiny = "0 or at least 1.2e-38 in magnitude (f32)";
    match (signed, lo) {
        (true, _) => format!("|value| <= {}{unit}, {tiny}", show(hi)),
        (false, 0.0) => format!("in [0, {}]{unit}, {tiny}", show(hi)),
        (false, l) => format!("in [{}, {}]{unit}", show(l), show(hi)),
    }
}

/// A number for messages: as written for ordinary magnitudes, else in
/// scientific notation (`1e39`, not 39 digits).
pub(crate) fn show(v: f64) -> String {
    let s = if v == 0.0 || !v.is_finite() || (1e-4..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    };
    if s.len() <= 12 {
        return s;
    }
    // a computed value: 5 significant digits
    let s = if (1e-4..1e6).contains(&v.abs()) {
        format!(
            "{v:.*}",
            (4 - v.abs().log10().floor() as i64).max(0) as usize
        )
    } else {
        format!("{v:.4e}")
    };
    let (m, e) = s
        .split_once('e')
        .map_or((s.as_str(), None), |(m, e)| (m, Some(e)));
    let m = if m.contains('.') {
        m.trim_end_matches('0').trim_end_matches('.')
    } else {
        m
    };
    match e {
        Some(e) => format!("{m}e{e}"),
        None => m.to_string(),
    }
}

/// The check of one number: `who: WHAT BOUNDS, found V`.
#[allow(clippy::too_many_arguments)]
fn number(
    field: &str,
    anchor: Option<&str>,
    who: &str,
    what: &str,
    v: f64,
    (lo, hi): (f64, f64),
    signed: bool,
    unit: &str,
) -> Result<(), Invalid> {
    if in_range(v, lo, hi, signed) {
        return Ok(());
    }
    let who = if who.is_empty() {
        String::new()
    } else {
        format!("{who}: ")
    };
    Err(Invalid::at(
        field,
        anchor,
        &format!(
            "{who}{what} {}, found {}",
            bounds(lo, hi, signed, unit),
            show(v)
        ),
    ))
}

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
    /// The bodies, in the order they are built (default none: a scene
    /// of shorthands only). After the shorthands' expansion, the walls'
    /// boxes and the chains' links come first (see [`shorthand`](super::shorthand)).
    #[serde(default)]
    pub bodies: Vec<BodySpec>,
    /// Revolute joints between bodies (or a body and `ground`). They must
    /// form trees: every body is the `child` of at most one joint.
    #[serde(default)]
    pub joints: Vec<JointSpec>,
    /// When the slots act, and how long the world runs.
    pub schedule: Schedule,
    /// The tracked point and the grid its terminal position is binned on.
    pub effect: EffectSpec,
    /// Serial chains of box links (default none): a shorthand for their
    /// bodies and joints, expanded at load (see [`ChainSpec`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub chains: Vec<ChainSpec>,
    /// Fixed walls along polylines or around rooms, with doors (default
    /// none): a shorthand for their boxes, expanded at load (see
    /// [`WallSpec`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub walls: Vec<WallSpec>,
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

impl BodySpec {
    /// The body's moment of inertia about its centre of mass, kg·m², or a
    /// lower bound of it (a capsule counts as its disc of `radius`); `None`
    /// for a body that does not turn (not dynamic, or `lock_rotation`).
    pub fn min_inertia(&self) -> Option<f64> {
        if self.kind != BodyKind::Dynamic || self.lock_rotation {
            return None;
        }
        let m = self.mass_kg();
        match self.shape {
            ShapeSpec::Ball { radius } | ShapeSpec::Capsule { radius, .. } => {
                Some(0.5 * m * radius * radius)
            }
            ShapeSpec::Cuboid { width, height } => {
                Some(m * (width * width + height * height) / 12.0)
            }
            ShapeSpec::Segment { .. } | ShapeSpec::Polyline { .. } => None,
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

    /// Whether the world still holds shorthands (`chains`, `walls`) to
    /// expand ([`Scene::expand`](crate::Scene::expand)); never for a
    /// loaded scene.
    pub fn has_shorthands(&self) -> bool {
        !(self.chains.is_empty() && self.walls.is_empty())
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
        for c in [g.0, g.1] {
            number(
                "gravity",
                None,
                "",
                "components",
                c,
                (0.0, MAX_GRAVITY),
                true,
                "m/s²",
            )?;
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
        if !(self.max_speed > 0.0 && in_range(self.max_speed, MIN_MAGNITUDE, MAX_SPEED, false)) {
            return Err(Invalid::at(
                "max_speed",
                None,
                &format!(
                    "a speed in [1.2e-38, {MAX_SPEED}] m/s (Rapier caps speeds at 400 m/s, silently), found {}",
                    show(self.max_speed)
                ),
            ));
        }
        if self.bodies.is_empty() {
            return Err(Invalid::at("bodies", None, "at least one body"));
        }
        if self.bodies.len() > MAX_BODIES {
            return Err(Invalid::at(
                "bodies",
                None,
                &format!("at most {MAX_BODIES} bodies, found {}", self.bodies.len()),
            ));
        }
        if self.joints.len() > MAX_JOINTS {
            return Err(Invalid::at(
                "joints",
                None,
                &format!("at most {MAX_JOINTS} joints, found {}", self.joints.len()),
            ));
        }
        // names to indices: linear in the number of bodies and joints
        let mut index: HashMap<&str, usize> = HashMap::with_capacity(self.bodies.len());
        for (i, b) in self.bodies.iter().enumerate() {
            let first = *index.entry(b.name.as_str()).or_insert(i);
            self.validate_body(b, first != i)?;
        }
        let position = |name: &str| index.get(name).copied();
        let mut joint_names: HashSet<&str> = HashSet::with_capacity(self.joints.len());
        let mut parent_of: Vec<Option<usize>> = vec![None; self.bodies.len()];
        for (i, j) in self.joints.iter().enumerate() {
            let at = quoted(&j.name);
            if j.name.trim().is_empty() {
                return Err(Invalid::at("name", None, "a non-empty joint name"));
            }
            if !joint_names.insert(j.name.as_str()) {
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
                match position(&j.parent) {
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
            let cb = match position(&j.child) {
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
                up = parent_of[b].and_then(|k| position(&self.joints[k].parent));
            }
            let who = format!("joint `{}`", j.name);
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
                for c in [v.0, v.1] {
                    number(
                        field,
                        Some(&at),
                        &who,
                        "coordinates",
                        c,
                        (0.0, MAX_LENGTH),
                        true,
                        "m",
                    )?;
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
                for v in [lo, hi] {
                    number(
                        "limits",
                        Some(&at),
                        &who,
                        "limits",
                        v,
                        (0.0, MAX_ANGLE),
                        true,
                        "rad",
                    )?;
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
            number(
                "damping",
                Some(&at),
                &who,
                "a damping",
                j.damping,
                (0.0, MAX_COEFFICIENT),
                false,
                "N·m·s/rad",
            )?;
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
                number(
                    "stiffness",
                    Some(&at),
                    &who,
                    "a motor stiffness",
                    m.stiffness,
                    (MIN_MAGNITUDE, MAX_COEFFICIENT),
                    false,
                    "N·m/rad",
                )?;
                number(
                    "motor",
                    Some(&at),
                    &who,
                    "a motor damping",
                    m.damping,
                    (0.0, MAX_COEFFICIENT),
                    false,
                    "N·m·s/rad",
                )?;
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
            number(
                f,
                None,
                "",
                "a duration",
                v,
                (0.0, MAX_STEPS as f64),
                false,
                "s",
            )?;
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
        for c in [self.effect.point.0, self.effect.point.1] {
            number(
                "point",
                None,
                "the tracked point",
                "coordinates",
                c,
                (0.0, MAX_LENGTH),
                true,
                "m",
            )?;
        }
        self.effect
            .grid
            .validate()
            .map_err(|e| Invalid::at("grid", None, &format!("a valid grid: {e}")))?;
        for &c in self.effect.grid.min.iter().chain(&self.effect.grid.max) {
            number(
                "grid",
                None,
                "the effect grid",
                "corners",
                c,
                (0.0, MAX_LENGTH),
                true,
                "m",
            )?;
        }
        // the actions
        let mut seen: HashMap<char, usize> = HashMap::new();
        for alphabet in scene.slots() {
            for s in alphabet {
                let count = seen.entry(s.symbol).or_insert(0);
                let nth = *count;
                *count += 1;
                let at = format!("'{}'", s.symbol);
                let bad_at = |field: &str, what: String| Invalid {
                    nth,
                    ..Invalid::at(field, Some(&at), &format!("symbol '{}': {what}", s.symbol))
                };
                self.check_action(&s.action, &position, &bad_at)?;
            }
        }
        // the values of continuous slots: the action at both ends of the
        // range (every check above is monotonic in the magnitude)
        if let super::CommandSpec::Continuous(slots) = &scene.command {
            if self.symmetry.is_some() {
                return Err(Invalid::at(
                    "symmetry",
                    None,
                    "no symmetry with continuous slots (a symmetry maps symbols; continuous commands are not memoised)",
                ));
            }
            for (i, slot) in slots.iter().enumerate() {
                let (lo, hi) = slot.range;
                let ends: &[f64] = match slot.action {
                    // the magnitude does not depend on the direction
                    super::ValueAction::Heading { .. } => &[0.0],
                    _ => &[lo, hi],
                };
                for &v in ends {
                    let name = slot
                        .name
                        .as_deref()
                        .map_or(String::new(), |n| format!(" ({n})"));
                    // what is wrong with the action itself (a name, a
                    // motor) is placed there; a number out of bounds at an
                    // end of the range, at the range
                    let bad_at = |field: &str, what: String| match field {
                        "action" => Invalid {
                            nth: i,
                            ..Invalid::at("action", None, &format!("slot {i}{name}: {what}"))
                        },
                        _ => Invalid {
                            nth: i,
                            ..Invalid::at(
                                "range",
                                None,
                                &format!("slot {i}{name} at {}: {what}", show(v)),
                            )
                        },
                    };
                    self.check_action(&slot.action.at(v), &position, &bad_at)?;
                }
            }
        }
        if let Some(sym) = self.symmetry {
            sym.validate(self, scene)?;
        }
        // bodies in one another at the start: Rapier would push them
        // apart explosively before the first command
        if let Some((i, j, depth)) = super::overlap::first_overlap(self) {
            let (a, b) = (&self.bodies[i], &self.bodies[j]);
            return Err(Invalid::at(
                "position",
                Some(&quoted(&b.name)),
                &format!(
                    "body `{}`: a start pose where it does not overlap `{}` ({:?} and {:?} overlap by {} m; at most {} m, touching, is allowed)",
                    b.name,
                    a.name,
                    b.kind,
                    a.kind,
                    show(depth),
                    super::overlap::OVERLAP_TOLERANCE
                ),
            ));
        }
        Ok(())
    }

    /// What is possible but suspicious, for `e3d scene check`: a tracked
    /// point that starts outside the effect grid (it is binned in the
    /// nearest border cell), a dynamic body outside it, a fixed body (a
    /// wall) that neither lies in nor touches it. (Bodies overlapping at
    /// the start are not a warning: [`Scene::validate`](crate::Scene::validate)
    /// refuses them.)
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let g = &self.effect.grid;
        let inside = |p: (f64, f64)| {
            p.0 >= g.min[0] && p.0 <= g.max[0] && p.1 >= g.min[1] && p.1 <= g.max[1]
        };
        if let Some(b) = self.body(&self.effect.body) {
            let p = to_world(b.position, b.angle, self.effect.point);
            if !inside(p) {
                out.push(format!(
                    "the tracked point starts at ({}, {}), outside the effect grid [{}, {}] x [{}, {}]: it counts in the nearest border cell",
                    show(p.0), show(p.1), g.min[0], g.max[0], g.min[1], g.max[1]
                ));
            }
        }
        for b in &self.bodies {
            if b.kind == BodyKind::Dynamic && !inside(b.position) {
                out.push(format!(
                    "dynamic body `{}` starts at ({}, {}), outside the effect grid",
                    b.name,
                    show(b.position.0),
                    show(b.position.1)
                ));
            }
        }
        // walls that do not enclose a free tracked body
        if let Some(l) = super::enclosure::leak(self) {
            out.push(format!(
                "the walls do not enclose the tracked body `{}`: from its start ({}, {}) it may leave them near ({:.2}, {:.2}) (fixed bodies rasterised on {} m cells; a gap of 1.5 times its radius or more counts)",
                self.effect.body,
                show(self.effect_start().0),
                show(self.effect_start().1),
                l.point.0,
                l.point.1,
                show(l.cell)
            ));
        }
        // a fixed body that neither lies in nor touches the effect grid
        // bounds no motion there: most likely a misplaced wall
        let tol = super::overlap::OVERLAP_TOLERANCE;
        for b in &self.bodies {
            if b.kind != BodyKind::Fixed || !b.collide {
                continue;
            }
            let (lo, hi) = super::overlap::start_aabb(b);
            if lo[0] > g.max[0] + tol
                || hi[0] < g.min[0] - tol
                || lo[1] > g.max[1] + tol
                || hi[1] < g.min[1] - tol
            {
                out.push(format!(
                    "fixed body `{}` spans [{}, {}] x [{}, {}], wholly outside the effect grid [{}, {}] x [{}, {}]: it bounds no motion on the grid (a misplaced wall?)",
                    b.name,
                    show(lo[0]), show(hi[0]), show(lo[1]), show(hi[1]),
                    g.min[0], g.max[0], g.min[1], g.max[1]
                ));
            }
        }
        out
    }

    fn effect_start(&self) -> (f64, f64) {
        self.body(&self.effect.body)
            .map_or((0.0, 0.0), |b| b.position)
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

    /// The checks of one action (a symbol's, or a continuous slot's at one
    /// value); `bad_at(field, what)` places a failure.
    fn check_action(
        &self,
        action: &Action,
        position: &dyn Fn(&str) -> Option<usize>,
        bad_at: &dyn Fn(&str, String) -> Invalid,
    ) -> Result<(), Invalid> {
        let bad = |what: String| bad_at("action", what);
        // a number of the action: its own field
        let field = match action {
            Action::Torque { .. } => "torque",
            Action::Impulse { .. } => "impulse",
            Action::Force { .. } => "force",
            Action::Target { .. } => "angle",
            _ => "action",
        };
        let bad_number = |what: String| bad_at(field, what);
        match action {
            Action::Idle => {}
            Action::Move { .. } => {
                return Err(bad(
                    "Torque, Impulse, Force, Target or Idle in a Physics world (Move is for Grid worlds)".into(),
                ))
            }
            Action::Torque { joint, torque } => {
                let j = self.known_joint(joint, &bad)?;
                if !torque.is_finite() {
                    return Err(bad_number(format!("a finite torque in N·m, found {torque}")));
                }
                if !in_range(*torque, 0.0, f64::MAX, true) {
                    return Err(bad_number(format!(
                        "a torque 0 or at least 1.2e-38 N·m in magnitude (f32), found {}",
                        show(*torque)
                    )));
                }
                // +torque on the child, -torque on a dynamic parent
                for name in [&j.child, &j.parent] {
                    let Some(b) = position(name).map(|i| &self.bodies[i]) else {
                        continue;
                    };
                    let Some(inertia) = b.min_inertia() else {
                        continue;
                    };
                    let spin = torque.abs() * self.dt / inertia;
                    if spin > MAX_STEP_CHANGE {
                        return Err(bad_number(format!(
                            "a torque that adds at most {} rad/s to a body in one step, but {} N·m adds {} rad/s to `{name}` (inertia about {} kg·m², dt {} s)",
                            show(MAX_STEP_CHANGE),
                            show(*torque),
                            show(spin),
                            show(inertia),
                            show(self.dt)
                        )));
                    }
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
                    return Err(bad_number(format!("a finite angle in radians, found {angle}")));
                }
                if !in_range(*angle, 0.0, MAX_ANGLE, true) {
                    return Err(bad_number(format!(
                        "a target angle {}, found {}",
                        bounds(0.0, MAX_ANGLE, true, "rad"),
                        show(*angle)
                    )));
                }
                if let Some((lo, hi)) = j.limits {
                    if *angle < lo || *angle > hi {
                        return Err(bad_number(format!(
                            "a target within joint `{joint}`'s limits ({lo}, {hi}), found {angle}"
                        )));
                    }
                }
            }
            Action::Impulse { body, impulse: v } | Action::Force { body, force: v } => {
                let b = match position(body).map(|i| &self.bodies[i]) {
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
                    return Err(bad_number("finite components".into()));
                }
                let (what, unit, per_step) = match action {
                    Action::Impulse { .. } => ("an impulse", "N·s", 1.0),
                    _ => ("a force", "N", self.dt),
                };
                if !(in_range(v.0, 0.0, f64::MAX, true) && in_range(v.1, 0.0, f64::MAX, true)) {
                    return Err(bad_number(format!(
                        "{what} whose components are 0 or at least 1.2e-38 {unit} in magnitude (f32), found ({}, {})",
                        show(v.0),
                        show(v.1)
                    )));
                }
                let m = b.mass_kg();
                let dv = v.0.hypot(v.1) * per_step / m;
                if dv > MAX_STEP_CHANGE {
                    return Err(bad_number(format!(
                        "{what} that adds at most {} m/s to a body in one step, but ({}, {}) {unit} adds {} m/s to `{body}` ({} kg{})",
                        show(MAX_STEP_CHANGE),
                        show(v.0),
                        show(v.1),
                        show(dv),
                        show(m),
                        if per_step == 1.0 { String::new() } else { format!(", dt {} s", show(self.dt)) }
                    )));
                }
            }
        }
        Ok(())
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

    fn validate_body(&self, b: &BodySpec, duplicate: bool) -> Result<(), Invalid> {
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
        if duplicate {
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
            ShapeSpec::Polyline { points } if points.len() > MAX_POINTS => {
                return Err(Invalid::at(
                    "points",
                    Some(&at),
                    &format!("{who}: at most {MAX_POINTS} points, found {}", points.len()),
                ))
            }
            _ => {}
        }
        // what f32 can hold: sizes, then every coordinate
        let sizes: Vec<(&str, f64)> = match &b.shape {
            ShapeSpec::Ball { radius } | ShapeSpec::Capsule { radius, .. } => {
                vec![("radius", *radius)]
            }
            ShapeSpec::Cuboid { width, height } => vec![("width", *width), ("height", *height)],
            _ => Vec::new(),
        };
        for (f, v) in sizes {
            number(f, Some(&at), &who, f, v, (MIN_SIZE, MAX_LENGTH), false, "m")?;
        }
        for v in b.shape.numbers() {
            number(
                "shape",
                Some(&at),
                &who,
                "coordinates",
                v,
                (0.0, MAX_LENGTH),
                true,
                "m",
            )?;
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
            number(
                "density",
                Some(&at),
                &who,
                "a density",
                d,
                (MIN_DENSITY, MAX_DENSITY),
                false,
                "kg/m²",
            )?;
        }
        if let Some(m) = b.mass {
            number(
                "mass",
                Some(&at),
                &who,
                "a mass",
                m,
                (MIN_MASS, MAX_MASS),
                false,
                "kg",
            )?;
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
            let field = if b.density.is_some() {
                "density"
            } else {
                "shape"
            };
            number(
                field,
                Some(&at),
                &who,
                "a mass (density x area)",
                b.mass_kg(),
                (MIN_MASS, MAX_MASS),
                false,
                "kg",
            )?;
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
        for v in [b.position.0, b.position.1] {
            number(
                "position",
                Some(&at),
                &who,
                "coordinates",
                v,
                (0.0, MAX_LENGTH),
                true,
                "m",
            )?;
        }
        number(
            "angle",
            Some(&at),
            &who,
            "an angle",
            b.angle,
            (0.0, MAX_ANGLE),
            true,
            "rad",
        )?;
        for (f, v, hi) in [
            ("linear_damping", b.linear_damping, MAX_COEFFICIENT),
            ("angular_damping", b.angular_damping, MAX_COEFFICIENT),
            ("friction", b.friction, MAX_FRICTION),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Invalid::at(
                    f,
                    Some(&at),
                    &format!("{who}: a finite number >= 0, found {v}"),
                ));
            }
            number(f, Some(&at), &who, "a number", v, (0.0, hi), false, "")?;
        }
        if !(in_range(b.restitution, 0.0, 1.0, false)) {
            return Err(Invalid::at(
                "restitution",
                Some(&at),
                &format!("{who}: a restitution in [0, 1], found {}", b.restitution),
            ));
        }
        Ok(())
    }
}
