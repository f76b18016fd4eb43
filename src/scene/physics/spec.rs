//! The types of the physics part of the scene format, and what they
//! compute without checking (masses, areas, steps, world positions).

use super::super::shorthand::{ChainSpec, WallSpec};
use super::super::symmetry::Symmetry;
use super::joint::JointSpec;
use crate::effect::{Binning, EffectGrid, Feature};
use parry2d::mass_properties::MassProperties;
use parry2d::math::Vector;
use serde::{Deserialize, Serialize};

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
    /// boxes and the chains' links come first (see [`shorthand`](crate::scene::shorthand)).
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
    /// Start contexts (default none: one start, the bodies as listed):
    /// each trial or episode starts from one of them, drawn with the
    /// session's generator (see [`StartState`](super::StartState)).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contexts: Vec<super::StartState>,
    /// Seeded noise on the actions and the start (default none: the
    /// world is deterministic; see [`NoiseSpec`](super::NoiseSpec)). A
    /// noisy world runs live: no outcome table, no memo.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise: Option<super::NoiseSpec>,
}

defaults! {
    default_dt: f64 = 1.0 / 60.0;
    default_max_speed: f64 = 100.0;
    yes: bool = true;
    half: f64 = 0.5;
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
    /// Drag from the fluid the body moves in (default none): a force
    /// against its velocity, stronger across the body than along it (see
    /// [`DragSpec`](super::DragSpec)). Dynamic bodies only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag: Option<super::DragSpec>,
    /// The moment of inertia about the centre of mass, kg·m² (default:
    /// from the shape and mass, [`BodySpec::inertia_kg_m2`]). Dynamic
    /// bodies with an area only.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
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

/// What the effect is made of: one tracked point binned on a grid (the
/// short form, `body`, `point`, `grid`), or a list of binned `features`
/// whose product is the effect (see [`Feature`]). Give one form or the
/// other.
///
/// ```ron
/// effect: (body: "puck", grid: (rows: 3, cols: 6, min: (0.0, 0.0), max: (6.0, 3.0))),
/// effect: (features: [
///     Joint(joint: "pivot", bins: 9, range: (-0.9, 0.9)),
///     Joint(joint: "rail", bins: 7, range: (-1.4, 1.4)),
/// ]),
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EffectSpec {
    /// The tracked body (the short form; empty with `features`).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub body: String,
    /// The tracked point in the body's local frame (default (0, 0), its origin).
    #[serde(default)]
    pub point: (f64, f64),
    /// The grid the terminal position is binned on (row 0 at the top);
    /// points outside it count in the nearest border cell. The short
    /// form; `None` with `features`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        serialize_with = "grid_as_written"
    )]
    pub grid: Option<EffectGrid>,
    /// The binned features whose product is the effect (default none:
    /// the short form's one point).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub features: Vec<Feature>,
}

/// A grid written as scene files write it, without `Some(...)`: a scene
/// of the short form serialises (and hashes) as before `features` existed.
fn grid_as_written<S: serde::Serializer>(
    grid: &Option<EffectGrid>,
    s: S,
) -> Result<S::Ok, S::Error> {
    match grid {
        Some(g) => g.serialize(s),
        None => s.serialize_none(),
    }
}

impl EffectSpec {
    /// The effect's features, in order: the short form is one
    /// [`Feature::Point`] in world coordinates.
    pub fn features(&self) -> Vec<Feature> {
        if !self.features.is_empty() {
            return self.features.clone();
        }
        match &self.grid {
            Some(g) => vec![Feature::Point {
                body: self.body.clone(),
                point: self.point,
                frame: None,
                grid: g.clone(),
            }],
            None => Vec::new(),
        }
    }

    /// The point whose cell in the world is the effect, when there is
    /// one: the short form, or a single [`Feature::Point`] without a
    /// `frame`. Its body, its local point and its grid (in metres, over
    /// the world). `None` for effects of other kinds (a joint's
    /// coordinate, an angle, a point in another body's frame, a product).
    pub fn world_point(&self) -> Option<(&str, (f64, f64), &EffectGrid)> {
        match (self.features.as_slice(), &self.grid) {
            ([], Some(g)) => Some((self.body.as_str(), self.point, g)),
            (
                [Feature::Point {
                    body,
                    point,
                    frame: None,
                    grid,
                }],
                None,
            ) => Some((body.as_str(), *point, grid)),
            _ => None,
        }
    }

