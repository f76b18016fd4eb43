//! The checks of the actions: each symbol's, and each continuous slot's
//! at both ends of its range.

use super::finite2;
use crate::scene::physics::limits::*;
use crate::scene::physics::{BodyKind, PhysicsSpec};
use crate::scene::{Action, CommandSpec, Invalid, SceneSpec, ValueAction};
use std::collections::HashMap;

impl PhysicsSpec {
    /// The action of every symbol of every slot.
    pub(super) fn check_symbol_actions(
        &self,
        scene: &SceneSpec,
        position: &dyn Fn(&str) -> Option<usize>,
    ) -> Result<(), Invalid> {
        let mut seen: HashMap<char, usize> = HashMap::new();
        for alphabet in scene.slots() {
            for s in alphabet {
                let count = seen.entry(s.symbol).or_insert(0);
                let nth = *count;
                *count += 1;
                let at = format!("'{}'", s.symbol);
                let bad_at = |field: &str, what: String| {
                    Invalid::at(field, Some(&at), &format!("symbol '{}': {what}", s.symbol))
                        .nth(nth)
                };
                self.check_action(&s.action, position, &bad_at)?;
            }
        }
        Ok(())
    }

    /// The values of continuous slots: the action at both ends of the range
    /// (every check of an action is monotonic in the magnitude); no
    /// symmetry with them.
    pub(super) fn check_value_actions(
        &self,
        scene: &SceneSpec,
        position: &dyn Fn(&str) -> Option<usize>,
    ) -> Result<(), Invalid> {
        let CommandSpec::Continuous(slots) = &scene.command else {
            return Ok(());
        };
        if self.symmetry.is_some() {
            return Err(Invalid::new(
                "symmetry",
                "no symmetry with continuous slots (a symmetry maps symbols; continuous commands are not memoised)",
            ));
        }
        for (i, slot) in slots.iter().enumerate() {
            let (lo, hi) = slot.range;
            let ends: &[f64] = match slot.action {
                // the magnitude does not depend on the direction
                ValueAction::Heading { .. } => &[0.0],
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
                let bad_at = |field: &str, what: String| {
                    let (field, at) = match field {
                        "action" => ("action", String::new()),
                        _ => ("range", format!(" at {}", show(v))),
                    };
                    Invalid::new(field, format!("slot {i}{name}{at}: {what}")).nth(i)
                };
                self.check_action(&slot.action.at(v), position, &bad_at)?;
            }
        }
        Ok(())
    }

    /// The checks of one action (a symbol's, or a continuous slot's at one
    /// value); `bad_at(field, what)` places a failure.
    fn check_action(
        &self,
        action: &Action,
        position: &dyn Fn(&str) -> Option<usize>,
        bad_at: &dyn Fn(&str, String) -> Invalid,
    ) -> Result<(), Invalid> {
        // a number of the action is placed at its own field
        let on = |field| Act {
            position,
            bad_at,
            field,
        };
        let grid =
            "Torque, Impulse, Force, Target or Idle in a Physics world (Move is for Grid worlds)";
        match action {
            Action::Idle => Ok(()),
            Action::Move { .. } => Err(bad_at("action", grid.into())),
            Action::Torque { joint, torque } => self.check_torque(joint, *torque, &on("torque")),
            Action::Target { joint, angle } => self.check_target(joint, *angle, &on("angle")),
            Action::Impulse { body, impulse: v } => {
                self.check_push(action, body, *v, &on("impulse"))
            }
            Action::Force { body, force: v } => self.check_push(action, body, *v, &on("force")),
        }
    }

    /// A torque on a known joint: finite, not subnormal in `f32`, adding
    /// at most [`MAX_STEP_CHANGE`] rad/s to the joint's bodies in one step.
    fn check_torque(&self, joint: &str, torque: f64, a: &Act) -> Result<(), Invalid> {
        let j = self.known_joint(joint, &|w| a.bad(w))?;
        if !j.kind.is_revolute() {
            return Err(a.bad(format!(
                "a Torque on a hinge, but joint `{joint}` is a slider (Prismatic): push its child with `Force(body: \"{}\", force: (x, y))` (the part along the axis moves it) or move its motor with `Target`",
                j.child
            )));
        }
        if !torque.is_finite() {
            return Err(a.number(format!("a finite torque in N·m, found {torque}")));
        }
        if !in_range(torque, 0.0, f64::MAX, true) {
            return Err(a.number(format!(
                "a torque 0 or at least 1.2e-38 N·m in magnitude (f32), found {}",
                show(torque)
            )));
        }
        // +torque on the child, -torque on a dynamic parent
        for name in [&j.child, &j.parent] {
            let Some(inertia) = (a.position)(name).and_then(|i| self.bodies[i].min_inertia())
            else {
                continue;
            };
            let spin = torque.abs() * self.dt / inertia;
            if spin > MAX_STEP_CHANGE {
                return Err(a.number(format!(
                    "a torque that adds at most {} rad/s to a body in one step, but {} N·m adds {} rad/s to `{name}` (inertia about {} kg·m², dt {} s)",
                    show(MAX_STEP_CHANGE),
                    show(torque),
                    show(spin),
                    show(inertia),
                    show(self.dt)
                )));
            }
        }
        Ok(())
    }

