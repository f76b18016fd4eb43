//! The physics world: a scene's bodies and joints simulated by Rapier.
//!
//! [`PhysicsWorld`] builds the Rapier world once, keeps a pristine copy of
//! every set, and restores it (`clone_from`) before each command: every
//! command starts from the same bits, so the same command always gives the
//! same terminal state, whatever ran before it. Jointed bodies are
//! [multibodies](rapier2d::dynamics::MultibodyJointSet) (reduced
//! coordinates: chains do not stretch); joint damping is the multibody's
//! implicit per-DoF damping.
//!
//! A command runs open loop. Per slot, per the scene's schedule:
//! impulses are applied once at the start of the phase, forces and torques
//! are held during the phase and removed at its end, joint targets move the
//! set point of the joint's position motor and hold. After the last phase
//! the world settles. The effect is the cell of the tracked point at the
//! end (moving or not).
//!
//! After every step the world checks for a blown-up simulation (Rapier's
//! quarantine, non-finite poses or velocities, a body faster than the
//! scene's `max_speed`, a body at Rapier's angular speed cap) and reports
//! it as [`WorldError::Diverged`] rather than a silent effect.

use super::{Outcome, World, WorldError};
use crate::command::{Command, CommandSpace, ValueSpace};
use crate::effect::EffectGrid;
use crate::scene::physics::{BodyKind, PhysicsSpec, ShapeSpec, GROUND};
use crate::scene::{Action, CommandSpec, Scene, Symmetry, ValueAction};
use rapier2d::math::{Pose, Real, Vector};
use rapier2d::prelude::{
    BroadPhaseBvh, CCDSolver, ColliderBuilder, ColliderSet, Group, ImpulseJointSet,
    IntegrationParameters, InteractionGroups, InteractionTestMode, IslandManager, JointAxesMask,
    JointAxis, MotorModel, MultibodyJointSet, NarrowPhase, PhysicsPipeline, RevoluteJointBuilder,
    RigidBodyBuilder, RigidBodyHandle, RigidBodySet, RigidBodyType, SoftBodySet,
};

/// Rapier's per-step rotation cap (45°) for bodies without fast rotation.
const MAX_ROTATION_PER_STEP: f64 = std::f64::consts::FRAC_PI_4;

/// How far (rad) from both of its limits a joint must be, besides four
/// steps of its current speed, for its limit to be left out of a step (see
/// `PhysicsWorld::gate_limits`).
const LIMIT_GATE_MARGIN: f64 = 0.5;

/// Everything Rapier keeps between steps: restored whole before a command.
#[derive(Clone, Default)]
struct Sets {
    islands: IslandManager,
    broad_phase: BroadPhaseBvh,
    narrow_phase: NarrowPhase,
    bodies: RigidBodySet,
    colliders: ColliderSet,
    impulse_joints: ImpulseJointSet,
    multibody_joints: MultibodyJointSet,
    soft_bodies: SoftBodySet,
    ccd: CCDSolver,
}

impl Sets {
    fn restore(&mut self, from: &Sets) {
        self.islands.clone_from(&from.islands);
        self.broad_phase.clone_from(&from.broad_phase);
        self.narrow_phase.clone_from(&from.narrow_phase);
        self.bodies.clone_from(&from.bodies);
        self.colliders.clone_from(&from.colliders);
        self.impulse_joints.clone_from(&from.impulse_joints);
        self.multibody_joints.clone_from(&from.multibody_joints);
        self.soft_bodies.clone_from(&from.soft_bodies);
        self.ccd.clone_from(&from.ccd);
    }
}

/// One symbol's action, resolved to handles.
#[derive(Debug, Clone, Copy)]
enum Act {
    Idle,
    Torque {
        child: RigidBodyHandle,
        parent: Option<RigidBodyHandle>,
        torque: Real,
    },
    Impulse {
        body: RigidBodyHandle,
        impulse: Vector,
    },
    Force {
        body: RigidBodyHandle,
        force: Vector,
    },
    Target {
        child: RigidBodyHandle,
        angle: Real,
        stiffness: Real,
        damping: Real,
    },
}

/// What the value of a continuous slot does, resolved to handles: the act
/// of the value 1, scaled, or an impulse whose direction is the value.
#[derive(Debug, Clone, Copy)]
enum ValueAct {
    Scaled(Act),
    Heading { body: RigidBodyHandle, impulse: f64 },
}

impl ValueAct {
    /// The act of the value `v`.
    fn at(self, v: f64) -> Act {
        let k = v as Real;
        match self {
            ValueAct::Scaled(act) => match act {
                Act::Idle => Act::Idle,
                Act::Torque {
                    child,
                    parent,
                    torque,
                } => Act::Torque {
                    child,
                    parent,
                    torque: torque * k,
                },
                Act::Impulse { body, impulse } => Act::Impulse {
                    body,
                    impulse: impulse * k,
                },
                Act::Force { body, force } => Act::Force {
                    body,
                    force: force * k,
                },
                Act::Target {
                    child,
                    angle,
                    stiffness,
                    damping,
                } => Act::Target {
                    child,
                    angle: angle * k,
                    stiffness,
                    damping,
                },
            },
            ValueAct::Heading { body, impulse } => Act::Impulse {
                body,
                impulse: v2((impulse * v.cos(), impulse * v.sin())),
            },
        }
    }
}

/// One command a copy runs: symbols, or the values of a continuous scene.
#[derive(Debug, Clone, Copy)]
enum Cmd<'a> {
    Symbols(&'a Command),
    Values(&'a [f64]),
}

/// The pose of one body, for pictures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyPose {
    /// The position of the body's origin `(x, y)`, metres.
    pub position: [f64; 2],
    /// The angle in radians.
    pub angle: f64,
}

/// What [`PhysicsWorld::trace`] records.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    /// The tracked point at the start and after every step.
    pub points: Vec<[f64; 2]>,
    /// The terminal pose of every body of the scene, in the scene's order.
    pub poses: Vec<BodyPose>,
    /// The outcome (as [`World::execute`] returns it).
    pub outcome: Outcome,
}

/// The whole motion of one command, step by step (see
/// [`PhysicsWorld::motion`]): every body's pose and velocity and every
/// joint's angle and angular velocity, at the start and after each step.
#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    /// The scene's bodies, in its order (fixed ones included).
    pub bodies: Vec<String>,
    /// The scene's joints, in its order.
    pub joints: Vec<String>,
    /// The start (time 0) and every step after it.
    pub frames: Vec<Frame>,
    /// The outcome (as [`World::execute`] returns it).
    pub outcome: Outcome,
}

/// One instant of a [`Motion`].
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Seconds since the start of the command.
    pub time: f64,
    /// The pose of each body, in [`Motion::bodies`]' order.
    pub poses: Vec<BodyPose>,
    /// Each body's velocity: `(vx, vy)` m/s and the angular velocity rad/s.
    pub velocities: Vec<[f64; 3]>,
    /// Each joint's angle (the child's rotation relative to the parent,
    /// 0 at the start pose, radians in `(-pi, pi]`), in
    /// [`Motion::joints`]' order.
    pub joint_angles: Vec<f64>,
    /// Each joint's angular velocity (child's minus parent's), rad/s.
    pub joint_velocities: Vec<f64>,
}

