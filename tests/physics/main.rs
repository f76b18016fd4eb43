//! The Rapier worlds: closed forms, the canonical physics scenes, copies,
//! symmetry, lockstep, whole motions, continuous commands, and the physics
//! scene loader's errors, the physics laws and the audit of every body
//! field and action. One test binary; each module is one topic.

#[path = "../common/mod.rs"]
mod common;

mod arm7;
mod arm_copies;
mod audit;
mod contexts;
mod continuous;
mod copies;
mod effect_kinds;
mod larger_scenes;
mod laws;
mod lockstep;
mod motion;
mod new_scenes;
mod noise;
mod pendulum;
mod prefixes;
mod puck;
mod rapier_identity;
mod scene_errors;
mod symmetry;
