//! Building the world that executes a scene's commands: a [`GridWorld`]
//! for a grid scene, a [`PhysicsWorld`] for a physics scene. It lives with
//! the worlds (a scene describes; the worlds simulate), as an `impl` of
//! [`Scene`].

use super::{GridWorld, PhysicsWorld, World};
use crate::scene::{Scene, SceneError, WorldSpec};

impl Scene {
    /// The scene's Rapier world itself, for what only a physics world
    /// gives ([`PhysicsWorld::motion`](crate::world::PhysicsWorld::motion),
    /// [`trace`](crate::world::PhysicsWorld::trace),
    /// [`inspect`](crate::world::PhysicsWorld::inspect)); `None` for a grid
    /// scene.
    ///
    /// # Panics
    /// On a scene that [`validate`](Self::validate) refuses (one edited in
    /// code), with its message; [`try_physics_world`](Self::try_physics_world)
    /// returns the error instead.
    pub fn physics_world(&self) -> Option<PhysicsWorld> {
        self.try_physics_world().unwrap_or_else(|e| panic!("{e}"))
    }

    /// [`physics_world`](Self::physics_world), validated first: an invalid
    /// scene is an error, never a panic.
    ///
    /// ```
    /// use e3d::Scene;
    /// let arm = Scene::builtin("arm7").unwrap();
    /// assert!(arm.try_physics_world().unwrap().is_some());
    /// let grid = Scene::builtin("two_rooms").unwrap();
    /// assert!(grid.try_physics_world().unwrap().is_none());
    /// ```
    pub fn try_physics_world(&self) -> Result<Option<PhysicsWorld>, SceneError> {
        self.validate()?;
        if let Some(s) = self.with_template_expanded() {
            return s.try_physics_world();
        }
        Ok(match &self.world {
            WorldSpec::Physics(p) => Some(PhysicsWorld::from_scene(self, p)),
            WorldSpec::Grid(_) => None,
        })
    }

    /// Builds the world that executes this scene's commands.
    ///
    /// A convenience for scenes known to be valid (those of [`load`](Self::load),
    /// [`parse`](Self::parse), [`builtin`](Self::builtin), [`resolve`](Self::resolve)).
    ///
    /// # Panics
    /// On a scene that [`validate`](Self::validate) refuses (one edited in
    /// code: a NaN, a torque that breaks its symmetry, no slots), with the
    /// validation's message, and on a continuous scene (whose world is
    /// [`physics_world`](Self::physics_world)); [`try_build`](Self::try_build)
    /// returns the error instead.
    pub fn build(&self) -> Box<dyn World + Send> {
        self.try_build().unwrap_or_else(|e| panic!("{e}"))
    }

    /// Validates the scene ([`validate`](Self::validate)), then builds the
    /// world that executes its commands: an edited scene that cannot be
    /// simulated is an error, never a panic.
    ///
    /// ```
    /// use e3d::scene::{Action, CommandSpec, Scene, SceneErrorKind};
    ///
    /// let mut arm = Scene::builtin("arm7").unwrap();
    /// assert!(arm.try_build().is_ok());
    /// // arm7 declares `symmetry: FlipY`: a torque whose mirror image is
    /// // not in its slot breaks it (`build` would panic)
    /// if let CommandSpec::Slots(slots) = &mut arm.command {
    ///     slots[0].alphabet[2].action = Action::Torque { joint: "j1".into(), torque: 2.0 };
    /// }
    /// let err = arm.try_build().err().unwrap();
    /// assert!(matches!(err.kind(), SceneErrorKind::Invalid { field, .. } if field == "action"));
    /// assert!(err.to_string().starts_with("<scene arm7>: field `action`: expected symmetry FlipY"));
    /// ```
    pub fn try_build(&self) -> Result<Box<dyn World + Send>, SceneError> {
        self.validate()?;
        if let Some(s) = self.with_template_expanded() {
            return s.try_build();
        }
        self.require_symbols(
            "a world of symbols (`Scene::build`; `Scene::physics_world` runs continuous commands)",
        )?;
        Ok(match &self.world {
            WorldSpec::Grid(g) => Box::new(GridWorld::from_scene(self, g)),
            WorldSpec::Physics(p) => Box::new(PhysicsWorld::from_scene(self, p)),
        })
    }
}