impl Motion {
    /// Writes the motion as CSV, one row per frame: `step,time`, then per
    /// body `NAME.x,NAME.y,NAME.angle,NAME.vx,NAME.vy,NAME.omega`, then per
    /// joint `NAME.angle,NAME.velocity`; with `command`, a leading
    /// `command` column holding it (and `header` false: rows only, for
    /// several commands in one file).
    pub fn write_csv(
        &self,
        mut out: impl std::io::Write,
        command: Option<&str>,
        header: bool,
    ) -> std::io::Result<()> {
        if header {
            let mut cols: Vec<String> = Vec::new();
            if command.is_some() {
                cols.push("command".into());
            }
            cols.extend(["step".into(), "time".into()]);
            for b in &self.bodies {
                for f in ["x", "y", "angle", "vx", "vy", "omega"] {
                    cols.push(format!("{b}.{f}"));
                }
            }
            for j in &self.joints {
                cols.push(format!("{j}.angle"));
                cols.push(format!("{j}.velocity"));
            }
            writeln!(out, "{}", cols.join(","))?;
        }
        for (k, f) in self.frames.iter().enumerate() {
            let mut row = String::new();
            if let Some(c) = command {
                row.push_str(c);
                row.push(',');
            }
            row.push_str(&format!("{k},{}", f.time));
            for (p, v) in f.poses.iter().zip(&f.velocities) {
                for x in [p.position[0], p.position[1], p.angle, v[0], v[1], v[2]] {
                    row.push_str(&format!(",{x}"));
                }
            }
            for (a, w) in f.joint_angles.iter().zip(&f.joint_velocities) {
                row.push_str(&format!(",{a},{w}"));
            }
            writeln!(out, "{row}")?;
        }
        Ok(())
    }
}

/// What happened during one command, for diagnostics (see
/// [`PhysicsWorld::inspect`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunStats {
    /// The outcome (as [`World::execute`] returns it).
    pub outcome: Outcome,
    /// The largest linear speed of a dynamic body, m/s.
    pub max_speed: f64,
    /// The largest angular speed of a dynamic body, rad/s.
    pub max_spin: f64,
    /// Steps during which two dynamic bodies touch (jointed neighbours
    /// never do unless their joint has `contacts: true`).
    pub contact_steps: u64,
    /// Steps during which some joint is within 0.01 rad of a limit (or
    /// beyond it: limits are slightly compliant).
    pub limit_steps: u64,
}

/// A joint, for diagnostics: child, parent, angle offset, limits.
#[derive(Debug, Clone, Copy)]
struct JointInfo {
    child: RigidBodyHandle,
    parent: Option<RigidBodyHandle>,
    offset: f64,
    limits: Option<(f64, f64)>,
}

/// A scene's rigid-body world, simulated by Rapier.
///
/// Built once per scene; before each command every Rapier set is restored
/// from a pristine copy, so the same command always gives the same bits.
/// Jointed bodies are multibodies; joint damping is their implicit per-DoF
/// damping. Impulses act once at the start of a slot's phase, forces and
/// torques are held during it, joint targets hold until changed; then the
/// world settles and the effect is the cell of the tracked point. A
/// blown-up state (quarantine, non-finite values, `max_speed`, Rapier's
/// angular cap) is a [`WorldError::Diverged`], never an effect.
///
/// ```
/// use e3d::{Scene, World};
/// let scene = Scene::builtin("puck_rooms").unwrap();
/// let mut world = scene.build();
/// let c = world.command_space().parse("SEEEEES").unwrap();
/// let a = world.execute(&c).unwrap();
/// // the same command, the same bits
/// assert_eq!(world.execute(&c).unwrap(), a);
/// ```
pub struct PhysicsWorld {
    scene: String,
    space: CommandSpace,
    /// The ranges of a continuous scene's slots.
    values: Option<ValueSpace>,
    grid: EffectGrid,
    reward: Vec<f64>,
    gravity: Vector,
    params: IntegrationParameters,
    pipeline: PhysicsPipeline,
    pristine: Sets,
    sets: Sets,
    /// The copies of the scene's moving bodies (one unless built by
    /// [`with_copies`](PhysicsWorld::with_copies)); copy 0 is the one
    /// [`World::execute`] uses.
    copies: Vec<Replica>,
    /// The copy owning each body, by the body handle's index (`u32::MAX`
    /// for shared fixed bodies): attributes Rapier's quarantine.
    copy_of_body: Vec<u32>,
    tracked_point: Vector,
    offset: Vec<usize>,
    phase_steps: u64,
    settle_steps: u64,
    together: bool,
    max_speed: f64,
    /// Whether limits far from their joints are left out of a step (see
    /// [`gate_limits`](Self::gate_limits); on for `execute` and
    /// `execute_batch`, off for traces and in the test that compares).
    gate_limits: bool,
    /// Per joint (copies one after another): its angle when its limit was
    /// left out of the current step, NaN when the limit is on.
    gated_angles: Vec<f64>,
    /// The margin of the gating ([`LIMIT_GATE_MARGIN`]) and the number of
    /// steps of speed added to it (4); smaller in a test.
    gate_margin: f64,
    gate_speed_steps: f64,
    /// Whether a joint whose limit was off moved further in one step than
    /// the gating assumes (then the command is run again, limits on).
    gate_missed: bool,
    /// The scene's declared symmetry and, per slot, each symbol's mirror
    /// image (see [`twin`](Self::twin)).
    mirror: Option<(Symmetry, Vec<Vec<u8>>)>,
    /// The scene's time step, seconds (Rapier holds it as f32).
    dt: f64,
    /// The scene's body and joint names, in its order (for motions).
    body_names: Vec<String>,
    joint_names: Vec<String>,
}

/// One copy of a scene's non-fixed bodies and joints, resolved to handles.
#[derive(Debug, Clone)]
struct Replica {
    /// The scene's bodies, in order (fixed bodies are shared by the copies).
    handles: Vec<RigidBodyHandle>,
    /// Dynamic bodies, and whether each may spin fast.
    dynamic: Vec<(RigidBodyHandle, bool)>,
    tracked: RigidBodyHandle,
    /// `acts[offset[slot] + symbol]`.
    acts: Vec<Act>,
    /// Per slot of a continuous scene, what its value does.
    value_acts: Vec<ValueAct>,
    joints: Vec<JointInfo>,
}

impl std::fmt::Debug for PhysicsWorld {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PhysicsWorld")
            .field("scene", &self.scene)
            .field("bodies", &self.copies[0].handles.len())
            .field("copies", &self.copies.len())
            .field("phase_steps", &self.phase_steps)
            .field("settle_steps", &self.settle_steps)
            .finish()
    }
}

fn v2(p: (f64, f64)) -> Vector {
    Vector::new(p.0 as Real, p.1 as Real)
}

