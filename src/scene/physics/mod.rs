//! The physics part of the scene format, `world: Physics(...)`: rigid
//! bodies, joints, a schedule and the effect, in SI units with y up
//! (`docs/scenes.md`, "Physics worlds"). `spec` and `joint` hold the types,
//! `limits` the bounds of their numbers, `check` the validation of a whole
//! world, and `warnings` what is possible but suspicious.

mod check;
mod context;
mod joint;
pub mod limits;
mod noise;
mod spec;
mod warnings;

pub use context::{BodyStart, JointStart, StartState};
pub use joint::{DragSpec, JointKind, JointSpec, MotorSpec};
pub(crate) use noise::generator;
pub use noise::{
    draw_key, noise_refusal, session_key, BodyNoise, DrawKey, NoiseSpec, Per, Spread, StartNoise,
};
pub(crate) use spec::to_world_point as to_world;
pub use spec::{
    steps_of, to_world_point, BodyKind, BodySpec, EffectSpec, PhysicsSpec, Schedule, ShapeSpec,
};

/// The name that stands for the fixed world frame in joints (`parent:
/// "ground"`). No body may take it.
pub const GROUND: &str = "ground";

/// The largest number of steps one command may take (about 2.8 hours at
/// 1/60 s): a guard against a mistyped duration.
pub const MAX_STEPS: u64 = 600_000;
