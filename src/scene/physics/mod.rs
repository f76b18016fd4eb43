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
//!
//! The module is in parts: `spec` holds the types of the format (`joint`
//! those of its joints), `limits`
//! the bounds of its numbers, `check` the validation of a whole world, and
//! `warnings` what is possible but suspicious.

mod check;
mod context;
mod joint;
pub mod limits;
mod spec;
mod warnings;

pub use context::{BodyStart, JointStart, StartState};
pub use joint::{JointKind, JointSpec, MotorSpec};
pub(crate) use spec::to_world;
pub use spec::{
    steps_of, to_world_point, BodyKind, BodySpec, EffectSpec, PhysicsSpec, Schedule, ShapeSpec,
};

/// The name that stands for the fixed world frame in joints (`parent:
/// "ground"`). No body may take it.
pub const GROUND: &str = "ground";

/// The largest number of steps one command may take (about 2.8 hours at
/// 1/60 s): a guard against a mistyped duration.
pub const MAX_STEPS: u64 = 600_000;