/// The largest number of copies one world holds: each copy has its own
/// collision group bit, and Rapier has 32.
pub const MAX_COPIES: usize = 32;

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
    for (i, b) in spec.bodies.iter().enumerate() {
        if let Some(h) = fixed[i] {
            handles.push(h);
            continue;
        }
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
        co = if area <= 0.0 {
            co.density(0.0)
        } else if let Some(m) = b.mass {
            co.mass(m as Real)
        } else {
            co.density(b.density.unwrap_or(1.0) as Real)
        };
        co = if !b.collide {
            co.collision_groups(InteractionGroups::none())
        } else if b.kind == BodyKind::Fixed {
            co.collision_groups(InteractionGroups::all())
        } else {
            co.collision_groups(groups)
        };
        s.colliders.insert_with_parent(co, h, &mut s.bodies);
        handles.push(h);
        if b.kind == BodyKind::Dynamic {
            dynamic.push((h, b.fast_rotation));
        }
        if b.kind == BodyKind::Fixed {
            fixed[i] = Some(h);
        }
    }
    // one ground per copy: a multibody rooted at a shared ground would join
    // the copies into one multibody
    let ground = if spec.joints.iter().any(|j| j.parent == GROUND) {
        Some(s.bodies.insert(RigidBodyBuilder::fixed()))
    } else {
        None
    };
    let body_index = |name: &str| spec.bodies.iter().position(|b| b.name == name);
    let handle_of = |name: &str| -> Option<RigidBodyHandle> {
        if name == GROUND {
            ground
        } else {
            body_index(name).map(|i| handles[i])
        }
    };
    let mut joints = Vec::new();
    for j in &spec.joints {
        let parent_angle = body_index(&j.parent).map_or(0.0, |i| spec.bodies[i].angle);
        let child = &spec.bodies[body_index(&j.child).expect("validated: known child")];
        let mut rj = RevoluteJointBuilder::new()
            .local_anchor1(v2(j.parent_anchor))
            .local_anchor2(v2(j.child_anchor))
            .contacts_enabled(j.contacts);
        if let Some((lo, hi)) = j.limits {
            rj = rj.limits([lo as Real, hi as Real]);
        }
        if let Some(m) = j.motor {
            rj = rj.motor_model(MotorModel::ForceBased).motor_position(
                0.0,
                m.stiffness as Real,
                m.damping as Real,
            );
        }
        let mut data = rj.build().data;
        // angle 0 is the start pose, whatever the bodies' start angles
        data.set_local_frame1(Pose::new(
            v2(j.parent_anchor),
            (child.angle - parent_angle) as Real,
        ));
        let p = handle_of(&j.parent).expect("validated: known parent");
        let c = handle_of(&j.child).expect("validated: known child");
        joints.push(JointInfo {
            child: c,
            parent: (j.parent != GROUND).then_some(p),
            offset: child.angle - parent_angle,
            limits: j.limits,
        });
        s.multibody_joints
            .insert(p, c, data, true)
            .expect("validated: joints form trees");
    }
    // joint damping: the multibody's per-DoF damping, indexed by the
    // link's assembly id (valid at any time, also before the first step)
    for j in &spec.joints {
        let c = handle_of(&j.child).expect("validated");
        let link = *s
            .multibody_joints
            .rigid_body_link(c)
            .expect("a jointed body");
        let mb = s
            .multibody_joints
            .get_multibody_mut(link.multibody)
            .expect("a live multibody");
        let aid = mb.link(link.id).expect("a live link").assembly_id();
        mb.damping_mut()[aid] = j.damping as Real;
    }

    let resolve = |action: &Action| -> Act {
        match action {
            Action::Idle | Action::Move { .. } => Act::Idle,
            Action::Torque { joint, torque } => {
                let j = spec.joint(joint).expect("validated: known joint");
                Act::Torque {
                    child: handle_of(&j.child).expect("validated"),
                    parent: if j.parent == GROUND {
                        None
                    } else {
                        handle_of(&j.parent)
                    },
                    torque: *torque as Real,
                }
            }
            Action::Impulse { body, impulse } => Act::Impulse {
                body: handle_of(body).expect("validated: known body"),
                impulse: v2(*impulse),
            },
            Action::Force { body, force } => Act::Force {
                body: handle_of(body).expect("validated: known body"),
                force: v2(*force),
            },
            Action::Target { joint, angle } => {
                let j = spec.joint(joint).expect("validated: known joint");
                let m = j.motor.expect("validated: a Target's joint has a motor");
                Act::Target {
                    child: handle_of(&j.child).expect("validated"),
                    angle: *angle as Real,
                    stiffness: m.stiffness as Real,
                    damping: m.damping as Real,
                }
            }
        }
    };
    let mut acts = Vec::new();
    for alphabet in scene.slots() {
        for sym in alphabet {
            acts.push(resolve(&sym.action));
        }
    }
    let value_acts = match &scene.command {
        CommandSpec::Continuous(slots) => slots
            .iter()
            .map(|slot| match &slot.action {
                ValueAction::Heading { body, impulse } => ValueAct::Heading {
                    body: handle_of(body).expect("validated: known body"),
                    impulse: *impulse,
                },
                a => ValueAct::Scaled(resolve(&a.at(1.0))),
            })
            .collect(),
        _ => Vec::new(),
    };
    let tracked_index = body_index(&spec.effect.body).expect("validated: tracked body");
    Replica {
        tracked: handles[tracked_index],
        handles,
        dynamic,
        acts,
        value_acts,
        joints,
    }
}

impl PhysicsWorld {
    /// Builds the world of a validated scene whose world is `spec`.
    ///
    /// # Panics
    /// Only on a scene that did not pass validation (for example a joint
    /// loop, which Rapier's multibodies cannot hold); [`Scene::load`] and
    /// [`Scene::parse`] validate, and so does [`Scene::try_physics_world`]
    /// (check a scene edited in code with [`Scene::validate`]).
    pub fn from_scene(scene: &Scene, spec: &PhysicsSpec) -> PhysicsWorld {
        Self::with_copies(scene, spec, 1)
    }

