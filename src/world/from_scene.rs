//! Building the world that executes a scene's commands: a [`GridWorld`]
//! for a grid scene, a [`PhysicsWorld`] for a physics scene. It lives with
//! the worlds (a scene describes; the worlds simulate), as an `impl` of
//! [`Scene`]. A [`Scene`] is valid by construction, so building cannot
//! fail.

use super::{GridWorld, PhysicsWorld, World};
use crate::scene::physics::PhysicsSpec;
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
        match &self.world {
            WorldSpec::Physics(spec) => Some(PhysicsScene { scene: self, spec }),
            WorldSpec::Grid(_) => None,
        }
    }

    /// Builds the world that executes this scene's commands.
    ///
    /// A continuous scene's world is its [`PhysicsWorld`], whose command
    /// space of symbols is a placeholder that refuses every command of
    /// symbols ([`WorldError::BadCommand`](crate::WorldError::BadCommand));
    /// its commands are values
    /// ([`PhysicsWorld::execute_values`](crate::world::PhysicsWorld::execute_values)).
    ///
    /// ```
    /// use e3d::Scene;
    /// let rooms = Scene::builtin("two_rooms").unwrap();
    /// let mut world = rooms.build();
    /// let c = rooms.command_space().parse("EEEEESS").unwrap();
    /// assert_eq!(world.execute(&c).unwrap().effect, 14);
    /// ```
    pub fn build(&self) -> Box<dyn World + Send> {
        match &self.world {
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

    /// Builds a world holding `copies` independent copies of the scene's
    /// non-fixed bodies and joints (fixed bodies are built once and
    /// shared), for [`PhysicsWorld::execute_batch`]: up to `copies`
    /// commands at once in one Rapier world, which amortises Rapier's
    /// per-step overhead over the copies ([`Scene::physics_world`] is one
    /// copy). Each copy has its own collision group: the copies touch the
    /// fixed bodies and, within a copy, the scene's own collision rules
    /// hold, but no two copies touch.
    ///
    /// Each copy's outcome is the one a single-copy world gives, bit for
    /// bit, on the shipped scenes (tested); a scene whose copies would
    /// differ ([`PhysicsSpec::copies_are_exact`]) should be executed one
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
