//! The validation of a physics world: every body, joint, action, the
//! schedule and the effect, with an error that names the field, the value
//! and what was expected.

use super::super::{Action, Invalid, Scene};
use super::limits::*;
use super::spec::to_world;
use super::{BodyKind, BodySpec, JointSpec, PhysicsSpec, Schedule, ShapeSpec, GROUND, MAX_STEPS};
use std::collections::{HashMap, HashSet};

/// `"name"`, the text that anchors an error on a named item.
fn quoted(name: &str) -> String {
    format!("\"{name}\"")
}

fn finite2(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

impl PhysicsSpec {
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
        if let crate::scene::CommandSpec::Continuous(slots) = &scene.command {
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
                    crate::scene::ValueAction::Heading { .. } => &[0.0],
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
        if let Some((i, j, depth)) = crate::scene::overlap::first_overlap(self) {
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
                    crate::scene::overlap::OVERLAP_TOLERANCE
                ),
            ));
        }
        Ok(())
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
                crate::scene::error::did_you_mean(name, &names),
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
                crate::scene::error::did_you_mean(name, &names),
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