    /// Builds a world holding `copies` independent copies of the scene's
    /// non-fixed bodies and joints (fixed bodies are built once and
    /// shared), for [`execute_batch`](Self::execute_batch): up to `copies`
    /// commands at once in one Rapier world, which amortises Rapier's
    /// per-step overhead over the copies. Each copy has its own collision
    /// group: the copies touch the fixed bodies and, within a copy, the
    /// scene's own collision rules hold, but no two copies touch.
    ///
    /// Each copy's outcome is the one a single-copy world gives, bit for
    /// bit, on the shipped scenes (tested); a scene whose copies would
    /// differ should be executed one command per world.
    ///
    /// # Panics
    /// If `copies` is 0 or above [`MAX_COPIES`], or on a scene that did not
    /// pass validation.
    pub fn with_copies(scene: &Scene, spec: &PhysicsSpec, copies: usize) -> PhysicsWorld {
        assert!(
            (1..=MAX_COPIES).contains(&copies),
            "between 1 and {MAX_COPIES} copies, not {copies}"
        );
        if spec.has_shorthands() {
            // a scene built in code with shorthands: build what they stand for
            let mut plain = spec.clone();
            if crate::scene::shorthand::expand(&mut plain).is_err() {
                panic!("shorthands that do not expand (validate the scene first)");
            }
            return Self::with_copies(scene, &plain, copies);
        }
        let mut s = Sets::default();
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
        // a continuous scene's command space of symbols is a placeholder
        // (one symbol per slot) that no command passes (`check_command`)
        let values = scene.value_space();
        let space = match &values {
            Some(v) => CommandSpace::repeat(v.num_slots(), &['~']).expect("validated scene"),
            None => scene.command_space(),
        };
        let mut offset = Vec::new();
        let mut n = 0;
        for alphabet in scene.slots() {
            offset.push(n);
            n += alphabet.len();
        }
        let mut params = IntegrationParameters {
            dt: spec.dt as Real,
            ..IntegrationParameters::default()
        };
        if let Some(n) = spec.solver_iterations {
            params.num_solver_iterations = n;
        }
        let (phase_steps, settle_steps, together) = spec.schedule.steps(spec.dt);
        PhysicsWorld {
            scene: scene.name.clone(),
            space,
            values,
            grid: spec.effect_grid(),
            reward: scene.reward_table(),
            gravity: v2(spec.gravity),
            params,
            pipeline: PhysicsPipeline::new(),
            sets: s.clone(),
            pristine: s,
            copies: replicas,
            copy_of_body,
            tracked_point: v2(spec.effect.point),
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
            mirror: spec.symmetry.map(|sym| {
                let maps = sym.symbol_maps(scene).expect("validated scene");
                (sym, maps)
            }),
            dt: spec.dt,
            body_names: spec.bodies.iter().map(|b| b.name.clone()).collect(),
            joint_names: spec.joints.iter().map(|j| j.name.clone()).collect(),
        }
    }

    /// The mirror image of `command` when the scene declares a
    /// [`Symmetry`] and that image has the lower index: the command this
    /// world simulates in its place, reflecting the outcome. `None` for the
    /// commands it simulates themselves (all of them without a symmetry).
    pub fn twin(&self, command: &Command) -> Option<Command> {
        let (_, maps) = self.mirror.as_ref()?;
        self.check_command(command).ok()?;
        let image = Command::new(
            command
                .symbols
                .iter()
                .zip(maps)
                .map(|(&s, m)| m[s as usize])
                .collect(),
        );
        (self.space.index_of(&image) < self.space.index_of(command)).then_some(image)
    }

    /// The outcome of a command's mirror image, from the outcome of the
    /// command (its terminal point reflected, then binned); unchanged
    /// without a symmetry.
    pub fn reflect_outcome(&self, outcome: Outcome) -> Outcome {
        let Some((sym, _)) = &self.mirror else {
            return outcome;
        };
        let point = sym.reflect(outcome.point);
        let effect = self.grid.effect_of(point);
        Outcome {
            effect,
            reward: self.reward[effect],
            point,
        }
    }

    /// The effect grid.
    pub fn grid(&self) -> &EffectGrid {
        &self.grid
    }

    /// The number of steps one command takes.
    pub fn steps_per_command(&self) -> u64 {
        if self.together {
            self.phase_steps + self.settle_steps
        } else {
            self.phase_steps * self.space.num_slots() as u64 + self.settle_steps
        }
    }

    /// Executes `command` and records the tracked point after every step
    /// and the terminal pose of every body (for pictures).
    ///
    /// With a [`Symmetry`], a command whose [`twin`](Self::twin) is
    /// simulated in its place gets the twin's trace, reflected.
    pub fn trace(&mut self, command: &Command) -> Result<Trace, WorldError> {
        let mut points = vec![self.tracked_position_in(&self.pristine, 0)];
        let outcome = self.run(command, false, |w| points.push(w.tracked_position()))?;
        let mut poses = self.terminal_poses();
        if let (Some((sym, _)), Some(_)) = (&self.mirror, self.twin(command)) {
            for p in &mut points[1..] {
                *p = sym.reflect(*p);
            }
            for pose in &mut poses {
                pose.position = sym.reflect(pose.position);
                pose.angle = sym.reflect_angle(pose.angle);
            }
        }
        Ok(Trace {
            points,
            poses,
            outcome,
        })
    }

    /// Executes `command` and records its whole motion ([`Motion`]): every
    /// body's pose and velocity, every joint's angle and angular velocity,
    /// with the time, at the start and after every step. The outcome is
    /// [`World::execute`]'s; with a [`Symmetry`], a command whose
    /// [`twin`](Self::twin) is simulated in its place gets the twin's
    /// motion, reflected.
    ///
    /// ```
    /// use e3d::Scene;
    /// let scene = Scene::builtin("arm7").unwrap();
    /// let mut world = scene.physics_world().unwrap();
    /// let c = scene.command_space().parse("+0-0+0-").unwrap();
    /// let m = world.motion(&c).unwrap();
    /// assert_eq!(m.frames.len(), 121); // the start and 120 steps
    /// assert_eq!(m.joints.len(), 7);
    /// assert!(m.frames[15].joint_angles[0] > 0.0); // joint 1 pushed by +t
    /// ```
    pub fn motion(&mut self, command: &Command) -> Result<Motion, WorldError> {
        let dt = self.dt;
        let mut frames = vec![self.frame_of(&self.pristine, 0.0)];
        let outcome = self.run(command, false, |w| {
            let t = frames.len() as f64 * dt;
            frames.push(w.frame_of(&w.sets, t));
        })?;
        if let (Some((sym, _)), Some(_)) = (&self.mirror, self.twin(command)) {
            let sym = *sym;
            for f in &mut frames {
                for (p, v) in f.poses.iter_mut().zip(&mut f.velocities) {
                    p.position = sym.reflect(p.position);
                    p.angle = sym.reflect_angle(p.angle);
                    let [vx, vy] = sym.reflect([v[0], v[1]]);
                    *v = [vx, vy, -v[2]];
                }
                // a mirror turns every relative rotation the other way
                for a in f.joint_angles.iter_mut().chain(&mut f.joint_velocities) {
                    *a = -*a;
                }
            }
        }
        Ok(Motion {
            bodies: self.body_names.clone(),
            joints: self.joint_names.clone(),
            frames,
            outcome,
        })
    }

