//! Experiments: the sessions behind `e3d reproduce` ([`paper`]), `e3d
//! compare` ([`drives`]) and `e3d closed-loop` ([`closed_loop`]), run.
//! [`report`](crate::report) draws what they produce.

pub mod closed_loop;
pub mod drives;
pub mod paper;
