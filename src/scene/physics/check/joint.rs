//! The checks of the joints: names, the bodies they join (trees), their
//! numbers, and their anchors meeting at the start pose.

use super::{finite2, quoted};
use crate::scene::physics::limits::*;
use crate::scene::physics::{to_world, BodyKind, JointKind, JointSpec, PhysicsSpec, GROUND};
use crate::scene::Invalid;
use std::collections::HashSet;

impl PhysicsSpec {
    /// Every joint in order: its name, the bodies it joins (a tree), its
    /// numbers, and its anchors meeting at the start pose.
    pub(super) fn check_joints(
        &self,
        position: &dyn Fn(&str) -> Option<usize>,
    ) -> Result<(), Invalid> {
        let mut joint_names: HashSet<&str> = HashSet::with_capacity(self.joints.len());
        let mut parent_of: Vec<Option<usize>> = vec![None; self.bodies.len()];
        for (i, j) in self.joints.iter().enumerate() {
            let at = quoted(&j.name);
            if j.name.trim().is_empty() {
                return Err(Invalid::at("name", None, "a non-empty joint name"));
            }
            crate::text::check_name(&j.name)
                .map_err(|e| Invalid::at("name", Some(&at), &format!("joint: {e}")))?;
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
            let (pb, cb) = self.joint_ends(j, &at, position)?;
            self.check_tree(i, j, &at, (pb, cb), position, &mut parent_of)?;
            self.check_joint_geometry(j, &at)?;
            self.check_joint_drive(j, &at)?;
            self.check_anchors_meet(j, &at, (pb, cb))?;
        }
        Ok(())
    }