    /// A joint target: a joint with a motor, a finite angle within the
    /// joint's limits.
    fn check_target(&self, joint: &str, angle: f64, a: &Act) -> Result<(), Invalid> {
        let j = self.known_joint(joint, &|w| a.bad(w))?;
        if j.motor.is_none() {
            return Err(a.bad(format!(
                "a Target on a joint with a `motor: (stiffness: ..., damping: ...)`, but joint `{joint}` has none"
            )));
        }
        let (what, unit, bound) = j.kind.coordinate();
        if !angle.is_finite() {
            return Err(a.number(format!("a finite {what} in {unit}, found {angle}")));
        }
        if !in_range(angle, 0.0, bound, true) {
            return Err(a.number(format!(
                "a target {what} {}, found {}",
                bounds(0.0, bound, true, unit),
                show(angle)
            )));
        }
        if let Some((lo, hi)) = j.limits.filter(|(lo, hi)| angle < *lo || angle > *hi) {
            return Err(a.number(format!(
                "a target within joint `{joint}`'s limits ({lo}, {hi}), found {angle}"
            )));
        }
        Ok(())
    }

    /// An impulse or a force (`action`) of `v` on `body`: a known dynamic
    /// body, finite components not subnormal in `f32`, adding at most
    /// [`MAX_STEP_CHANGE`] m/s to the body in one step.
    fn check_push(
        &self,
        action: &Action,
        body: &str,
        v: (f64, f64),
        a: &Act,
    ) -> Result<(), Invalid> {
        let Some(b) = (a.position)(body).map(|i| &self.bodies[i]) else {
            return Err(a.bad(format!(
                "a known body, but there is no body `{body}`; bodies: {}",
                self.body_names()
            )));
        };
        if b.kind != BodyKind::Dynamic {
            return Err(a.bad(format!("a dynamic body, but `{body}` is {:?}", b.kind)));
        }
        if matches!(action, Action::Impulse { .. }) && self.hangs_from_ground(body) {
            return Err(a.bad(format!(
                "an Impulse on a free body or on a link of a free-floating chain, but `{body}` is a link of a chain hung on `ground` (a Rapier multibody link: an impulse on it would be lost at the next step); push it with `Force(body: \"{body}\", force: (x, y))` held over the phase (an impulse J over a phase of T s is the force J / T), or turn its joint with `Torque`"
            )));
        }
        if !finite2(v) {
            return Err(a.number("finite components".into()));
        }
        let (what, unit, per_step) = match action {
            Action::Impulse { .. } => ("an impulse", "N·s", 1.0),
            _ => ("a force", "N", self.dt),
        };
        if !(in_range(v.0, 0.0, f64::MAX, true) && in_range(v.1, 0.0, f64::MAX, true)) {
            return Err(a.number(format!(
                "{what} whose components are 0 or at least 1.2e-38 {unit} in magnitude (f32), found ({}, {})",
                show(v.0),
                show(v.1)
            )));
        }
        let m = b.mass_kg();
        let dv = v.0.hypot(v.1) * per_step / m;
        if dv > MAX_STEP_CHANGE {
            return Err(a.number(format!(
                "{what} that adds at most {} m/s to a body in one step, but ({}, {}) {unit} adds {} m/s to `{body}` ({} kg{})",
                show(MAX_STEP_CHANGE),
                show(v.0),
                show(v.1),
                show(dv),
                show(m),
                if per_step == 1.0 { String::new() } else { format!(", dt {} s", show(self.dt)) }
            )));
        }
        Ok(())
    }
}

/// What the checks of one action need: the bodies' indices, and where a
/// failure goes (`action` for the action itself, `field` for its number).
struct Act<'a> {
    position: &'a dyn Fn(&str) -> Option<usize>,
    bad_at: &'a dyn Fn(&str, String) -> Invalid,
    field: &'static str,
}

impl Act<'_> {
    fn bad(&self, what: String) -> Invalid {
        (self.bad_at)("action", what)
    }

    fn number(&self, what: String) -> Invalid {
        (self.bad_at)(self.field, what)
    }
}
