//! Setting joints' coordinates and rates at the start of a context: a
//! multibody link through its generalized coordinate and velocity (then
//! forward kinematics places its bodies), a free-floating tree's impulse
//! joint by placing its child from its parent, root first.

use super::{JointInfo, Sets};
use rapier2d::math::{Pose, Real, Rotation, Vector};

/// What a context does to the joints of a world (copy 0).
#[derive(Debug, Clone)]
pub(super) struct JointGeometry {
    /// Per joint of the scene: its parent's and its child's anchors (in
    /// their frames).
    anchors: Vec<(Vector, Vector)>,
    /// The impulse joints (free-floating trees), parents before children.
    impulse_order: Vec<usize>,
}

impl JointGeometry {
    /// The geometry of `infos` (copy 0's joints) with `anchors` per joint;
    /// `sets` tells which joints are multibody links.
    pub(super) fn of(infos: &[JointInfo], anchors: Vec<(Vector, Vector)>, sets: &Sets) -> Self {
        let depth = |k: usize| {
            let mut d = 0;
            let mut at = infos[k].parent;
            while let Some(p) = at {
                match infos.iter().find(|j| j.child == p) {
                    Some(j) if d <= infos.len() => {
                        d += 1;
                        at = j.parent;
                    }
                    _ => break,
                }
            }
            d
        };
        let mut impulse_order: Vec<usize> = (0..infos.len())
            .filter(|&k| {
                sets.multibody_joints
                    .rigid_body_link(infos[k].child)
                    .is_none()
            })
            .collect();
        impulse_order.sort_by_key(|&k| (depth(k), k));
        JointGeometry {
            anchors,
            impulse_order,
        }
    }
}

/// Sets every joint of `infos` to `target` (coordinate, rate) in `sets`:
/// the multibody links listed in `listed`, and every impulse joint (so a
/// free-floating tree follows its moved root and its turned joints).
pub(super) fn set_joints(
    sets: &mut Sets,
    infos: &[JointInfo],
    geometry: &JointGeometry,
    target: &[(f64, f64)],
    listed: &[usize],
) {
    set_multibody_links(sets, infos, target, listed);
    for &k in &geometry.impulse_order {
        place_child(sets, &infos[k], geometry.anchors[k], target[k]);
    }
}

/// Sets the multibody links of `listed` to their targets, then runs
/// forward kinematics on their multibodies and sets their bodies'
/// velocities from the generalized ones.
fn set_multibody_links(
    sets: &mut Sets,
    infos: &[JointInfo],
    target: &[(f64, f64)],
    listed: &[usize],
) {
    let mut touched = Vec::new();
    for &k in listed {
        let Some(link) = sets
            .multibody_joints
            .rigid_body_link(infos[k].child)
            .copied()
        else {
            continue;
        };
        let Some(mb) = sets.multibody_joints.get_multibody_mut(link.multibody) else {
            continue;
        };
        let Some(l) = mb.link_mut(link.id) else {
            continue;
        };
        // a hinge's angle is its angular coordinate, a slider's position
        // its first linear one (2D: coords = [x, y, angle])
        let now = l.joint.coords()[if infos[k].slider.is_none() { 2 } else { 0 }];
        l.joint.apply_displacement(&[target[k].0 as Real - now]);
        let aid = l.assembly_id();
        mb.generalized_velocity_mut()[aid] = target[k].1 as Real;
        if !touched.contains(&link.multibody) {
            touched.push(link.multibody);
        }
    }
    for m in touched {
        let Some(mb) = sets.multibody_joints.get_multibody_mut(m) else {
            continue;
        };
        mb.forward_kinematics(&sets.bodies, false);
        mb.update_rigid_bodies(&mut sets.bodies, true);
        let qd = mb.generalized_velocity();
        for l in mb.links() {
            let j = mb.body_jacobian(l.link_id());
            let v = |r: usize| (0..qd.len()).map(|c| j[(r, c)] * qd[c]).sum::<Real>();
            let b = &mut sets.bodies[l.rigid_body_handle()];
            b.set_linvel(Vector::new(v(0), v(1)), true);
            b.set_angvel(v(2), true);
        }
    }
}

/// Places the child of the impulse joint `j` from its parent's pose and
/// velocity so that the joint holds at coordinate `q.0`, rate `q.1`.
fn place_child(sets: &mut Sets, j: &JointInfo, (a1, a2): (Vector, Vector), q: (f64, f64)) {
    let (pose, angvel) = j.parent.map_or((Pose::IDENTITY, 0.0), |p| {
        (*sets.bodies[p].position(), sets.bodies[p].angvel())
    });
    let at = |point: Vector| {
        j.parent
            .map_or(Vector::ZERO, |p| sets.bodies[p].velocity_at_point(point))
    };
    let parent_angle = pose.rotation.angle() as f64;
    let (angle, anchor, linear) = match j.slider {
        None => (
            parent_angle + j.offset + q.0,
            pose.transform_point(a1),
            None,
        ),
        Some((axis, a1, _)) => {
            let axis = pose.rotation * axis;
            let p1 = pose.transform_point(a1);
            (parent_angle + j.offset, p1 + axis * q.0 as Real, Some(axis))
        }
    };
    let rot = Rotation::new(angle as Real);
    let a2 = j.slider.map_or(a2, |(_, _, a2)| a2);
    let child_pose = Pose::from_parts(anchor - rot * a2, rot);
    let com = child_pose.transform_point(
        sets.bodies[j.child]
            .mass_properties()
            .local_mprops
            .local_com,
    );
    let (omega, v) = match linear {
        // a hinge: the anchor moves with the parent, the child turns about it
        None => {
            let w = angvel + q.1 as Real;
            let r = com - anchor;
            (w, at(anchor) + Vector::new(-w * r.y, w * r.x))
        }
        // a slider: the child moves with the parent's frame, plus the rate
        Some(axis) => (angvel, at(com) + axis * q.1 as Real),
    };
    let b = &mut sets.bodies[j.child];
    b.set_position(child_pose, true);
    b.set_linvel(v, true);
    b.set_angvel(omega, true);
}
