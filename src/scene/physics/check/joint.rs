//! The checks of the joints: names, the bodies they join (trees), their
//! numbers, and their anchors meeting at the start pose.

use super::{check_name, finite2, listed};
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
            let duplicate = !joint_names.insert(j.name.as_str());
            let (at, who) = check_name("joint", &j.name, duplicate)?;
            let on = On::new(Some(&at), &who);
            let (pb, cb) = self.joint_ends(j, on, position)?;
            self.check_tree(i, j, on, (pb, cb), position, &mut parent_of)?;
            check_joint_geometry(j, on)?;
            check_joint_drive(j, on)?;
            self.check_anchors_meet(j, on, (pb, cb))?;
        }
        Ok(())
    }

    /// The indices of a joint's parent (`None`: the ground) and child: known
    /// bodies, two different ones, the child dynamic.
    fn joint_ends(
        &self,
        j: &JointSpec,
        on: On,
        position: &dyn Fn(&str) -> Option<usize>,
    ) -> Result<(Option<usize>, usize), Invalid> {
        let known = |field, name: &str| {
            position(name).ok_or_else(|| self.unknown_body(field, name, on.who))
        };
        let pb = match j.parent.as_str() {
            GROUND => None,
            parent => Some(known("parent", parent)?),
        };
        if j.child == GROUND {
            return Err(on.bad("child", "a body as child; `ground` can only be a parent"));
        }
        let cb = known("child", &j.child)?;
        let (child, kind) = (&j.child, self.bodies[cb].kind);
        if pb == Some(cb) {
            let what = format!("two different bodies, but it joins `{child}` to itself");
            return Err(on.bad("child", what));
        }
        if kind != BodyKind::Dynamic {
            let what = format!("a dynamic child body, but `{child}` is {kind:?}");
            return Err(on.bad("child", what));
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
        on: On,
        (pb, cb): (Option<usize>, usize),
        position: &dyn Fn(&str) -> Option<usize>,
        parent_of: &mut [Option<usize>],
    ) -> Result<(), Invalid> {
        if let Some(p) = parent_of[cb] {
            return Err(on.bad(
                "child",
                format!(
                    "a body that is the child of one joint only (joints form trees), but `{}` is already the child of `{}`",
                    j.child, self.joints[p].name
                ),
            ));
        }
        parent_of[cb] = Some(i);
        // no loops: walk up from the parent
        let mut up = pb;
        let mut hops = 0;
        while let Some(b) = up {
            if b == cb || hops > self.bodies.len() {
                return Err(on.bad(
                    "parent",
                    "joints that form trees, but this one closes a loop",
                ));
            }
            hops += 1;
            up = parent_of[b].and_then(|k| position(&self.joints[k].parent));
        }
        Ok(())
    }

    /// A joint's anchors meet at the start pose.
    fn check_anchors_meet(
        &self,
        j: &JointSpec,
        on: On,
        (pb, cb): (Option<usize>, usize),
    ) -> Result<(), Invalid> {
        let pa = pb.map_or(j.parent_anchor, |p| {
            let b = &self.bodies[p];
            to_world(b.position, b.angle, j.parent_anchor)
        });
        let c = &self.bodies[cb];
        let ca = to_world(c.position, c.angle, j.child_anchor);
        let gap = ((pa.0 - ca.0).powi(2) + (pa.1 - ca.1).powi(2)).sqrt();
        if gap > 1e-6 {
            return Err(on.bad(
                "child_anchor",
                format!(
                    "anchors that meet at the start pose, but the parent's is at ({:.4}, {:.4}) and the child's at ({:.4}, {:.4})",
                    pa.0, pa.1, ca.0, ca.1
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
                listed(&names)
            ))
        })
    }
}

/// A joint's anchors and limits.
fn check_joint_geometry(j: &JointSpec, on: On) -> Result<(), Invalid> {
    for (field, v) in [
        ("parent_anchor", j.parent_anchor),
        ("child_anchor", j.child_anchor),
    ] {
        if !finite2(v) {
            return Err(on.bad(field, "finite coordinates"));
        }
        for c in [v.0, v.1] {
            on.number(field, "coordinates", c, COORDINATES)?;
        }
    }
    if let JointKind::Prismatic { axis } = j.kind {
        let ok = finite2(axis)
            && axis.0.hypot(axis.1) >= MIN_SIZE
            && axis.0.abs() <= MAX_LENGTH
            && axis.1.abs() <= MAX_LENGTH;
        if !ok {
            return Err(on.bad(
                "axis",
                format!(
                    "a slider's axis (x, y), finite, of length at least {} and components at most {} (any such length: it is normalised), found ({}, {})",
                    show(MIN_SIZE),
                    show(MAX_LENGTH),
                    show(axis.0),
                    show(axis.1)
                ),
            ));
        }
    }
    let (coordinate, unit, bound) = j.kind.coordinate();
    if let Some((lo, hi)) = j.limits {
        if !(lo.is_finite() && hi.is_finite() && lo <= 0.0 && 0.0 <= hi && lo < hi) {
            return Err(on.bad(
                "limits",
                format!(
                    "finite limits (min, max) with min <= 0 <= max and min < max ({coordinate} 0 is the start pose), found ({lo}, {hi})"
                ),
            ));
        }
        for v in [lo, hi] {
            on.number("limits", "limits", v, Bound::magnitude(bound, unit))?;
        }
    }
    Ok(())
}

/// A joint's damping and motor.
fn check_joint_drive(j: &JointSpec, on: On) -> Result<(), Invalid> {
    let (damping_unit, stiffness_unit) = if j.kind.is_revolute() {
        ("N·m·s/rad", "N·m/rad")
    } else {
        ("N·s/m", "N/m")
    };
    let d = j.damping;
    if !(d.is_finite() && d >= 0.0) {
        return Err(on.bad(
            "damping",
            format!("a damping >= 0 in {damping_unit}, found {d}"),
        ));
    }
    let dampings = Bound::range(0.0, MAX_COEFFICIENT, damping_unit);
    on.number("damping", "a damping", d, dampings)?;
    let Some(m) = j.motor else {
        return Ok(());
    };
    if !(m.stiffness.is_finite() && m.stiffness > 0.0 && m.damping.is_finite() && m.damping >= 0.0)
    {
        return Err(on.bad(
            "motor",
            format!(
                "a motor with stiffness > 0 and damping >= 0, found ({}, {})",
                m.stiffness, m.damping
            ),
        ));
    }
    let stiffnesses = Bound::range(MIN_MAGNITUDE, MAX_COEFFICIENT, stiffness_unit);
    on.number("stiffness", "a motor stiffness", m.stiffness, stiffnesses)?;
    on.number("motor", "a motor damping", m.damping, dampings)
}