    /// The body and local point drawn as the effect's tracked point in
    /// figures and traces: the [`world_point`](Self::world_point) if
    /// any, else the first feature's point or body origin (a joint's
    /// child, via `child_of`).
    pub fn drawn_point<'a>(
        &'a self,
        child_of: impl Fn(&str) -> Option<&'a str>,
    ) -> Option<(&'a str, (f64, f64))> {
        if let Some((b, p, _)) = self.world_point() {
            return Some((b, p));
        }
        match self.features.first()? {
            Feature::Point { body, point, .. } => Some((body.as_str(), *point)),
            Feature::Angle { body, .. } => Some((body.as_str(), (0.0, 0.0))),
            Feature::Centre { bodies, .. } => Some((bodies.first()?.as_str(), (0.0, 0.0))),
            Feature::Joint { joint, .. } => Some((child_of(joint)?, (0.0, 0.0))),
        }
    }

    /// How the features are binned; `None` for an effect that does not
    /// validate.
    pub fn binning(&self) -> Option<Binning> {
        let axes: Vec<_> = self.features().iter().map(Feature::axis).collect();
        Binning::new(axes).ok()
    }
}

/// The number of steps of a duration, `round(seconds / dt)`.
pub fn steps_of(seconds: f64, dt: f64) -> u64 {
    (seconds / dt).round() as u64
}

impl Schedule {
    /// `(steps of one phase, settle steps)` for `dt`, and whether all slots
    /// act together.
    pub fn steps(&self, dt: f64) -> (u64, u64, bool) {
        let (phase, settle, together) = match *self {
            Schedule::Sequential { phase, settle } => (phase, settle, false),
            Schedule::Simultaneous { push, settle } => (push, settle, true),
        };
        (steps_of(phase, dt), steps_of(settle, dt), together)
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

    /// The moment of inertia about the centre of mass, kg·m², that Rapier
    /// (parry2d) gives the body: its `inertia` if set, else from its shape
    /// and mass `m`: a ball of radius `r`, `m r²/2`; a cuboid `w` x `h`,
    /// `m (w² + h²)/12`; a capsule of segment length `l` and radius `r`,
    /// `m_r (l² + 4r²)/12 + m_d (r²/2 + l²/4 + 3lr/8)` with `m_r` and `m_d`
    /// the mass shares of its rectangle `l` x `2r` and of its two half
    /// discs (by area). `None` for a body without
    /// area (a segment, a polyline), whose own mass is a point's. The
    /// number Rapier gives the world (parry2d's, in f32).
    pub fn inertia_kg_m2(&self) -> Option<f64> {
        if let (Some(i), false) = (self.inertia, self.kind == BodyKind::Dynamic) {
            return Some(i);
        }
        self.mass_properties()
            .map(|mp| mp.principal_inertia() as f64)
    }

    /// The mass properties Rapier gives the body's collider (parry2d's,
    /// f32): its shape's at the density of its `mass` (or its `density`),
    /// with a dynamic body's `inertia` about the shape's centre if set
    /// ([`inertia_kg_m2`](Self::inertia_kg_m2) says the formulas).
    /// `None` for a body without area (a segment, a polyline): its own
    /// mass is a point's at its origin. The one computation the world,
    /// the MJCF export and the import use.
    pub(crate) fn mass_properties(&self) -> Option<MassProperties> {
        let v = |p: (f64, f64)| Vector::new(p.0 as f32, p.1 as f32);
        let unit = |density: f32| match &self.shape {
            ShapeSpec::Ball { radius } => Some(MassProperties::from_ball(density, *radius as f32)),
            ShapeSpec::Cuboid { width, height } => Some(MassProperties::from_cuboid(
                density,
                Vector::new((width / 2.0) as f32, (height / 2.0) as f32),
            )),
            ShapeSpec::Capsule { a, b, radius } => Some(MassProperties::from_capsule(
                density,
                v(*a),
                v(*b),
                *radius as f32,
            )),
            ShapeSpec::Segment { .. } | ShapeSpec::Polyline { .. } => None,
        };
        if self.shape.area() <= 0.0 {
            return None;
        }
        if let (Some(i), BodyKind::Dynamic) = (self.inertia, self.kind) {
            let centre = match &self.shape {
                ShapeSpec::Capsule { a, b, .. } => ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0),
                _ => (0.0, 0.0),
            };
            return Some(MassProperties::new(
                v(centre),
                self.mass_kg() as f32,
                i as f32,
            ));
        }
        match (self.mass, self.density) {
            (Some(m), _) => unit(1.0).map(|mut mp| {
                // what Rapier does with a collider's `mass`
                mp.set_mass(m as f32, true);
                mp
            }),
            (None, d) => unit(d.unwrap_or(1.0) as f32),
        }
    }

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

