//! Start contexts and states of a physics world: where a command starts
//! from, and the state it leaves, continued exactly by the next command.
//!
//! A [`PhysicsState`] carries a snapshot of every Rapier set (bodies,
//! colliders, joints and their motors' set points, the island manager,
//! the broad phase, the narrow phase with its contact manifolds and the
//! solver's warm-start impulses, the CCD solver): the next command starts
//! from those very bits, so executing `c1` then `c2` from the state `c1`
//! left is one continued rollout of `c1` then `c2`. Poses and velocities
//! alone would not be: a body resting against a wall restarts with no
//! contact manifold and no warm-start impulse, and its first step differs
//! in the last bits (and multibody links are set by their joints'
//! coordinates, not by their poses). The poses, velocities and joint
//! coordinates are also kept in the open, to compare and serialise.

use super::joint_start::{set_joints, JointGeometry};
use super::{v2, Cmd, JointInfo, PhysicsWorld, Replica, Sets};
use crate::command::Command;
use crate::rng::SessionRng;
use crate::scene::physics::{BodyStart, JointStart, PhysicsSpec};
use crate::scene::valid::Links;
use crate::world::{Episodic, Outcome, WorldError, WorldState};
use rand::RngExt;
use rapier2d::math::{Real, Rotation, Vector};
use rapier2d::prelude::RigidBodyHandle;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// A state of a physics world (its copy 0): every body's pose and
/// velocity and every joint's coordinate, and the snapshot of the Rapier
/// sets from which a command continues exactly.
///
/// Two states are equal when their poses, velocities and joint
/// coordinates are equal bit for bit. A state read back from a file has
/// no snapshot: it can be compared, not executed from.
#[derive(Clone, Serialize, Deserialize)]
pub struct PhysicsState {
    /// Per body of the scene, in its order: `[x, y, angle]` (m, rad).
    pub poses: Vec<[f64; 3]>,
    /// Per body: `[vx, vy, angular velocity]` (m/s, rad/s).
    pub velocities: Vec<[f64; 3]>,
    /// Per joint of the scene, in its order: `[coordinate, rate]` (a
    /// hinge's angle from its start pose in rad and rad/s, a slider's
    /// position in m and m/s).
    pub joints: Vec<[f64; 2]>,
    /// The named start context this state is the start of (`None` for a
    /// drawn start or the state a command left): commands from it may be
    /// looked up by `(context, command)`.
    pub context: Option<usize>,
    #[serde(skip)]
    snapshot: Option<Arc<Sets>>,
    /// Whether [`Episodic::draw_start`] drew it (a start, not where a
    /// command left the world): a noisy world offsets its starts.
    #[serde(skip)]
    start: bool,
}

impl PhysicsState {
    /// The state's numbers as little-endian bytes (poses, velocities,
    /// joints, in order): equal bytes, equal states.
    pub fn to_bytes(&self) -> Vec<u8> {
        let p = self.poses.iter().chain(&self.velocities).flatten();
        let j = self.joints.iter().flatten();
        p.chain(j).flat_map(|v| v.to_le_bytes()).collect()
    }

    /// Whether the state holds the snapshot commands continue from.
    pub fn is_executable(&self) -> bool {
        self.snapshot.is_some()
    }
}

impl PartialEq for PhysicsState {
    fn eq(&self, other: &Self) -> bool {
        self.context == other.context && self.to_bytes() == other.to_bytes()
    }
}

impl std::fmt::Debug for PhysicsState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("PhysicsState")
            .field("poses", &self.poses)
            .field("velocities", &self.velocities)
            .field("joints", &self.joints)
            .field("context", &self.context)
            .finish()
    }
}

/// How a start context of a world starts.
#[derive(Clone)]
pub(super) enum ContextStart {
    /// The scene's start (a scene without contexts).
    Pristine,
    /// A named state: the pristine sets with the context's bodies and
    /// joints set.
    Named(Arc<Sets>),
    /// A drawn state: the bodies and joints to set, ranges drawn at each
    /// start.
    Sampled(Placement),
}

/// What a context sets: bodies (by handle), joints (by index), and
/// whether the joints must be set at all (some joint is listed, or a
/// listed body carries a joint).
#[derive(Clone)]
pub(super) struct Placement {
    bodies: Vec<(RigidBodyHandle, BodyStart)>,
    joints: Vec<(usize, JointStart)>,
    carry: bool,
}

