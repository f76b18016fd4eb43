//! A physics scene's start contexts, as the scene reads them: their
//! number, names, and the checks of their fields.

use super::super::context::{BodyStart, JointStart};
use super::super::{BodyKind, BodySpec, JointSpec, PhysicsSpec};
use super::{finite2, listed};
use crate::scene::Invalid;

impl PhysicsSpec {
    /// The number of start contexts: the declared ones, or 1 (the scene's
    /// start).
    pub fn num_contexts(&self) -> usize {
        self.contexts.len().max(1)
    }

    /// The contexts' names (`["start"]` for a scene without contexts).
    pub fn context_names(&self) -> Vec<String> {
        if self.contexts.is_empty() {
            return vec!["start".into()];
        }
        self.contexts.iter().map(|c| c.name.clone()).collect()
    }

    /// Checks the contexts (at most [`MAX_CONTEXTS`](crate::scene::MAX_CONTEXTS)):
    /// distinct names, known free bodies and joints, finite numbers within the
    /// limits, `to` only with `position` or `angle`; in time linear in the scene.
    pub(crate) fn check_contexts(&self) -> Result<(), Invalid> {
        use std::collections::{HashMap, HashSet};
        crate::scene::check_context_count(self.contexts.len())?;
        let bodies: HashMap<&str, &BodySpec> =
            self.bodies.iter().map(|b| (b.name.as_str(), b)).collect();
        let children: HashSet<&str> = self.joints.iter().map(|j| j.child.as_str()).collect();
        let joints: HashMap<&str, &JointSpec> =
            self.joints.iter().map(|j| (j.name.as_str(), j)).collect();
        let mut names = HashSet::with_capacity(self.contexts.len());
        for (k, c) in self.contexts.iter().enumerate() {
            let shown = crate::text::echo(&c.name);
            let here = |field: &str, expected: String| {
                Invalid::new(field, format!("context `{shown}`: {expected}")).within("contexts", k)
            };
            if c.name.trim().is_empty() || !names.insert(c.name.as_str()) {
                return Err(here(
                    "name",
                    "a distinct, non-empty name for every context".into(),
                ));
            }
            crate::text::check_name(&c.name).map_err(|e| here("name", e))?;
            let mut listed = HashSet::with_capacity(c.bodies.len());
            for b in &c.bodies {
                let name = b.body.as_str();
                if !listed.insert(name) {
                    return Err(here("body", format!("body `{name}` listed once")));
                }
                let what = match bodies.get(name) {
                    None => format!("a body of the scene, found `{}`", crate::text::echo(name)),
                    Some(spec) if spec.kind != BodyKind::Dynamic || children.contains(name) => {
                        format!(
                            "a free dynamic body (no joint's child), found `{name}` (set a jointed body by its joint: `joints: [(joint: \"...\", angle: ...)]`)"
                        )
                    }
                    Some(_) => {
                        self.check_body_start(b, &here)?;
                        continue;
                    }
                };
                return Err(here("body", what));
            }
            let mut listed = HashSet::with_capacity(c.joints.len());
            for s in &c.joints {
                if !listed.insert(s.joint.as_str()) {
                    return Err(here("joint", format!("joint `{}` listed once", s.joint)));
                }
                self.check_joint_start(s, joints.get(s.joint.as_str()).copied(), &here)?;
            }
        }
        Ok(())
    }

    /// The numbers of one joint's start in a context: a known joint, a
    /// finite coordinate (and range end) within its limits, a finite rate.
    fn check_joint_start(
        &self,
        s: &JointStart,
        spec: Option<&JointSpec>,
        here: &dyn Fn(&str, String) -> Invalid,
    ) -> Result<(), Invalid> {
        let Some(spec) = spec else {
            let names: Vec<&str> = self.joints.iter().map(|j| j.name.as_str()).collect();
            return Err(here(
                "joint",
                format!(
                    "a joint of the scene, found `{}` (joints: {})",
                    crate::text::echo(&s.joint),
                    listed(&names)
                ),
            ));
        };
        let unit = spec.kind.unit();
        let bad = |field, what: String| Err(here(field, format!("joint `{}`: {what}", s.joint)));
        for (field, v) in [("angle", s.angle), ("to", s.to)] {
            let Some(v) = v else { continue };
            if !v.is_finite() || v.abs() > 1e3 {
                return bad(
                    field,
                    format!("a finite coordinate within 1000 {unit}, found {v}"),
                );
            }
            if let Some((lo, hi)) = spec.limits.filter(|(lo, hi)| v < *lo || v > *hi) {
                let within = format!("a coordinate within its limits [{lo}, {hi}] {unit}");
                return bad(field, format!("{within}, found {v}"));
            }
        }
        if s.to.is_some() && s.angle.is_none() {
            return bad("to", "`to` with an `angle` (the range's other end)".into());
        }
        if s.velocity.is_some_and(|w| !w.is_finite() || w.abs() > 1e3) {
            return bad("velocity", format!("a finite rate within 1000 {unit}/s"));
        }
        Ok(())
    }

    /// The numbers of one body's start in a context.
    fn check_body_start(
        &self,
        b: &BodyStart,
        here: &dyn Fn(&str, String) -> Invalid,
    ) -> Result<(), Invalid> {
        let bad = |field, what: String| Err(here(field, format!("body `{}`: {what}", b.body)));
        for (field, p) in [("position", b.position), ("to", b.to)] {
            if p.is_some_and(|p| !finite2(p) || p.0.abs() > 1e6 || p.1.abs() > 1e6) {
                return bad(field, "a finite position within 1e6 m".into());
            }
        }
        if b.to.is_some() && b.position.is_none() {
            return bad(
                "to",
                "`to` with a `position` (the range's other corner)".into(),
            );
        }
        if b.angle.is_some_and(|a| !a.is_finite() || a.abs() > 1e3) {
            return bad("angle", "a finite angle (rad)".into());
        }
        let max = self.max_speed;
        if let Some(v) = b.velocity.filter(|v| !finite2(*v) || v.0.hypot(v.1) >= max) {
            let slower = format!("a finite velocity slower than max_speed ({max} m/s)");
            return bad("velocity", format!("{slower}, found {v:?}"));
        }
        if b.angular_velocity
            .is_some_and(|w| !w.is_finite() || w.abs() > 1e3)
        {
            return bad(
                "angular_velocity",
                "a finite angular velocity within 1000 rad/s".into(),
            );
        }
        Ok(())
    }
}