    pub(super) fn numbers(&self) -> Vec<f64> {
        match self {
            ShapeSpec::Ball { radius } => vec![*radius],
            ShapeSpec::Cuboid { width, height } => vec![*width, *height],
            ShapeSpec::Capsule { a, b, radius } => vec![a.0, a.1, b.0, b.1, *radius],
            ShapeSpec::Segment { a, b } => vec![a.0, a.1, b.0, b.1],
            ShapeSpec::Polyline { points } => points.iter().flat_map(|p| [p.0, p.1]).collect(),
        }
    }
}

/// The world position of local point `p` on a body at `pos`, `angle`.
pub fn to_world_point(pos: (f64, f64), angle: f64, p: (f64, f64)) -> (f64, f64) {
    let (s, c) = angle.sin_cos();
    (pos.0 + c * p.0 - s * p.1, pos.1 + s * p.0 + c * p.1)
}

impl PhysicsSpec {
    /// A copy of the scene without its start contexts, which are not
    /// copied at all: what is posed once per context (copying every
    /// context for each made the per-context tools quadratic).
    pub fn without_contexts(&self) -> PhysicsSpec {
        PhysicsSpec {
            gravity: self.gravity,
            dt: self.dt,
            solver_iterations: self.solver_iterations,
            max_speed: self.max_speed,
            bodies: self.bodies.clone(),
            joints: self.joints.clone(),
            schedule: self.schedule.clone(),
            effect: self.effect.clone(),
            chains: self.chains.clone(),
            walls: self.walls.clone(),
            symmetry: self.symmetry,
            contexts: Vec::new(),
            noise: self.noise.clone(),
        }
    }

    /// The scene's noise, when it draws anything.
    pub fn active_noise(&self) -> Option<&super::NoiseSpec> {
        self.noise.as_ref().filter(|n| n.is_active())
    }

    /// The body named `name`, if any.
    pub fn body(&self, name: &str) -> Option<&BodySpec> {
        self.bodies.iter().find(|b| b.name == name)
    }

    /// The index of the body named `name`, if any.
    pub(crate) fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The joints up the tree from body `name`: the joint whose child it
    /// is, then its parent's, ... (at most as many as there are joints).
    pub(crate) fn joints_above<'a>(&'a self, name: &'a str) -> impl Iterator<Item = &'a JointSpec> {
        let mut at = name;
        std::iter::from_fn(move || {
            let j = self.joints.iter().find(|j| j.child == at)?;
            at = &j.parent;
            Some(j)
        })
        .take(self.joints.len() + 1)
    }

    /// The joint named `name`, if any.
    pub fn joint(&self, name: &str) -> Option<&JointSpec> {
        self.joints.iter().find(|j| j.name == name)
    }

    /// Whether body `name` hangs, through its joints, from `ground`: such a tree
    /// is one Rapier multibody (`docs/physics.md`); a free-floating chain or a
    /// body without joints is not.
    pub fn hangs_from_ground(&self, name: &str) -> bool {
        self.joints_above(name).any(|j| j.parent == super::GROUND)
    }

    /// Whether copies of this world in one Rapier world give bit for bit the
    /// outcomes of one world per command: when at most one non-fixed body has
    /// contacts (with several, Rapier's contact ordering differs between them).
    pub fn copies_are_exact(&self) -> bool {
        self.bodies
            .iter()
            .filter(|b| b.kind != BodyKind::Fixed && b.collide)
            .count()
            <= 1
    }

    /// Whether the world still holds shorthands (`chains`, `walls`) to
    /// expand ([`SceneSpec::expand`](crate::SceneSpec::expand)); never for a
    /// loaded scene.
    pub fn has_shorthands(&self) -> bool {
        !(self.chains.is_empty() && self.walls.is_empty())
    }

    /// The effect grid: the tracked point's grid, or the layout of the
    /// features' product (see [`Binning`]); `None` for an effect that does
    /// not validate.
    pub fn effect_grid(&self) -> Option<EffectGrid> {
        if let Some((_, _, g)) = self.effect.world_point() {
            return Some(g.clone());
        }
        Some(self.effect.binning()?.layout().clone())
    }

    /// The body a joint moves (its child), if the joint exists.
    pub fn child_of(&self, joint: &str) -> Option<&str> {
        self.joint(joint).map(|j| j.child.as_str())
    }
}