/// Sets the start of the bodies then the joints of `starts` in `sets`,
/// drawing each body range's x then y, then each joint range's coordinate,
/// with `rng` (`None`: the ranges' first ends).
fn place(
    sets: &mut Sets,
    starts: &Placement,
    infos: &[JointInfo],
    geometry: &JointGeometry,
    rng: Option<&mut SessionRng>,
) {
    let mut rng = rng;
    // the joints' coordinates before the bodies move: the unlisted ones keep them
    let mut target: Vec<(f64, f64)> = if starts.carry {
        infos.iter().map(|j| j.coordinate(&sets.bodies)).collect()
    } else {
        Vec::new()
    };
    for (h, s) in &starts.bodies {
        let b = &mut sets.bodies[*h];
        if let Some(p) = s.position {
            let (x, y) = match (s.to, rng.as_deref_mut()) {
                (Some(to), Some(r)) => (
                    r.random_range(p.0.min(to.0)..=p.0.max(to.0)),
                    r.random_range(p.1.min(to.1)..=p.1.max(to.1)),
                ),
                _ => p,
            };
            b.set_translation(Vector::new(x as Real, y as Real), true);
        }
        if let Some(a) = s.angle {
            b.set_rotation(Rotation::new(a as Real), true);
        }
        let v = s.velocity.unwrap_or((0.0, 0.0));
        b.set_linvel(Vector::new(v.0 as Real, v.1 as Real), true);
        b.set_angvel(s.angular_velocity.unwrap_or(0.0) as Real, true);
    }
    if !starts.carry {
        return;
    }
    for (k, s) in &starts.joints {
        if let Some(a) = s.angle {
            target[*k].0 = match (s.to, rng.as_deref_mut()) {
                (Some(to), Some(r)) => r.random_range(a.min(to)..=a.max(to)),
                _ => a,
            };
        }
        if let Some(w) = s.velocity {
            target[*k].1 = w;
        }
    }
    let listed: Vec<usize> = starts.joints.iter().map(|(k, _)| *k).collect();
    set_joints(sets, infos, geometry, &target, &listed);
}

impl PhysicsWorld {
    /// The start contexts of `spec` (its names resolved in `links`), on
    /// `copy` (copy 0) of `pristine`, and the geometry of its joints they
    /// set.
    pub(super) fn context_starts(
        spec: &PhysicsSpec,
        links: &Links,
        copy: &Replica,
        pristine: &Sets,
    ) -> (Vec<ContextStart>, JointGeometry) {
        let anchors = spec
            .joints
            .iter()
            .map(|j| (v2(j.parent_anchor), v2(j.child_anchor)))
            .collect();
        let geometry = JointGeometry::of(&copy.joints, anchors, pristine);
        if spec.contexts.is_empty() {
            return (vec![ContextStart::Pristine], geometry);
        }
        let starts = spec
            .contexts
            .iter()
            .zip(&links.contexts)
            .map(|(c, (body_index, joint_index))| {
                let bodies: Vec<(RigidBodyHandle, BodyStart)> = c
                    .bodies
                    .iter()
                    .zip(body_index)
                    .map(|(b, &i)| (copy.handles[i], b.clone()))
                    .collect();
                let joints: Vec<(usize, JointStart)> = c
                    .joints
                    .iter()
                    .zip(joint_index)
                    .map(|(s, &k)| (k, s.clone()))
                    .collect();
                let carry = !joints.is_empty()
                    || spec
                        .joints
                        .iter()
                        .any(|j| c.bodies.iter().any(|b| b.body == j.parent));
                let starts = Placement {
                    bodies,
                    joints,
                    carry,
                };
                if c.is_sampled() {
                    ContextStart::Sampled(starts)
                } else {
                    let mut sets = pristine.clone();
                    place(&mut sets, &starts, &copy.joints, &geometry, None);
                    ContextStart::Named(Arc::new(sets))
                }
            })
            .collect();
        (starts, geometry)
    }

    /// The state of copy 0 in `sets`, holding `snapshot` (those sets).
    pub(super) fn state_of(&self, snapshot: Arc<Sets>, context: Option<usize>) -> PhysicsState {
        let f = self.frame_of(&snapshot, 0.0);
        PhysicsState {
            poses: f
                .poses
                .iter()
                .map(|p| [p.position[0], p.position[1], p.angle])
                .collect(),
            velocities: f.velocities,
            joints: f
                .joint_angles
                .iter()
                .zip(&f.joint_velocities)
                .map(|(&a, &w)| [a, w])
                .collect(),
            context,
            snapshot: Some(snapshot),
            start: false,
        }
    }

    /// The snapshot of `state`, if it is a state of this world holding one.
    fn snapshot<'a>(&'a self, state: &'a WorldState) -> Option<&'a Arc<Sets>> {
        match state {
            WorldState::Physics(PhysicsState {
                snapshot: Some(s), ..
            }) if s.bodies.len() == self.pristine.bodies.len() => Some(s),
            _ => None,
        }
    }

