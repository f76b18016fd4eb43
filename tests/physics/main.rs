//! The Rapier worlds: closed forms, the canonical physics scenes, copies,
//! symmetry, lockstep, whole motions, continuous commands, and the physics
//! scene loader's errors. One test binary; each module is one topic.

#[path = "../common/mod.rs"]
mod common;

mod arm7;
mod continuous;
mod copies;
mod effect_kinds;
mod larger_scenes;
mod lockstep;
mod motion;
mod pendulum;
mod puck;
mod scene_errors;
mod symmetry;
