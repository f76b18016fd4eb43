//! The physics world: a scene's bodies and joints simulated by Rapier
//! ([`PhysicsWorld`]).
//!
//! `build` makes the Rapier sets of a scene; `step` applies commands,
//! steps and guards against blow-ups; `record` records traces and motions;
//! `mirror` runs a command as its mirror image under the scene's symmetry;
//! `context` and `joint_start` start commands from given states; `prefix`
//! reuses the states at the phase ends of earlier commands.

mod build;
mod context;
mod joint_start;
mod mirror;
mod noise;
mod prefix;
mod record;
mod step;

pub use context::PhysicsState;
pub use prefix::PREFIX_STATES;
pub use record::{BodyPose, Frame, Motion, RunStats, Trace};

use super::{Outcome, World, WorldError};
use crate::command::{Command, CommandSpace, ValueSpace};
use crate::effect::{Binning, EffectGrid};
use crate::scene::physics::{DragSpec, DrawKey};
use crate::scene::Symmetry;
use rapier2d::math::{Real, Vector};
use rapier2d::prelude::{
    BroadPhaseBvh, CCDSolver, ColliderSet, ImpulseJointHandle, ImpulseJointSet,
    IntegrationParameters, IslandManager, JointAxis, MultibodyJointSet, NarrowPhase,
    PhysicsPipeline, RigidBodyHandle, RigidBodySet, SoftBodySet,
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
        /// The joint, when it is an impulse joint (a free-floating tree);
        /// else the child's multibody link holds it.
        impulse: Option<ImpulseJointHandle>,
        /// `AngX` for a hinge, `LinX` for a slider.
        axis: JointAxis,
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

/// One command a copy runs: symbols, or the values of a continuous scene.
#[derive(Debug, Clone, Copy)]
enum Cmd<'a> {
    Symbols(&'a Command),
    Values(&'a [f64]),
}

/// A joint, for diagnostics: child, parent, angle offset, limits.
#[derive(Debug, Clone, Copy)]
struct JointInfo {
    child: RigidBodyHandle,
    parent: Option<RigidBodyHandle>,
    offset: f64,
    limits: Option<(f64, f64)>,
    /// A slider's unit axis in the parent's frame (world for `ground`)
    /// and its anchors (parent's, child's), for its position; `None` for
    /// a hinge.
    slider: Option<(Vector, Vector, Vector)>,
}

impl JointInfo {
    /// The joint's coordinate now: a hinge's angle (the child's rotation
    /// relative to the parent, 0 at the start pose, in `(-pi, pi]`), a
    /// slider's position along its axis (m, 0 at the start pose); and its
    /// rate (rad/s or m/s).
    fn coordinate(&self, bodies: &RigidBodySet) -> (f64, f64) {
        let c = &bodies[self.child];
        let parent = self.parent.map(|p| &bodies[p]);
        if let Some((axis, a1, a2)) = self.slider {
            let (p1, v1, axis) = match parent {
                Some(p) => {
                    let w = p.position().transform_point(a1);
                    (w, p.velocity_at_point(w), p.position().rotation * axis)
                }
                None => (a1, Vector::ZERO, axis),
            };
            let p2 = c.position().transform_point(a2);
            let v2 = c.velocity_at_point(p2);
            return ((p2 - p1).dot(axis) as f64, (v2 - v1).dot(axis) as f64);
        }
        let (pa, pw) = parent.map_or((0.0, 0.0), |p| {
            (p.rotation().angle() as f64, p.angvel() as f64)
        });
        let a = c.rotation().angle() as f64 - pa - self.offset;
        let a = (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        (a, c.angvel() as f64 - pw)
    }
}

/// One feature of the effect, resolved to handles.
#[derive(Debug, Clone)]
enum Probe {
    /// A point of `body`, in world coordinates or in `frame`'s.
    Point {
        body: RigidBodyHandle,
        point: Vector,
        frame: Option<RigidBodyHandle>,
    },
    /// A joint's coordinate, by its index in the replica's joints.
    Joint(usize),
    /// A body's angle in the world.
    Angle(RigidBodyHandle),
    /// The centre of mass of bodies of these masses (kg).
    Centre(Vec<(RigidBodyHandle, f64)>),
}

/// A scene's rigid-body world, simulated by Rapier.
///
/// Built once per scene; before each command every Rapier set is restored
/// (`clone_from`) from a pristine copy, so the same command always gives
/// the same bits, whatever ran before. Jointed bodies are
/// [multibodies](rapier2d::dynamics::MultibodyJointSet) (reduced
/// coordinates: chains do not stretch); joint damping is their implicit
/// per-DoF damping. Impulses act once at the start of a slot's phase, forces and
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
    /// [`PhysicsScene::world`](crate::world::PhysicsScene::world)); copy 0 is the one
    /// [`World::execute`] uses.
    copies: Vec<Replica>,
    /// The copy owning each body, by the body handle's index (`u32::MAX`
    /// for shared fixed bodies): attributes Rapier's quarantine.
    copy_of_body: Vec<u32>,
    tracked_point: Vector,
    /// How the features the probes read make the effect.
    binning: Binning,
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
    /// The start contexts (one, the pristine start, for a scene without
    /// contexts).
    contexts: Vec<context::ContextStart>,
    /// The joints' anchors and order, for the contexts that set them.
    joint_geometry: joint_start::JointGeometry,
    /// The states at the phase ends of the prefixes run so far (a world
    /// of one copy on a sequential schedule; see [`prefix`]).
    prefixes: prefix::Prefixes,
    /// The scene's noise, if it draws anything: then no prefix state is
    /// kept and no mirror twin runs (a command's draws are its own).
    noise: Option<noise::Noise>,
    /// The forces and torques the bodies with drag held before a step's
    /// drag was added (kept between steps: no allocation per step).
    held_forces: Vec<(Vector, Real)>,
}

/// One copy of a scene's non-fixed bodies and joints, resolved to handles.
#[derive(Debug, Clone)]
struct Replica {
    /// The scene's bodies, in order (fixed bodies are shared by the copies).
    handles: Vec<RigidBodyHandle>,
    /// Dynamic bodies, and whether each may spin fast.
    dynamic: Vec<(RigidBodyHandle, bool)>,
    /// The dynamic bodies with drag, and their drag.
    drag: Vec<(RigidBodyHandle, DragSpec)>,
    tracked: RigidBodyHandle,
    /// What the effect reads, one probe per feature.
    probes: Vec<Probe>,
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

impl PhysicsWorld {
    /// The effect grid.
    pub fn grid(&self) -> &EffectGrid {
        &self.grid
    }

    /// The layout point and the effect of the start state, before any
    /// command: where the effect's features are binned at rest.
    pub fn start(&self) -> ([f64; 2], usize) {
        self.located_in(&self.pristine, 0)
    }

    /// The number of steps one command takes.
    pub fn steps_per_command(&self) -> u64 {
        if self.together {
            self.phase_steps + self.settle_steps
        } else {
            self.phase_steps * self.space.num_slots() as u64 + self.settle_steps
        }
    }

    /// The ranges of a continuous scene's slots (`None` for a scene of
    /// symbols).
    pub fn value_space(&self) -> Option<&ValueSpace> {
        self.values.as_ref()
    }

    /// Restores every Rapier set to the pristine state, as before each
    /// command (exposed to measure its cost; commands do it themselves).
    pub fn reset(&mut self) {
        self.sets.restore(&self.pristine);
    }

    /// Keeps at most `capacity` phase-end states of the prefixes of the
    /// commands run (0: none; by default [`PREFIX_STATES`], none in a world
    /// of many copies), and forgets those kept. On a `Sequential` schedule
    /// a command that shares a prefix with an earlier one starts from the
    /// deepest state kept: the same bits, fewer steps. A state takes 16 to
    /// 25 KB on the shipped scenes.
    ///
    /// ```
    /// use e3d::{Scene, World};
    /// let scene = Scene::builtin("puck_rooms").unwrap();
    /// let mut world = scene.physics_world().unwrap();
    /// assert_eq!(world.prefix_depth(), 5); // 4 + 16 + 64 + 256 + 1024 states
    /// let c = world.command_space().parse("SEEEEES").unwrap();
    /// let a = world.execute(&c).unwrap();
    /// assert_eq!(world.prefix_states_kept(), 5);
    /// let d = world.command_space().parse("SEEEWWN").unwrap();
    /// world.execute(&d).unwrap(); // starts after `SEEE`
    /// world.set_prefix_states(0);
    /// assert_eq!((world.prefix_depth(), world.prefix_states_kept()), (0, 0));
    /// assert_eq!(world.execute(&c).unwrap(), a); // every step simulated
    /// ```
    pub fn set_prefix_states(&mut self, capacity: usize) {
        self.prefixes = self.prefixes.with_capacity(capacity);
    }

    /// The longest prefix, in slots, whose phase-end states this world
    /// keeps (see [`set_prefix_states`](Self::set_prefix_states)).
    pub fn prefix_depth(&self) -> usize {
        self.prefixes.depth()
    }

    /// The number of phase-end states kept now (see
    /// [`set_prefix_states`](Self::set_prefix_states)).
    pub fn prefix_states_kept(&self) -> usize {
        self.prefixes.len()
    }

    /// The number of copies this world holds (see
    /// [`PhysicsScene::world`](crate::world::PhysicsScene::world)).
    pub fn num_copies(&self) -> usize {
        self.copies.len()
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
        self.run_one(Cmd::Symbols(command), true, |_| {})
    }

    /// Not when the scene has a `noise` section that draws something.
    fn is_deterministic(&self) -> bool {
        self.noise.is_none()
    }

    fn set_draw_keys(&mut self, keys: &[DrawKey]) {
        if let Some(n) = &mut self.noise {
            n.give(keys);
        }
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
    use crate::scene::{Scene, WorldSpec};
    use rapier2d::prelude::JointAxesMask;

    /// Leaving far limits out of a step changes no bit: arm7 (whose joints
    /// reach their limits on many commands) and pendulum3, on commands
    /// spread over their spaces, give the same terminal points with and
    /// without the gating.
    #[test]
    fn limit_gating_changes_no_bit() {
        for name in ["arm7", "pendulum3"] {
            let scene = Scene::builtin(name).unwrap();
            let space = scene.command_space();
            let n = space.num_commands().unwrap();
            let mut gated = scene.as_physics().unwrap().world(1);
            let mut plain = scene.as_physics().unwrap().world(1);
            plain.gate_limits = false;
            let mut c = space.first();
            for k in 0..60u64 {
                space.write_command_at(k * 7919 % n, &mut c);
                let a = gated.execute(&c).unwrap();
                let b = plain.execute(&c).unwrap();
                let bits = |o: Outcome| (o.point.map(f64::to_bits), o.effect);
                assert_eq!(bits(a), bits(b), "{name} {k}");
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
        let space = scene.command_space();
        let mut careless = scene.as_physics().unwrap().world(1);
        careless.gate_margin = 1e-6;
        careless.gate_speed_steps = 0.0;
        let mut plain = scene.as_physics().unwrap().world(1);
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

    /// A batch of 3 commands on a world of 32 copies simulates 3: the
    /// other copies' bodies are switched off and stay where they start;
    /// the next batch of 32 switches every copy on again.
    #[test]
    fn copies_without_a_command_are_not_simulated() {
        let scene = Scene::builtin("puck_rooms").unwrap();
        let space = scene.command_space();
        let mut world = scene.as_physics().unwrap().world(32);
        let start = world.tracked_position_in(&world.pristine, 31);
        let cmds: Vec<_> = (0..32u64)
            .map(|k| space.command_at(k * 509 % 16384))
            .collect();
        let enabled = |w: &PhysicsWorld, c: usize| w.sets.bodies[w.copies[c].tracked].is_enabled();
        let mut out = Vec::new();
        world.execute_batch(&cmds[..3], &mut out);
        assert!((0..3).all(|c| enabled(&world, c)));
        assert!((3..32).all(|c| !enabled(&world, c)));
        assert_eq!(world.tracked_position_in(&world.sets, 31), start);
        world.execute_batch(&cmds, &mut out);
        assert!((0..32).all(|c| enabled(&world, c)));
        assert_ne!(world.tracked_position_in(&world.sets, 31), start);
    }

    /// Prefix states and the gating together: on arm7 run sequentially
    /// (its joints gated, a slot's torques for 0.25 s each), a world that
    /// reuses prefix states and gates carelessly (some commands rerun)
    /// gives the bits of a world that does neither. A state kept from a
    /// gated phase has every limit on again.
    #[test]
    fn prefix_states_hold_every_limit() {
        let mut arm = Scene::builtin("arm7").unwrap().to_spec();
        let WorldSpec::Physics(p) = &mut arm.world else {
            unreachable!("a physics scene")
        };
        p.schedule = crate::scene::physics::Schedule::Sequential {
            phase: 0.25,
            settle: 1.0,
        };
        p.symmetry = None;
        let scene = arm.validate().unwrap();
        let space = scene.command_space();
        let n = space.num_commands().unwrap();
        let mut careless = scene.as_physics().unwrap().world(1);
        assert!(careless.prefix_depth() > 0);
        careless.gate_margin = 0.15;
        careless.gate_speed_steps = 0.0;
        let mut plain = scene.as_physics().unwrap().world(1);
        plain.gate_limits = false;
        plain.set_prefix_states(0);
        let (mut reruns, mut reused) = (0, 0);
        let mut c = space.first();
        for k in 0..120u64 {
            // neighbours in index order share long prefixes
            space.write_command_at((k / 4) * 7919 % n + k % 4, &mut c);
            let kept = careless.prefix_states_kept();
            let a = careless.execute(&c).unwrap();
            reruns += usize::from(careless.gate_missed);
            reused += usize::from(careless.prefix_states_kept() == kept);
            let b = plain.execute(&c).unwrap();
            assert_eq!(a.point.map(f64::to_bits), b.point.map(f64::to_bits), "{k}");
        }
        assert!(reruns >= 20, "only {reruns} of 120 commands were rerun");
        assert!(reused >= 40, "only {reused} of 120 commands reused a state");
        // every state kept has every limit on, as the pristine state has
        let mbs = |s: &'_ Sets| {
            let j = &careless.copies[0].joints;
            j.iter()
                .filter(|j| {
                    let link = s.multibody_joints.rigid_body_link(j.child).unwrap();
                    let mb = s.multibody_joints.get_multibody(link.multibody).unwrap();
                    let axes = mb.link(link.id).unwrap().joint().data.limit_axes;
                    axes.contains(JointAxesMask::ANG_X)
                })
                .count()
        };
        assert_eq!(mbs(&careless.pristine), 7);
        assert!(careless.prefixes.states().all(|s| mbs(s) == 7));
    }
}
