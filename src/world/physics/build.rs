//! Building a scene's Rapier sets: bodies, colliders, joints and the
//! actions of every symbol, once per copy.

use super::prefix::{Prefixes, PREFIX_STATES};
use super::step::multibody_mut;
use super::{
    v2, Act, JointInfo, PhysicsWorld, Probe, Replica, Sets, ValueAct, LIMIT_GATE_MARGIN, MAX_COPIES,
};
use crate::scene::physics::{BodyKind, BodySpec, JointSpec, PhysicsSpec, ShapeSpec};
use crate::scene::valid::{Links, Resolved, ResolvedProbe, ResolvedValue};
use crate::scene::Scene;
use rapier2d::geometry::BvhOptimizationStrategy;
use rapier2d::math::{Pose, Real};
use rapier2d::prelude::{
    BroadPhaseBvh, ColliderBuilder, GenericJoint, Group, ImpulseJointHandle, IntegrationParameters,
    InteractionGroups, InteractionTestMode, JointAxesMask, JointAxis, MotorModel, PhysicsPipeline,
    RigidBodyBuilder, RigidBodyHandle, RigidBodyType, Vector,
};

/// Builds one copy of the scene's non-fixed bodies, their joints and the
/// actions on them into `s`. Fixed bodies are built by the first copy
/// (into `fixed`, by scene index) and shared by the others. `groups` keeps
/// this copy's colliders apart from the other copies' while they still
/// touch the fixed bodies.
fn build_copy(
    s: &mut Sets,
    scene: &Scene,
    spec: &PhysicsSpec,
    groups: InteractionGroups,
    fixed: &mut [Option<RigidBodyHandle>],
) -> Replica {
    let mut handles = Vec::new();
    let mut dynamic = Vec::new();
    let mut drag = Vec::new();
    for (i, b) in spec.bodies.iter().enumerate() {
        if let Some(h) = fixed[i] {
            handles.push(h);
            continue;
        }
        let h = insert_body(s, b, groups);
        handles.push(h);
        if b.kind == BodyKind::Dynamic {
            dynamic.push((h, b.fast_rotation));
            drag.extend(b.drag.map(|d| (h, d)));
        }
        if b.kind == BodyKind::Fixed {
            fixed[i] = Some(h);
        }
    }
    let links = scene.links();
    let (joints, impulse_of) = insert_joints(s, spec, links, &handles);
    set_multibody_damping(s, spec, links, &handles);
    let acts = Acts {
        spec,
        links,
        handles: &handles,
        impulse_of: &impulse_of,
    };
    let value_acts = links
        .values
        .iter()
        .map(|v| match v {
            ResolvedValue::Heading { body, impulse } => ValueAct::Heading {
                body: handles[*body],
                impulse: *impulse,
            },
            ResolvedValue::Scaled(a) => ValueAct::Scaled(acts.of(a)),
        })
        .collect();
    let probes = links
        .probes
        .iter()
        .map(|p| match p {
            ResolvedProbe::Point { body, point, frame } => Probe::Point {
                body: handles[*body],
                point: v2(*point),
                frame: frame.map(|f| handles[f]),
            },
            ResolvedProbe::Joint(j) => Probe::Joint(*j),
            ResolvedProbe::Angle(b) => Probe::Angle(handles[*b]),
            ResolvedProbe::Centre(bodies) => Probe::Centre(
                bodies
                    .iter()
                    .map(|&b| (handles[b], spec.bodies[b].mass_kg()))
                    .collect(),
            ),
        })
        .collect();
    Replica {
        tracked: handles[links.tracked],
        probes,
        acts: links.symbols.iter().map(|a| acts.of(a)).collect(),
        handles,
        dynamic,
        drag,
        value_acts,
        joints,
    }
}

