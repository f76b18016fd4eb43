//! Building the world of a [`Scene`] (valid by construction, so building
//! cannot fail): a [`GridWorld`] or a [`PhysicsWorld`].

use super::{ContinuousWorld, Episodic, GridWorld, Outcome, PhysicsWorld, World, WorldError};
use crate::command::ValueSpace;
use crate::scene::physics::{DrawKey, PhysicsSpec};
use crate::scene::{Scene, WorldSpec};

impl Scene {
    /// The scene's Rapier world itself, for what only a physics world
    /// gives ([`PhysicsWorld::motion`](crate::world::PhysicsWorld::motion),
    /// [`trace`](crate::world::PhysicsWorld::trace),
    /// [`inspect`](crate::world::PhysicsWorld::inspect),
    /// [`execute_values`](crate::world::PhysicsWorld::execute_values) for a
    /// continuous scene); `None` for a grid scene.
    ///
    /// ```
    /// use e3d::Scene;
    /// let arm = Scene::builtin("arm7").unwrap();
    /// assert!(arm.physics_world().is_some());
    /// let grid = Scene::builtin("two_rooms").unwrap();
    /// assert!(grid.physics_world().is_none());
    /// ```
    pub fn physics_world(&self) -> Option<PhysicsWorld> {
        self.as_physics().map(|p| p.world(1))
    }

    /// The scene as a physics scene, whose worlds of many copies can be
    /// built ([`PhysicsScene::world`]); `None` for a grid scene.
    pub fn as_physics(&self) -> Option<PhysicsScene<'_>> {
        match &self.spec().world {
            WorldSpec::Physics(spec) => Some(PhysicsScene { scene: self, spec }),
            WorldSpec::Grid(_) => None,
        }
    }

    /// The scene as a continuous scene (its slots take values): its physics
    /// and its value space; `None` exactly when
    /// [`is_continuous`](crate::scene::SceneSpec::is_continuous) is false.
    ///
    /// ```
    /// use e3d::Scene;
    /// use e3d::world::ContinuousWorld;
    /// let arm = Scene::builtin("arm7_continuous").unwrap();
    /// let c = arm.as_continuous().unwrap();
    /// assert_eq!(c.values().num_slots(), 7);
    /// assert_eq!(c.world(1).value_space().num_slots(), 7);
    /// assert!(Scene::builtin("arm7").unwrap().as_continuous().is_none());
    /// ```
    pub fn as_continuous(&self) -> Option<ContinuousScene<'_>> {
        Some(ContinuousScene {
            physics: self.as_physics()?,
            values: self.values()?,
        })
    }

    /// Builds the world that executes this scene's commands ([`World`]),
    /// also from its start contexts and given states ([`Episodic`]). A
    /// continuous scene's world refuses every command of symbols: its
    /// commands are values
    /// ([`PhysicsWorld::execute_values`](crate::world::PhysicsWorld::execute_values)).
    ///
    /// ```
    /// use e3d::Scene;
    /// let rooms = Scene::builtin("two_rooms").unwrap();
    /// let mut world = rooms.build();
    /// let c = rooms.command_space().parse("EEEEESS").unwrap();
    /// assert_eq!(world.execute(&c).unwrap().effect, 14);
    /// ```
    pub fn build(&self) -> Box<dyn Episodic + Send> {
        match &self.spec().world {
            WorldSpec::Grid(g) => Box::new(GridWorld::of(self, g)),
            WorldSpec::Physics(p) => Box::new(PhysicsWorld::of(self, p, 1)),
        }
    }
}

/// A [`Scene`] whose world is physics ([`Scene::as_physics`]).
#[derive(Debug, Clone, Copy)]
pub struct PhysicsScene<'a> {
    scene: &'a Scene,
    spec: &'a PhysicsSpec,
}

impl<'a> PhysicsScene<'a> {
    /// The scene.
    pub fn scene(&self) -> &'a Scene {
        self.scene
    }

    /// Its physics world's spec.
    pub fn spec(&self) -> &'a PhysicsSpec {
        self.spec
    }

    /// Builds a world holding `copies` copies of the scene's non-fixed
    /// bodies and joints (fixed bodies shared; no two copies touch), for
    /// [`PhysicsWorld::execute_batch`]: up to `copies` commands stepped
    /// together, Rapier's per-step overhead shared. Each copy gives a
    /// single-copy world's outcome, bit for bit, where
    /// [`PhysicsSpec::copies_are_exact`]; other scenes should run one
    /// command per world.
    ///
    /// # Panics
    /// If `copies` is 0 or above [`MAX_COPIES`](crate::world::MAX_COPIES).
    ///
    /// ```
    /// use e3d::Scene;
    /// let arm = Scene::builtin("arm7").unwrap();
    /// let mut world = arm.as_physics().unwrap().world(4);
    /// let c = arm.command_space().first();
    /// let mut out = Vec::new();
    /// world.execute_batch(&[c.clone(), c.clone()], &mut out);
    /// assert_eq!(out[0].as_ref().unwrap(), out[1].as_ref().unwrap());
    /// ```
    pub fn world(&self, copies: usize) -> PhysicsWorld {
        PhysicsWorld::of(self.scene, self.spec, copies)
    }
}

/// A [`Scene`] whose slots take values ([`Scene::as_continuous`]): a
/// physics scene and its value space, together.
#[derive(Debug, Clone, Copy)]
pub struct ContinuousScene<'a> {
    physics: PhysicsScene<'a>,
    values: &'a ValueSpace,
}

impl<'a> ContinuousScene<'a> {
    /// The scene.
    pub fn scene(&self) -> &'a Scene {
        self.physics.scene
    }

    /// The scene as a physics scene.
    pub fn physics(&self) -> PhysicsScene<'a> {
        self.physics
    }

    /// The ranges of its slots.
    pub fn values(&self) -> &'a ValueSpace {
        self.values
    }

    /// Builds a world of `copies` copies ([`PhysicsScene::world`]) that
    /// executes values.
    ///
    /// # Panics
    /// If `copies` is 0 or above [`MAX_COPIES`](crate::world::MAX_COPIES).
    pub fn world(&self, copies: usize) -> ValueWorld {
        ValueWorld {
            world: self.physics.world(copies),
            values: self.values.clone(),
        }
    }
}

/// The physics world of a continuous scene, known to take values: what
/// [`run_value_session`](crate::session::run_value_session) steps on (a
/// [`ContinuousWorld`]). Made by [`ContinuousScene::world`].
#[derive(Debug)]
pub struct ValueWorld {
    world: PhysicsWorld,
    values: ValueSpace,
}

impl ValueWorld {
    /// The Rapier world itself (motions, traces, batches).
    pub fn physics(&self) -> &PhysicsWorld {
        &self.world
    }
}

impl ContinuousWorld for ValueWorld {
    fn value_space(&self) -> &ValueSpace {
        &self.values
    }
    fn num_effects(&self) -> usize {
        World::num_effects(&self.world)
    }
    fn execute_values(&mut self, values: &[f64]) -> Result<Outcome, WorldError> {
        self.world.execute_values(values)
    }
    fn set_draw_keys(&mut self, keys: &[DrawKey]) {
        World::set_draw_keys(&mut self.world, keys)
    }
    fn is_deterministic(&self) -> bool {
        World::is_deterministic(&self.world)
    }
    fn execute_values_batch(
        &mut self,
        commands: &[Vec<f64>],
        out: &mut Vec<Result<Outcome, WorldError>>,
    ) {
        self.world.execute_values_batch(commands, out)
    }
}