    /// The indices of a joint's parent (`None`: the ground) and child: known
    /// bodies, two different ones, the child dynamic.
    fn joint_ends(
        &self,
        j: &JointSpec,
        at: &str,
        position: &dyn Fn(&str) -> Option<usize>,
    ) -> Result<(Option<usize>, usize), Invalid> {
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
                Some(at),
                &format!(
                    "joint `{}`: a body as child; `ground` can only be a parent",
                    j.name
                ),
            ));
        }
        let cb = match position(&j.child) {
            Some(c) => c,
            None => {
                return Err(self.unknown_body("child", &j.child, &format!("joint `{}`", j.name)))
            }
        };
        if pb == Some(cb) {
            return Err(Invalid::at(
                "child",
                Some(at),
                &format!(
                    "joint `{}`: two different bodies, but it joins `{}` to itself",
                    j.name, j.child
                ),
            ));
        }
        if self.bodies[cb].kind != BodyKind::Dynamic {
            return Err(Invalid::at(
                "child",
                Some(at),
                &format!(
                    "joint `{}`: a dynamic child body, but `{}` is {:?}",
                    j.name, j.child, self.bodies[cb].kind
                ),
            ));
        }
        Ok((pb, cb))
    }

    /// Joint `i` (joining `pb` to `cb`) keeps the joints a forest: its
    /// child is the child of no other joint, and it closes no loop.
    /// Records it in `parent_of`.
    fn check_tree(
        &self,
        i: usize,
        j: &JointSpec,
        at: &str,
        (pb, cb): (Option<usize>, usize),
        position: &dyn Fn(&str) -> Option<usize>,
        parent_of: &mut [Option<usize>],
    ) -> Result<(), Invalid> {
        if let Some(p) = parent_of[cb] {
            return Err(Invalid::at(
                "child",
                Some(at),
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
                    Some(at),
                    &format!(
                        "joint `{}`: joints that form trees, but this one closes a loop",
                        j.name
                    ),
                ));
            }
            hops += 1;
            up = parent_of[b].and_then(|k| position(&self.joints[k].parent));
        }
        Ok(())
    }

    /// A joint's anchors and limits.
    fn check_joint_geometry(&self, j: &JointSpec, at: &str) -> Result<(), Invalid> {
        let who = format!("joint `{}`", j.name);
        for (field, v) in [
            ("parent_anchor", j.parent_anchor),
            ("child_anchor", j.child_anchor),
        ] {
            if !finite2(v) {
                return Err(Invalid::at(
                    field,
                    Some(at),
                    &format!("joint `{}`: finite coordinates", j.name),
                ));
            }
            for c in [v.0, v.1] {
                number(
                    field,
                    Some(at),
                    &who,
                    "coordinates",
                    c,
                    (0.0, MAX_LENGTH),
                    true,
                    "m",
                )?;
            }
        }
        if let JointKind::Prismatic { axis } = j.kind {
            let ok = finite2(axis)
                && axis.0.hypot(axis.1) >= MIN_SIZE
                && axis.0.abs() <= MAX_LENGTH
                && axis.1.abs() <= MAX_LENGTH;
            if !ok {
                return Err(Invalid::at(
                    "axis",
                    Some(at),
                    &format!(
                        "joint `{}`: a slider's axis (x, y), finite, of length at least {} and components at most {} (any such length: it is normalised), found ({}, {})",
                        j.name,
                        show(MIN_SIZE),
                        show(MAX_LENGTH),
                        show(axis.0),
                        show(axis.1)
                    ),
                ));
            }
        }
        let (coordinate, unit, bound) = if j.kind.is_revolute() {
            ("angle", "rad", MAX_ANGLE)
        } else {
            ("position", "m", MAX_LENGTH)
        };
        if let Some((lo, hi)) = j.limits {
            if !(lo.is_finite() && hi.is_finite() && lo <= 0.0 && 0.0 <= hi && lo < hi) {
                return Err(Invalid::at(
                    "limits",
                    Some(at),
                    &format!(
                        "joint `{}`: finite limits (min, max) with min <= 0 <= max and min < max ({coordinate} 0 is the start pose), found ({lo}, {hi})",
                        j.name
                    ),
                ));
            }
            for v in [lo, hi] {
                number(
                    "limits",
                    Some(at),
                    &who,
                    "limits",
                    v,
                    (0.0, bound),
                    true,
                    unit,
                )?;
            }
        }
        Ok(())
    }

    /// A joint's damping and motor.
    fn check_joint_drive(&self, j: &JointSpec, at: &str) -> Result<(), Invalid> {
        let who = format!("joint `{}`", j.name);
        let (damping_unit, stiffness_unit) = if j.kind.is_revolute() {
            ("N·m·s/rad", "N·m/rad")
        } else {
            ("N·s/m", "N/m")
        };
        if !(j.damping.is_finite() && j.damping >= 0.0) {
            return Err(Invalid::at(
                "damping",
                Some(at),
                &format!(
                    "joint `{}`: a damping >= 0 in {damping_unit}, found {}",
                    j.name, j.damping
                ),
            ));
        }
        number(
            "damping",
            Some(at),
            &who,
            "a damping",
            j.damping,
            (0.0, MAX_COEFFICIENT),
            false,
            damping_unit,
        )?;
        let Some(m) = j.motor else {
            return Ok(());
        };
        if !(m.stiffness.is_finite()
            && m.stiffness > 0.0
            && m.damping.is_finite()
            && m.damping >= 0.0)
        {
            return Err(Invalid::at(
                "motor",
                Some(at),
                &format!(
                    "joint `{}`: a motor with stiffness > 0 and damping >= 0, found ({}, {})",
                    j.name, m.stiffness, m.damping
                ),
            ));
        }
        number(
            "stiffness",
            Some(at),
            &who,
            "a motor stiffness",
            m.stiffness,
            (MIN_MAGNITUDE, MAX_COEFFICIENT),
            false,
            stiffness_unit,
        )?;
        number(
            "motor",
            Some(at),
            &who,
            "a motor damping",
            m.damping,
            (0.0, MAX_COEFFICIENT),
            false,
            damping_unit,
        )
    }

    /// A joint's anchors meet at the start pose.
    fn check_anchors_meet(
        &self,
        j: &JointSpec,
        at: &str,
        (pb, cb): (Option<usize>, usize),
    ) -> Result<(), Invalid> {
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
                Some(at),
                &format!(
                    "joint `{}`: anchors that meet at the start pose, but the parent's is at ({:.4}, {:.4}) and the child's at ({:.4}, {:.4})",
                    j.name, pa.0, pa.1, ca.0, ca.1
                ),
            ));
        }
        Ok(())
    }

    pub(super) fn known_joint(
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
}