/// Inserts body `b` and its collider into `s`; its collider in `groups`
/// (unless it collides with nothing, or is fixed: then with everything).
fn insert_body(s: &mut Sets, b: &BodySpec, groups: InteractionGroups) -> RigidBodyHandle {
    let kind = match b.kind {
        BodyKind::Dynamic => RigidBodyType::Dynamic,
        BodyKind::Kinematic => RigidBodyType::KinematicVelocityBased,
        BodyKind::Fixed => RigidBodyType::Fixed,
    };
    let mut rb = RigidBodyBuilder::new(kind)
        .translation(v2(b.position))
        .rotation(b.angle as Real)
        .linear_damping(b.linear_damping as Real)
        .angular_damping(b.angular_damping as Real)
        // a sleeping body stops short: the effect would depend on
        // the sleep thresholds
        .can_sleep(false)
        .allow_fast_rotation(b.fast_rotation);
    if b.lock_rotation {
        rb = rb.lock_rotations();
    }
    let area = b.shape.area();
    if area <= 0.0 && b.kind == BodyKind::Dynamic {
        // segments and polylines have no area: the mass is the body's own
        rb = rb.additional_mass(b.mass_kg() as Real);
    }
    let h = s.bodies.insert(rb);
    let mut co = match &b.shape {
        ShapeSpec::Ball { radius } => ColliderBuilder::ball(*radius as Real),
        ShapeSpec::Cuboid { width, height } => {
            ColliderBuilder::cuboid((width / 2.0) as Real, (height / 2.0) as Real)
        }
        ShapeSpec::Capsule { a, b, radius } => {
            ColliderBuilder::capsule_from_endpoints(v2(*a), v2(*b), *radius as Real)
        }
        ShapeSpec::Segment { a, b } => ColliderBuilder::segment(v2(*a), v2(*b)),
        ShapeSpec::Polyline { points } => {
            ColliderBuilder::polyline(points.iter().map(|p| v2(*p)).collect(), None)
        }
    }
    .friction(b.friction as Real)
    .restitution(b.restitution as Real);
    co = match b.mass_properties() {
        // a segment or polyline: no area, the body's own mass (above)
        None => co.density(0.0),
        Some(mp) => co.mass_properties(mp),
    };
    co = if !b.collide {
        co.collision_groups(InteractionGroups::none())
    } else if b.kind == BodyKind::Fixed {
        co.collision_groups(InteractionGroups::all())
    } else {
        co.collision_groups(groups)
    };
    s.colliders.insert_with_parent(co, h, &mut s.bodies);
    h
}

/// Inserts the joints of one copy (its bodies `handles`) into `s`: per
/// joint, its [`JointInfo`] and its impulse joint, for a free-floating
/// tree (`None`: a multibody link, for a tree hung on ground).
fn insert_joints(
    s: &mut Sets,
    spec: &PhysicsSpec,
    links: &Links,
    handles: &[RigidBodyHandle],
) -> (Vec<JointInfo>, Vec<Option<ImpulseJointHandle>>) {
    // one ground per copy: a multibody rooted at a shared ground would join
    // the copies into one multibody
    let ground = if links.joints.iter().any(|&(parent, _)| parent.is_none()) {
        s.bodies.insert(RigidBodyBuilder::fixed())
    } else {
        RigidBodyHandle::invalid()
    };
    let handle_of = |body: Option<usize>| body.map_or(ground, |i| handles[i]);
    let mut joints = Vec::new();
    let mut impulse_of = Vec::new();
    for (k, (j, &(parent, child))) in spec.joints.iter().zip(&links.joints).enumerate() {
        let parent_angle = parent.map_or(0.0, |i| spec.bodies[i].angle);
        // angle 0 is the start pose, whatever the bodies' start angles
        let offset = spec.bodies[child].angle - parent_angle;
        // a tree hung on ground is a multibody (reduced coordinates); a
        // free-floating one is built of impulse joints, because Rapier's
        // multibody with a dynamic root does not conserve momentum (see
        // docs/physics.md)
        let multibody = links.forest.hangs_from_ground(k);
        let (data, slider) = joint_data(j, offset, multibody);
        let (p, c) = (handle_of(parent), handles[child]);
        joints.push(JointInfo {
            child: c,
            parent: parent.map(|_| p),
            offset,
            limits: j.limits,
            slider,
        });
        if multibody {
            // the joints form a forest (`Forest`): Rapier's multibodies
            // refuse only a second parent or a loop
            s.multibody_joints
                .insert(p, c, data, true)
                .expect("a Forest has no second parent and no loop");
            impulse_of.push(None);
        } else {
            impulse_of.push(Some(s.impulse_joints.insert(p, c, data, true)));
        }
    }
    (joints, impulse_of)
}