    /// The state of copy 0 in `sets`, at time `time`.
    fn frame_of(&self, sets: &Sets, time: f64) -> Frame {
        let bodies = &sets.bodies;
        let (mut poses, mut velocities) = (Vec::new(), Vec::new());
        for &h in &self.copies[0].handles {
            let b = &bodies[h];
            let p = b.position();
            poses.push(BodyPose {
                position: [p.translation.x as f64, p.translation.y as f64],
                angle: p.rotation.angle() as f64,
            });
            let v = b.linvel();
            velocities.push([v.x as f64, v.y as f64, b.angvel() as f64]);
        }
        let (mut joint_angles, mut joint_velocities) = (Vec::new(), Vec::new());
        for j in &self.copies[0].joints {
            let (pa, pw) = j.parent.map_or((0.0, 0.0), |p| {
                (
                    bodies[p].rotation().angle() as f64,
                    bodies[p].angvel() as f64,
                )
            });
            let c = &bodies[j.child];
            let a = c.rotation().angle() as f64 - pa - j.offset;
            let a =
                (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
            joint_angles.push(a);
            joint_velocities.push(c.angvel() as f64 - pw);
        }
        Frame {
            time,
            poses,
            velocities,
            joint_angles,
            joint_velocities,
        }
    }

    /// The total kinetic energy (J) of the dynamic bodies at the end of
    /// each step of `command` (for tests of energy conservation).
    pub fn kinetic_energy_trace(&mut self, command: &Command) -> Result<Vec<f64>, WorldError> {
        let mut e = Vec::new();
        self.run(command, false, |w| {
            e.push(
                w.copies[0]
                    .dynamic
                    .iter()
                    .map(|(h, _)| w.sets.bodies[*h].kinetic_energy() as f64)
                    .sum(),
            )
        })?;
        Ok(e)
    }

    /// Executes `command` and reports speeds, contacts between dynamic
    /// bodies and joints at their limits (for diagnostics and docs).
    pub fn inspect(&mut self, command: &Command) -> Result<RunStats, WorldError> {
        let (mut max_speed, mut max_spin) = (0.0f64, 0.0f64);
        let (mut contact_steps, mut limit_steps) = (0u64, 0u64);
        let outcome =
            self.run(command, false, |w| {
                let bodies = &w.sets.bodies;
                for (h, _) in &w.copies[0].dynamic {
                    let b = &bodies[*h];
                    max_speed = max_speed.max((b.linvel().length()) as f64);
                    max_spin = max_spin.max((b.angvel() as f64).abs());
                }
                let dynamic = |c: rapier2d::prelude::ColliderHandle| {
                    w.sets.colliders[c]
                        .parent()
                        .is_some_and(|h| bodies[h].is_dynamic())
                };
                if w.sets.narrow_phase.contact_pairs().any(|p| {
                    p.has_any_active_contact() && dynamic(p.collider1) && dynamic(p.collider2)
                }) {
                    contact_steps += 1;
                }
                let at_limit = w.copies[0].joints.iter().any(|j| {
                    let Some((lo, hi)) = j.limits else {
                        return false;
                    };
                    let pa = j
                        .parent
                        .map_or(0.0, |p| bodies[p].rotation().angle() as f64);
                    let mut a = bodies[j.child].rotation().angle() as f64 - pa - j.offset;
                    a = (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                        - std::f64::consts::PI;
                    a <= lo + 0.01 || a >= hi - 0.01
                });
                if at_limit {
                    limit_steps += 1;
                }
            })?;
        Ok(RunStats {
            outcome,
            max_speed,
            max_spin,
            contact_steps,
            limit_steps,
        })
    }

    fn tracked_position_in(&self, sets: &Sets, copy: usize) -> [f64; 2] {
        let p = sets.bodies[self.copies[copy].tracked]
            .position()
            .transform_point(self.tracked_point);
        [p.x as f64, p.y as f64]
    }

    fn tracked_position(&self) -> [f64; 2] {
        self.tracked_position_in(&self.sets, 0)
    }

    fn diverged(&self, command: Cmd<'_>, reason: String) -> WorldError {
        WorldError::Diverged {
            scene: self.scene.clone(),
            command: self.describe(command),
            reason,
        }
    }

    /// A command as written: its symbols, or its values.
    fn describe(&self, command: Cmd<'_>) -> String {
        match (command, &self.values) {
            (Cmd::Symbols(c), _) => self.space.format(c),
            (Cmd::Values(v), Some(space)) => space.format(v),
            (Cmd::Values(v), None) => format!("{v:?}"),
        }
    }

    fn check_command(&self, command: &Command) -> Result<(), WorldError> {
        if self.values.is_some() {
            return Err(WorldError::BadCommand {
                command: command.to_string(),
                reason: format!(
                    "scene `{}` takes values, not symbols: its slots are continuous (execute_values)",
                    self.scene
                ),
            });
        }
        super::check_command(&self.space, command)
    }

    /// `Ok` if `command` fits this world.
    fn check(&self, command: Cmd<'_>) -> Result<(), WorldError> {
        match (command, &self.values) {
            (Cmd::Symbols(c), _) => self.check_command(c),
            (Cmd::Values(v), Some(space)) => space.check(v).map_err(|e| WorldError::BadCommand {
                command: space.format(v),
                reason: e.to_string(),
            }),
            (Cmd::Values(v), None) => Err(WorldError::BadCommand {
                command: format!("{v:?}"),
                reason: format!(
                    "scene `{}` takes symbols, not values: its slots are not continuous",
                    self.scene
                ),
            }),
        }
    }

    /// Starts the actions of one slot.
    fn apply(&mut self, act: Act) {
        let bodies = &mut self.sets.bodies;
        match act {
            Act::Idle => {}
            Act::Torque {
                child,
                parent,
                torque,
            } => {
                bodies[child].add_torque(torque, true);
                if let Some(p) = parent {
                    bodies[p].add_torque(-torque, true);
                }
            }
            Act::Impulse { body, impulse } => bodies[body].apply_impulse(impulse, true),
            Act::Force { body, force } => bodies[body].add_force(force, true),
            Act::Target {
                child,
                angle,
                stiffness,
                damping,
            } => {
                let mbj = &mut self.sets.multibody_joints;
                let link = *mbj.rigid_body_link(child).expect("a jointed body");
                if let Some(l) = mbj
                    .get_multibody_mut(link.multibody)
                    .and_then(|mb| mb.link_mut(link.id))
                {
                    l.joint
                        .data
                        .set_motor_position(JointAxis::AngX, angle, stiffness, damping);
                }
            }
        }
    }

    /// Starts the actions of slot `slot` of `command` on copy `copy`.
    fn apply_slot(&mut self, copy: usize, command: Cmd<'_>, slot: usize) {
        let act = match command {
            Cmd::Symbols(c) => self.copies[copy].acts[self.offset[slot] + c.symbols[slot] as usize],
            Cmd::Values(v) => self.copies[copy].value_acts[slot].at(v[slot]),
        };
        self.apply(act);
    }

    /// Removes every held force and torque (of every copy).
    fn release(&mut self) {
        for r in &self.copies {
            for (h, _) in &r.dynamic {
                let b = &mut self.sets.bodies[*h];
                b.reset_forces(false);
                b.reset_torques(false);
            }
        }
    }

    /// Switches off, for the coming step, the limits of the joints that
    /// cannot reach them during it, and on again those of the others.
    ///
    /// Why this changes no result: Rapier rebuilds a multibody joint's
    /// limit constraint at every substep whatever the joint's position, and
    /// one whose joint is inside its limits has impulse bounds `[0, 0]`, so
    /// it never changes a velocity (`v + 0 = v`). It still costs a solve
    /// with the multibody's LU factorisation at every substep, about 14% of
    /// an arm7 rollout. A joint further than [`LIMIT_GATE_MARGIN`] plus four
    /// steps of its current speed from both limits keeps its limit off for
    /// one step. Joints with a motor are left alone (Rapier's motor
    /// constraint reads the limits too).
    ///
    /// The margin is an assumption about how far a joint can move within
    /// one step, so it is checked: after the step, a joint whose limit was
    /// off and which moved more than half the margin sets `gate_missed`,
    /// and the command is run again with every limit on
    /// ([`run_copies`](Self::run_copies)). Every table of the shipped
    /// scenes is byte-identical with and without the gating.
    fn gate_limits(&mut self) {
        if !self.gate_limits {
            return;
        }
        let dt = self.params.dt as f64;
        let total: usize = self.copies.iter().map(|c| c.joints.len()).sum();
        self.gated_angles.resize(total, f64::NAN);
        let mbs = &mut self.sets.multibody_joints;
        let joints = self.copies.iter().flat_map(|c| &c.joints);
        for (j, gated) in joints.zip(&mut self.gated_angles) {
            *gated = f64::NAN;
            let Some((lo, hi)) = j.limits else { continue };
            let Some(link) = mbs.rigid_body_link(j.child).copied() else {
                continue;
            };
            let Some(mb) = mbs.get_multibody_mut(link.multibody) else {
                continue;
            };
            let Some(l) = mb.link(link.id) else { continue };
            if !l.joint().data.motor_axes.is_empty() {
                continue;
            }
            // a revolute joint's angle is its angular coordinate
            let q = l.joint().coords()[2] as f64;
            let w = mb.generalized_velocity()[l.assembly_id()] as f64;
            let margin = self.gate_margin + self.gate_speed_steps * w.abs() * dt;
            let near = q - lo < margin || hi - q < margin;
            let Some(l) = mb.link_mut(link.id) else {
                continue;
            };
            let axes = &mut l.joint.data.limit_axes;
            if near {
                axes.insert(JointAxesMask::ANG_X);
            } else {
                axes.remove(JointAxesMask::ANG_X);
                *gated = q;
            }
        }
    }

    /// After a step: whether a joint whose limit was off moved more than
    /// half of [`LIMIT_GATE_MARGIN`] (see [`gate_limits`](Self::gate_limits)).
    fn check_gated(&mut self) {
        if !self.gate_limits || self.gate_missed {
            return;
        }
        let mbs = &self.sets.multibody_joints;
        let joints = self.copies.iter().flat_map(|c| &c.joints);
        for (j, &q0) in joints.zip(&self.gated_angles) {
            if q0.is_nan() {
                continue;
            }
            let moved = mbs
                .rigid_body_link(j.child)
                .and_then(|link| mbs.get_multibody(link.multibody)?.link(link.id))
                .map(|l| (l.joint().coords()[2] as f64 - q0).abs());
            if !moved.is_some_and(|m| m <= 0.5 * self.gate_margin) {
                self.gate_missed = true;
                return;
            }
        }
    }

    /// One Rapier step of the whole world.
    fn pipeline_step(&mut self) {
        self.gate_limits();
        self.step_rapier();
        self.check_gated();
    }

    /// Rapier's step, nothing else.
    fn step_rapier(&mut self) {
        let s = &mut self.sets;
        self.pipeline.step(
            self.gravity,
            &self.params,
            &mut s.islands,
            &mut s.broad_phase,
            &mut s.narrow_phase,
            &mut s.bodies,
            &mut s.colliders,
            &mut s.impulse_joints,
            &mut s.multibody_joints,
            &mut s.soft_bodies,
            &mut s.ccd,
            &(),
            &(),
        );
    }

    /// The copies Rapier quarantined during the last step, with the number
    /// of bodies and colliders of each (`None`: nothing quarantined).
    fn quarantined(&self) -> Option<Vec<(usize, usize)>> {
        let q = self.pipeline.quarantine();
        if q.bodies().is_empty() && q.colliders().is_empty() {
            return None;
        }
        let mut per_copy = vec![(0usize, 0usize); self.copies.len()];
        let copy_of = |h: RigidBodyHandle| -> Option<usize> {
            let c = *self.copy_of_body.get(h.into_raw_parts().0 as usize)?;
            (c != u32::MAX).then_some(c as usize)
        };
        // a body or collider of no known copy counts against every copy
        let mut charge = |c: Option<usize>, body: bool| match c {
            Some(c) => {
                if body {
                    per_copy[c].0 += 1
                } else {
                    per_copy[c].1 += 1
                }
            }
            None => per_copy
                .iter_mut()
                .for_each(|p| if body { p.0 += 1 } else { p.1 += 1 }),
        };
        for &h in q.bodies() {
            charge(copy_of(h), true);
        }
        for &c in q.colliders() {
            charge(
                self.sets
                    .colliders
                    .get(c)
                    .and_then(|c| c.parent())
                    .and_then(copy_of),
                false,
            );
        }
        Some(per_copy)
    }

    /// Why copy `copy` counts as blown up after a step, if it does.
    fn blown_up(&self, copy: usize) -> Option<String> {
        let dt = self.params.dt as f64;
        for &(h, fast) in &self.copies[copy].dynamic {
            let b = &self.sets.bodies[h];
            let t = b.translation();
            let v = b.linvel();
            let w = b.angvel() as f64;
            if !(t.x.is_finite()
                && t.y.is_finite()
                && v.x.is_finite()
                && v.y.is_finite()
                && w.is_finite())
            {
                return Some("a body's pose or velocity is not finite".into());
            }
            // squared speeds first: `hypot` at every step of every body
            // costs a few per cent of a puck's rollout
            let (vx, vy) = (v.x as f64, v.y as f64);
            if vx * vx + vy * vy > self.max_speed * self.max_speed && vx.hypot(vy) > self.max_speed
            {
                let speed = vx.hypot(vy);
                return Some(format!(
                    "a body moves at {speed:.1} m/s, above the scene's max_speed {} m/s",
                    self.max_speed
                ));
            }
            if !fast && w.abs() * dt >= 0.99 * MAX_ROTATION_PER_STEP {
                return Some(format!(
                    "a body spins at {:.1} rad/s, Rapier's cap of 45° per step: its rotation would be silently clamped (give it `fast_rotation: true` or a smaller dt)",
                    w.abs()
                ));
            }
        }
        None
    }

    /// One step, then the checks of the copies still running (`failed[c]`
    /// is `None`); a copy that blows up gets its error in `failed`.
    /// Returns whether some copy is still running.
    fn step(&mut self, commands: &[Cmd<'_>], failed: &mut [Option<WorldError>]) -> bool {
        self.pipeline_step();
        if let Some(q) = self.quarantined() {
            for (c, &(bodies, colliders)) in q.iter().enumerate().take(commands.len()) {
                if failed[c].is_none() && bodies + colliders > 0 {
                    failed[c] = Some(self.diverged(
                        commands[c],
                        format!(
                            "Rapier quarantined {bodies} bod(ies) and {colliders} collider(s) whose state became non-finite"
                        ),
                    ));
                }
            }
        }
        let mut running = false;
        for c in 0..commands.len() {
            if failed[c].is_none() {
                match self.blown_up(c) {
                    Some(reason) => failed[c] = Some(self.diverged(commands[c], reason)),
                    None => running = true,
                }
            }
        }
        running
    }

    /// Runs `commands` (at most one per copy; copy `c` runs `commands[c]`,
    /// copies without a command stay idle) from the pristine state, calling
    /// `each_step` after every step, and appends one result per command to
    /// `out`.
    ///
    /// With `gated`, limits far from their joints are left out of steps
    /// ([`gate_limits`](Self::gate_limits)); if a joint then moves further
    /// than the gating assumes, the commands are run again with every limit
    /// on, so the results are always those of Rapier with every limit.
    /// Traces run with every limit on (`gated` false), so that `each_step`
    /// sees each step once.
    fn run_copies(
        &mut self,
        commands: &[Cmd<'_>],
        out: &mut Vec<Result<Outcome, WorldError>>,
        gated: bool,
        each_step: impl FnMut(&Self),
    ) {
        let configured = self.gate_limits;
        self.gate_limits = configured && gated;
        self.gate_missed = false;
        let start = out.len();
        self.run_copies_once(commands, out, each_step);
        if self.gate_missed {
            out.truncate(start);
            self.gate_limits = false;
            self.run_copies_once(commands, out, |_| {});
        }
        self.gate_limits = configured;
    }

    /// [`run_copies`](Self::run_copies) once, with the gating as set.
    fn run_copies_once(
        &mut self,
        commands: &[Cmd<'_>],
        out: &mut Vec<Result<Outcome, WorldError>>,
        mut each_step: impl FnMut(&Self),
    ) {
        let n = commands.len();
        assert!(n <= self.copies.len(), "more commands than copies");
        let mut failed: Vec<Option<WorldError>> =
            commands.iter().map(|&c| self.check(c).err()).collect();
        self.sets.restore(&self.pristine);
        let slots = self.space.num_slots();
        let mut running = failed.iter().any(Option::is_none);
        // one phase with every slot (simultaneous) or one phase per slot
        // (sequential): apply the phase's slots, step, release
        let (phases, width) = if self.together {
            (1, slots)
        } else {
            (slots, 1)
        };
        for phase in 0..phases {
            for (c, &command) in commands.iter().enumerate() {
                if failed[c].is_none() {
                    for slot in phase * width..(phase + 1) * width {
                        self.apply_slot(c, command, slot);
                    }
                }
            }
            for _ in 0..self.phase_steps {
                if !running {
                    break;
                }
                running = self.step(commands, &mut failed);
                each_step(self);
            }
            self.release();
        }
        for _ in 0..self.settle_steps {
            if !running {
                break;
            }
            running = self.step(commands, &mut failed);
            each_step(self);
        }
        for (c, f) in failed.into_iter().enumerate() {
            out.push(match f {
                Some(e) => Err(e),
                None => {
                    let point = self.tracked_position_in(&self.sets, c);
                    let effect = self.grid.effect_of(point);
                    Ok(Outcome {
                        effect,
                        reward: self.reward[effect],
                        point,
                    })
                }
            });
        }
    }

    /// Runs `command` on copy 0 from the pristine state, calling
    /// `each_step` after every step; returns the outcome.
    ///
    /// A command with a [`twin`](Self::twin) runs its twin instead, and
    /// gets the reflected outcome (`each_step` sees the twin's steps).
    fn run(
        &mut self,
        command: &Command,
        gated: bool,
        each_step: impl FnMut(&Self),
    ) -> Result<Outcome, WorldError> {
        let mut out = Vec::with_capacity(1);
        let twin = self.twin(command);
        let run = Cmd::Symbols(twin.as_ref().unwrap_or(command));
        self.run_copies(&[run], &mut out, gated, each_step);
        let result = out.pop().expect("one result per command");
        match twin {
            None => result,
            Some(t) => self.mirrored_result(command, &t, result),
        }
    }

    /// The result of `command` from the result of its twin `twin`: the
    /// outcome reflected, or the twin's failure, naming both commands.
    fn mirrored_result(
        &self,
        command: &Command,
        twin: &Command,
        result: Result<Outcome, WorldError>,
    ) -> Result<Outcome, WorldError> {
        match result {
            Ok(o) => Ok(self.reflect_outcome(o)),
            Err(WorldError::Diverged { scene, reason, .. }) => Err(WorldError::Diverged {
                scene,
                command: self.space.format(command),
                reason: format!(
                    "{reason} (simulated as its mirror image {}, by the scene's symmetry)",
                    self.space.format(twin)
                ),
            }),
            Err(e) => Err(e),
        }
    }

    /// Runs the values of a continuous command on copy 0 from the pristine
    /// state, calling `each_step` after every step.
    fn run_values(
        &mut self,
        values: &[f64],
        gated: bool,
        each_step: impl FnMut(&Self),
    ) -> Result<Outcome, WorldError> {
        let mut out = Vec::with_capacity(1);
        self.run_copies(&[Cmd::Values(values)], &mut out, gated, each_step);
        out.pop().expect("one result per command")
    }

    /// The ranges of a continuous scene's slots (`None` for a scene of
    /// symbols).
    pub fn value_space(&self) -> Option<&ValueSpace> {
        self.values.as_ref()
    }

    /// Executes a continuous command open loop from the start state: slot
    /// `i` acts with the value `values[i]` (see
    /// [`ValueAction`](crate::scene::ValueAction)), on the scene's
    /// schedule. The same values always give the same bits. A scene of
    /// symbols, a wrong number of values or a value outside its range is a
    /// [`WorldError::BadCommand`].
    ///
    /// ```
    /// use e3d::Scene;
    /// let scene = Scene::builtin("arm7_continuous").unwrap();
    /// let mut world = scene.physics_world().unwrap();
    /// let space = world.value_space().unwrap().clone();
    /// let v = space.parse("1.8, -1.2, 0.75, 0, 0, 0, 0").unwrap();
    /// let a = world.execute_values(&v).unwrap();
    /// assert_eq!(world.execute_values(&v).unwrap(), a);
    /// assert!(world.execute_values(&[2.0; 7]).is_err()); // 2 > 1.8 on slot 0
    /// ```
    pub fn execute_values(&mut self, values: &[f64]) -> Result<Outcome, WorldError> {
        self.run_values(values, true, |_| {})
    }

    /// Executes continuous commands (any number), up to
    /// [`num_copies`](Self::num_copies) at once, and appends one result per
    /// command to `out`, in order: each the one
    /// [`execute_values`](Self::execute_values) gives on a world of one
    /// copy (up to the copies' contact order, as for
    /// [`execute_batch`](Self::execute_batch)).
    pub fn execute_values_batch(
        &mut self,
        commands: &[Vec<f64>],
        out: &mut Vec<Result<Outcome, WorldError>>,
    ) {
        out.reserve(commands.len());
        for batch in commands.chunks(self.copies.len()) {
            let batch: Vec<Cmd<'_>> = batch.iter().map(|v| Cmd::Values(v)).collect();
            self.run_copies(&batch, out, true, |_| {});
        }
    }

    /// [`trace`](Self::trace) of a continuous command.
    pub fn trace_values(&mut self, values: &[f64]) -> Result<Trace, WorldError> {
        let mut points = vec![self.tracked_position_in(&self.pristine, 0)];
        let outcome = self.run_values(values, false, |w| points.push(w.tracked_position()))?;
        Ok(Trace {
            points,
            poses: self.terminal_poses(),
            outcome,
        })
    }

    /// [`motion`](Self::motion) of a continuous command.
    pub fn motion_values(&mut self, values: &[f64]) -> Result<Motion, WorldError> {
        let dt = self.dt;
        let mut frames = vec![self.frame_of(&self.pristine, 0.0)];
        let outcome = self.run_values(values, false, |w| {
            let t = frames.len() as f64 * dt;
            frames.push(w.frame_of(&w.sets, t));
        })?;
        Ok(Motion {
            bodies: self.body_names.clone(),
            joints: self.joint_names.clone(),
            frames,
            outcome,
        })
    }

    /// The pose of every body of copy 0 now.
    fn terminal_poses(&self) -> Vec<BodyPose> {
        self.copies[0]
            .handles
            .iter()
            .map(|&h| {
                let p = self.sets.bodies[h].position();
                BodyPose {
                    position: [p.translation.x as f64, p.translation.y as f64],
                    angle: p.rotation.angle() as f64,
                }
            })
            .collect()
    }

    /// Restores every Rapier set to the pristine state, as before each
    /// command (exposed to measure its cost; commands do it themselves).
    pub fn reset(&mut self) {
        self.sets.restore(&self.pristine);
    }

    /// The number of copies this world holds (see
    /// [`with_copies`](Self::with_copies)).
    pub fn num_copies(&self) -> usize {
        self.copies.len()
    }

    /// Executes `commands` (any number), up to [`num_copies`](Self::num_copies)
    /// at once, and appends one result per command to `out`, in order. Each
    /// result is the one [`World::execute`] gives for that command; a
    /// command that blows up fails alone, the others of its batch go on.
    /// With a [`Symmetry`], a command with a [`twin`](Self::twin) runs as
    /// its twin.
    pub fn execute_batch(
        &mut self,
        commands: &[Command],
        out: &mut Vec<Result<Outcome, WorldError>>,
    ) {
        out.reserve(commands.len());
        let start = out.len();
        let twins: Vec<Option<Command>> = match self.mirror {
            Some(_) => commands.iter().map(|c| self.twin(c)).collect(),
            None => Vec::new(),
        };
        let runs: std::borrow::Cow<'_, [Command]> = if twins.iter().any(Option::is_some) {
            let runs = commands.iter().zip(&twins);
            runs.map(|(c, t)| t.as_ref().unwrap_or(c).clone()).collect()
        } else {
            commands.into()
        };
        for batch in runs.chunks(self.copies.len()) {
            let batch: Vec<Cmd<'_>> = batch.iter().map(Cmd::Symbols).collect();
            self.run_copies(&batch, out, true, |_| {});
        }
        for (k, (c, t)) in commands.iter().zip(&twins).enumerate() {
            if let Some(t) = t {
                let r =
                    std::mem::replace(&mut out[start + k], Err(WorldError::Other(String::new())));
                out[start + k] = self.mirrored_result(c, t, r);
            }
        }
    }
}

impl World for PhysicsWorld {
    fn command_space(&self) -> &CommandSpace {
        &self.space
    }

    fn num_effects(&self) -> usize {
        self.grid.num_cells()
    }

    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        self.run(command, true, |_| {})
    }

    fn execute_batch(&mut self, commands: &[Command], out: &mut Vec<Result<Outcome, WorldError>>) {
        // the inherent method: up to `num_copies` commands stepped together
        PhysicsWorld::execute_batch(self, commands, out)
    }

    fn mirror_of(&self, command: &Command) -> Option<Command> {
        self.twin(command)
    }

    fn mirror_outcome(&self, outcome: Outcome) -> Outcome {
        self.reflect_outcome(outcome)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::WorldSpec;

    /// Leaving far limits out of a step changes no bit: arm7 (whose joints
    /// reach their limits on many commands) and pendulum3, on commands
    /// spread over their spaces, give the same terminal points with and
    /// without the gating.
    #[test]
    fn limit_gating_changes_no_bit() {
        for name in ["arm7", "pendulum3"] {
            let scene = Scene::builtin(name).unwrap();
            let WorldSpec::Physics(spec) = &scene.world else {
                unreachable!("a physics scene")
            };
            let space = scene.command_space();
            let n = space.num_commands().unwrap();
            let mut gated = PhysicsWorld::from_scene(&scene, spec);
            let mut plain = PhysicsWorld::from_scene(&scene, spec);
            plain.gate_limits = false;
            let mut c = space.first();
            for k in 0..60u64 {
                space.write_command_at(k * 7919 % n, &mut c);
                let a = gated.execute(&c).unwrap();
                let b = plain.execute(&c).unwrap();
                assert_eq!(
                    a.point.map(f64::to_bits),
                    b.point.map(f64::to_bits),
                    "{name} {k}"
                );
                assert_eq!(a.effect, b.effect);
            }
        }
    }

    /// When a joint moves further in a step than the gating assumes, the
    /// command is run again with every limit on: with a margin far too
    /// small (joints reach their limits while those are off), the results
    /// are still those of the ungated world, and the rerun happened.
    #[test]
    fn a_missed_gate_reruns_the_command_with_every_limit() {
        let scene = Scene::builtin("arm7").unwrap();
        let WorldSpec::Physics(spec) = &scene.world else {
            unreachable!("a physics scene")
        };
        let space = scene.command_space();
        let mut careless = PhysicsWorld::from_scene(&scene, spec);
        careless.gate_margin = 1e-6;
        careless.gate_speed_steps = 0.0;
        let mut plain = PhysicsWorld::from_scene(&scene, spec);
        plain.gate_limits = false;
        let mut reruns = 0;
        let mut c = space.first();
        for k in 0..20u64 {
            space.write_command_at(k * 7919 % 2187, &mut c);
            let a = careless.execute(&c).unwrap();
            reruns += usize::from(careless.gate_missed);
            let b = plain.execute(&c).unwrap();
            assert_eq!(a.point.map(f64::to_bits), b.point.map(f64::to_bits), "{k}");
        }
        assert!(reruns >= 15, "only {reruns} of 20 commands were rerun");
    }
}