    /// Runs `f` with `from` as the world's start (no mirror twin: the
    /// symmetry holds about the scene's start only), then puts the
    /// scene's start and symmetry back: what [`trace`](Self::trace),
    /// [`inspect`](Self::inspect) and the like do from the scene's start,
    /// `f` does from `from`.
    ///
    /// ```
    /// use e3d::world::Episodic;
    /// use e3d::{Scene, World};
    /// let scene = Scene::load("scenes/puck_contexts.ron").unwrap();
    /// let mut world = scene.physics_world().unwrap();
    /// let c = scene.command_space().parse("EEEEEEE").unwrap();
    /// let mut rng = <e3d::rng::SessionRng as rand::SeedableRng>::seed_from_u64(0);
    /// let from = world.draw_start(1, &mut rng).unwrap();
    /// let trace = world.from_start(&from, |w| w.trace(&c)).unwrap().unwrap();
    /// let (o, _) = world.execute_from(&from, &c).unwrap();
    /// assert_eq!(trace.outcome, o);
    /// ```
    pub fn from_start<R>(
        &mut self,
        from: &WorldState,
        f: impl FnOnce(&mut Self) -> R,
    ) -> Result<R, WorldError> {
        let snapshot = match (self.snapshot(from), from) {
            (Some(s), _) => s.clone(),
            (None, WorldState::Physics(_)) => return Err(WorldError::Other(
                "this physics state has no snapshot of this world (read back from a file, or another scene's): it cannot be continued exactly".into(),
            )),
            (None, other) => return Err(WorldError::Other(format!(
                "scene `{}` is a physics world; it cannot start from {other:?}",
                self.scene
            ))),
        };
        // a run restores `pristine` first: put the state's sets there, and
        // keep no prefix state of the scene's start (see `prefix`)
        let saved = std::mem::replace(&mut self.pristine, Sets::clone(&snapshot));
        let prefixes = std::mem::take(&mut self.prefixes);
        let mirror = self.mirror.take();
        // the start offsets of a noisy world apply to starts only
        let start = matches!(from, WorldState::Physics(s) if s.start);
        if let Some(n) = &mut self.noise {
            n.offsets = start;
        }
        let r = f(self);
        if let Some(n) = &mut self.noise {
            n.offsets = true;
        }
        self.pristine = saved;
        self.prefixes = prefixes;
        self.mirror = mirror;
        Ok(r)
    }
}

impl Episodic for PhysicsWorld {
    fn num_contexts(&self) -> usize {
        self.contexts.len()
    }

    /// The context's start state: a named context's is fixed, a sampled
    /// one draws two floats (x, then y) per ranged body, then one per
    /// ranged joint. A noisy world offsets the starts of a command from it
    /// (not of one from a state a command left).
    fn draw_start(&self, context: usize, rng: &mut SessionRng) -> Result<WorldState, WorldError> {
        let start = self.contexts.get(context).ok_or_else(|| {
            WorldError::Other(format!(
                "context {context}: scene `{}` has {} start contexts",
                self.scene,
                self.contexts.len()
            ))
        })?;
        let mut state = match start {
            ContextStart::Pristine => self.state_of(Arc::new(self.pristine.clone()), Some(0)),
            ContextStart::Named(sets) => self.state_of(sets.clone(), Some(context)),
            ContextStart::Sampled(starts) => {
                let mut sets = self.pristine.clone();
                let infos = &self.copies[0].joints;
                place(&mut sets, starts, infos, &self.joint_geometry, Some(rng));
                self.state_of(Arc::new(sets), None)
            }
        };
        state.start = true;
        Ok(WorldState::Physics(state))
    }

    /// The effect's bin of the state (the effect a command ending there has).
    fn bin_state(&self, state: &WorldState) -> Result<usize, WorldError> {
        let s = self.snapshot(state).ok_or_else(|| {
            WorldError::Other(format!(
                "scene `{}`: a state of this physics world, with its snapshot, found {state:?}",
                self.scene
            ))
        })?;
        Ok(self.located_in(s, 0).1)
    }

    /// Continues exactly from the state's snapshot of every Rapier set, on
    /// copy 0 (no mirror twin: the symmetry holds about the scene's start
    /// only).
    fn execute_from(
        &mut self,
        from: &WorldState,
        command: &Command,
    ) -> Result<(Outcome, WorldState), WorldError> {
        let outcome =
            self.from_start(from, |w| w.run_one(Cmd::Symbols(command), true, |_| {}))??;
        let end = self.state_of(Arc::new(self.sets.clone()), None);
        Ok((outcome, WorldState::Physics(end)))
    }
}