/// The Rapier joint of `j` (its child's start angle `offset` from its
/// parent's; a `multibody` link or an impulse joint) and, for a slider,
/// its axis and anchors (see [`JointInfo`]).
fn joint_data(
    j: &JointSpec,
    offset: f64,
    multibody: bool,
) -> (GenericJoint, Option<(Vector, Vector, Vector)>) {
    let (p, c) = (v2(j.parent_anchor), v2(j.child_anchor));
    let slider = j
        .axis()
        .map(|(x, y)| (Vector::new(x as Real, y as Real), p, c));
    let (axis, locked) = match slider {
        None => (JointAxis::AngX, JointAxesMask::LOCKED_REVOLUTE_AXES),
        Some(_) => (JointAxis::LinX, JointAxesMask::LOCKED_PRISMATIC_AXES),
    };
    let mut data = GenericJoint::new(locked);
    data.set_local_anchor1(p)
        .set_local_anchor2(c)
        .set_contacts_enabled(j.contacts);
    if let Some((lo, hi)) = j.limits {
        data.set_limits(axis, [lo as Real, hi as Real]);
    }
    match slider {
        // a hinge's angle is 0 at the start pose
        None => data.set_local_frame1(Pose::new(p, offset as Real)),
        Some((a, _, _)) => {
            // the axis in the child's frame: the parent's, turned back
            // by the child's start angle relative to the parent
            let (sn, cs) = (-offset).sin_cos();
            let a2 = Vector::new(
                (cs * a.x as f64 - sn * a.y as f64) as Real,
                (sn * a.x as f64 + cs * a.y as f64) as Real,
            );
            data.set_local_axis1(a).set_local_axis2(a2)
        }
    };
    // an impulse joint's damping is a velocity motor (a force-based
    // motor's damping term, -c v): joint damping plus a motor's own
    let extra = if multibody { 0.0 } else { j.damping };
    if let Some(m) = j.motor {
        data.set_motor_model(axis, MotorModel::ForceBased);
        data.set_motor_position(axis, 0.0, m.stiffness as Real, (m.damping + extra) as Real);
    } else if extra > 0.0 {
        data.set_motor_model(axis, MotorModel::ForceBased);
        data.set_motor_velocity(axis, 0.0, extra as Real);
    }
    (data, slider)
}

/// Joint damping: the multibody's per-DoF damping, indexed by the link's
/// assembly id (valid at any time, also before the first step).
fn set_multibody_damping(
    s: &mut Sets,
    spec: &PhysicsSpec,
    links: &Links,
    handles: &[RigidBodyHandle],
) {
    for (j, &(_, child)) in spec.joints.iter().zip(&links.joints) {
        if let Some((mb, id)) = multibody_mut(&mut s.multibody_joints, handles[child]) {
            if let Some(aid) = mb.link(id).map(|l| l.assembly_id()) {
                mb.damping_mut()[aid] = j.damping as Real;
            }
        }
    }
}

/// What the actions of one copy act on: its bodies `handles` and its
/// joints' impulse joints `impulse_of` (see [`insert_joints`]).
struct Acts<'a> {
    spec: &'a PhysicsSpec,
    links: &'a Links,
    handles: &'a [RigidBodyHandle],
    impulse_of: &'a [Option<ImpulseJointHandle>],
}

impl Acts<'_> {
    /// The act of `action` on this copy.
    fn of(&self, action: &Resolved) -> Act {
        let (spec, links, handles) = (self.spec, self.links, self.handles);
        match *action {
            Resolved::Idle => Act::Idle,
            Resolved::Torque { joint, torque } => {
                let (parent, child) = links.joints[joint];
                Act::Torque {
                    child: handles[child],
                    parent: parent.map(|i| handles[i]),
                    torque: torque as Real,
                }
            }
            Resolved::Impulse { body, impulse } => Act::Impulse {
                body: handles[body],
                impulse: v2(impulse),
            },
            Resolved::Force { body, force } => Act::Force {
                body: handles[body],
                force: v2(force),
            },
            Resolved::Target {
                joint: k,
                angle,
                motor: m,
            } => {
                let j = &spec.joints[k];
                let impulse = self.impulse_of[k];
                Act::Target {
                    child: handles[links.joints[k].1],
                    impulse,
                    axis: if j.kind.is_revolute() {
                        JointAxis::AngX
                    } else {
                        JointAxis::LinX
                    },
                    angle: angle as Real,
                    stiffness: m.stiffness as Real,
                    // an impulse joint's damping rides on its motor
                    damping: (m.damping + if impulse.is_some() { j.damping } else { 0.0 }) as Real,
                }
            }
        }
    }
}

