//! A scene's declared symmetry: a command whose mirror image has the
//! lower index is simulated as that image, and its outcome reflected.

use super::PhysicsWorld;
use crate::command::Command;
use crate::world::{Outcome, WorldError};

impl PhysicsWorld {
    /// The mirror image of `command` when the scene declares a
    /// [`Symmetry`](crate::scene::Symmetry) and that image has the lower index: the command this
    /// world simulates in its place, reflecting the outcome. `None` for the
    /// commands it simulates themselves (all of them without a symmetry).
    pub fn twin(&self, command: &Command) -> Option<Command> {
        let (_, maps) = self.mirror.as_ref()?;
        self.check(super::Cmd::Symbols(command)).ok()?;
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

    /// The result of `command` from the result of its twin `twin`: the
    /// outcome reflected, or the twin's failure, naming both commands.
    pub(super) fn mirrored_result(
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
}
