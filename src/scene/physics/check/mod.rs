//! The validation of a physics world: every body, joint, action, the
//! schedule and the effect, with an error that names the field, the value
//! and what was expected.

mod action;
mod body;
mod joint;
mod symmetry;

use super::limits::*;
use super::{PhysicsSpec, Schedule, MAX_STEPS};
use crate::scene::overlap::{first_overlap, OVERLAP_TOLERANCE};
use crate::scene::{Invalid, SceneSpec};
use std::collections::HashMap;

/// `"name"`, the text that anchors an error on a named item.
fn quoted(name: &str) -> String {
    format!("\"{name}\"")
}

fn finite2(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

impl PhysicsSpec {
    /// Checks the whole world, part by part, in a fixed order (the first
    /// fault is reported): the world's own numbers, the bodies, the joints,
    /// the schedule, the effect, the symbols' actions, the continuous
    /// slots' actions, the symmetry, and bodies overlapping at the start.
    pub(crate) fn validate(&self, scene: &SceneSpec) -> Result<(), Invalid> {
        self.check_world_numbers()?;
        self.check_counts()?;
        // names to indices: linear in the number of bodies and joints
        let index = self.check_bodies()?;
        let position = |name: &str| index.get(name).copied();
        self.check_joints(&position)?;
        // fields that Rapier would silently ignore on some kinds of body
        for b in &self.bodies {
            self.check_body_kind(b)?;
        }
        self.check_schedule(scene)?;
        self.check_effect()?;
        self.check_symbol_actions(scene, &position)?;
        self.check_value_actions(scene, &position)?;
        if let Some(sym) = self.symmetry {
            sym.validate(self, scene)?;
        }
        self.check_overlap()
    }

    /// Gravity, `dt`, `solver_iterations` and `max_speed`.
    fn check_world_numbers(&self) -> Result<(), Invalid> {
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
        Ok(())
    }

    /// At least one body, at most [`MAX_BODIES`] bodies and [`MAX_JOINTS`]
    /// joints.
    fn check_counts(&self) -> Result<(), Invalid> {
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
        Ok(())
    }

    /// Every body in order; returns the index of each body's name (its
    /// first occurrence).
    fn check_bodies(&self) -> Result<HashMap<&str, usize>, Invalid> {
        let mut index: HashMap<&str, usize> = HashMap::with_capacity(self.bodies.len());
        for (i, b) in self.bodies.iter().enumerate() {
            let first = *index.entry(b.name.as_str()).or_insert(i);
            self.validate_body(b, first != i)?;
        }
        Ok(index)
    }

    /// The schedule's durations: finite, whole numbers of steps, at least
    /// one step of action, at most [`MAX_STEPS`] steps per command.
    fn check_schedule(&self, scene: &SceneSpec) -> Result<(), Invalid> {
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
        Ok(())
    }

    /// The effect: a known tracked body, a finite tracked point, a valid
    /// grid within [`MAX_LENGTH`].
    fn check_effect(&self) -> Result<(), Invalid> {
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
        Ok(())
    }

    /// No two bodies in one another at the start: Rapier would push them
    /// apart explosively before the first command.
    fn check_overlap(&self) -> Result<(), Invalid> {
        let Some((i, j, depth)) = first_overlap(self) else {
            return Ok(());
        };
        let (a, b) = (&self.bodies[i], &self.bodies[j]);
        Err(Invalid::at(
            "position",
            Some(&quoted(&b.name)),
            &format!(
                "body `{}`: a start pose where it does not overlap `{}` ({:?} and {:?} overlap by {} m; at most {} m, touching, is allowed)",
                b.name,
                a.name,
                b.kind,
                a.kind,
                show(depth),
                OVERLAP_TOLERANCE
            ),
        ))
    }

    pub(super) fn body_names(&self) -> String {
        let names: Vec<&str> = self.bodies.iter().map(|b| b.name.as_str()).collect();
        names.join(", ")
    }

    pub(super) fn unknown_body(&self, field: &str, name: &str, whose: &str) -> Invalid {
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
                crate::scene::error::did_you_mean(name, &names),
                names.join(", ")
            ),
        )
    }
}
