//! Experiments: the sessions behind a report, run. What they produce is
//! drawn by [`report`](crate::report), which runs nothing.
//!
//! - [`paper`]: Figures 2 and 3 of Daucé (2020) on `two_rooms`, four arms
//!   of sessions ([`paper::run_paper`]; what `e3d reproduce` runs);
//! - [`drives`]: every drive on the canonical scenes, as a sweep
//!   ([`drives::drives_sweep`], [`drives::with_reachable_cells`]; what
//!   `e3d compare` runs);
//! - [`closed_loop`]: closed loop against open loop on equal budgets of
//!   moves ([`closed_loop::run_comparison`]; what `e3d closed-loop` runs).

pub mod closed_loop;
pub mod drives;
pub mod paper;