/// The sets of `copies` copies of `scene` (whose world is `spec`), each
/// copy's replica, and the copy of each body by its raw index
/// (`u32::MAX`: a fixed body, shared).
fn build_copies(
    scene: &Scene,
    spec: &PhysicsSpec,
    copies: usize,
) -> (Sets, Vec<Replica>, Vec<u32>) {
    let mut s = Sets::default();
    if copies > 1 && spec.copies_are_exact() {
        // The broad phase's BVH optimiser reshapes the tree every few steps
        // (about a tenth of a 32-copy puck step). The shape of the tree
        // decides no bit of an exact copy's outcome: a copy gives a
        // one-copy world's outcome, whose tree is another altogether.
        s.broad_phase = BroadPhaseBvh::with_optimization_strategy(BvhOptimizationStrategy::None);
    }
    let mut fixed = vec![None; spec.bodies.len()];
    let mut copy_of_body = Vec::new();
    let replicas: Vec<Replica> = (0..copies)
        .map(|c| {
            let groups = if copies == 1 {
                InteractionGroups::all()
            } else {
                let bit = Group::from_bits_truncate(1 << c);
                InteractionGroups::new(bit, bit, InteractionTestMode::And)
            };
            let before = s.bodies.len();
            let r = build_copy(&mut s, scene, spec, groups, &mut fixed);
            for (h, _) in s.bodies.iter().skip(before) {
                let i = h.into_raw_parts().0 as usize;
                if copy_of_body.len() <= i {
                    copy_of_body.resize(i + 1, u32::MAX);
                }
                if !fixed.contains(&Some(h)) {
                    copy_of_body[i] = c as u32;
                }
            }
            r
        })
        .collect();
    (s, replicas, copy_of_body)
}

impl PhysicsWorld {
    /// The world of `copies` copies of `scene`, whose world is `spec`.
    pub(crate) fn of(scene: &Scene, spec: &PhysicsSpec, copies: usize) -> PhysicsWorld {
        assert!(
            (1..=MAX_COPIES).contains(&copies),
            "between 1 and {MAX_COPIES} copies, not {copies}"
        );
        let (s, replicas, copy_of_body) = build_copies(scene, spec, copies);
        // a continuous scene's command space of symbols is a placeholder
        // (one symbol per slot) that no command passes (`check_command`)
        let values = scene.value_space();
        let space = scene.command_space();
        let sizes: Vec<usize> = scene.spec().slots().map(|a| a.len()).collect();
        let offset = sizes
            .iter()
            .scan(0, |n, k| Some(std::mem::replace(n, *n + k)))
            .collect();
        let mut params = IntegrationParameters {
            dt: spec.dt as Real,
            ..IntegrationParameters::default()
        };
        if let Some(n) = spec.solver_iterations {
            params.num_solver_iterations = n;
        }
        let (phase_steps, settle_steps, together) = spec.schedule.steps(spec.dt);
        let (contexts, joint_geometry) =
            PhysicsWorld::context_starts(spec, scene.links(), &replicas[0], &s);
        // a world of many copies runs batches, whose copies share no prefix
        let noise = super::noise::Noise::of(spec, &s, &replicas[0]);
        let capacity = if copies == 1 && noise.is_none() {
            PREFIX_STATES
        } else {
            0
        };
        let prefixes = Prefixes::new(&sizes, !together && values.is_none(), capacity);
        // Rapier's statistics (on by default) are read by no one and cost
        // a walk over every contact bucket at every step
        let mut pipeline = PhysicsPipeline::new();
        pipeline.counters.disable();
        PhysicsWorld {
            scene: scene.spec().name.clone(),
            space,
            values,
            grid: scene.effect_grid(),
            reward: scene.reward_table(),
            gravity: v2(spec.gravity),
            params,
            pipeline,
            sets: s.clone(),
            pristine: s,
            copies: replicas,
            copy_of_body,
            tracked_point: v2(scene.links().tracked_point),
            binning: scene.binning().clone(),
            offset,
            phase_steps,
            settle_steps,
            together,
            max_speed: spec.max_speed,
            gate_limits: true,
            gated_angles: Vec::new(),
            gate_margin: LIMIT_GATE_MARGIN,
            gate_speed_steps: 4.0,
            gate_missed: false,
            mirror: scene.mirror().cloned().filter(|_| noise.is_none()),
            dt: spec.dt,
            body_names: spec.bodies.iter().map(|b| b.name.clone()).collect(),
            joint_names: spec.joints.iter().map(|j| j.name.clone()).collect(),
            contexts,
            joint_geometry,
            prefixes,
            noise,
            held_forces: Vec::new(),
        }
    }
}
