//! The outcomes of commands from named start contexts, kept by
//! `(context, command)`: one [`OutcomeMemo`] per context (states drawn
//! from ranges, and the states commands leave, run live).

use super::{Episodic, OutcomeMemo, World, WorldError, WorldState};
use crate::command::{Command, CommandSpace};
use crate::world::Outcome;

/// `world`, the outcomes of its commands from named start contexts kept in
/// `memos` (one per context, in context order, shared by every session of
/// a run): [`Episodic::execute_outcome_from`] looks them up; every other call
/// goes to the world. Outcomes are the world's, bit for bit.
///
/// ```
/// use e3d::world::{ContextMemoized, Episodic, OutcomeMemo};
/// use e3d::{Scene, World};
/// let scene = Scene::load("scenes/puck_contexts.ron").unwrap();
/// let memos: Vec<OutcomeMemo> = (0..2)
///     .map(|_| OutcomeMemo::new(&scene.command_space(), scene.num_effects(), 1000).unwrap())
///     .collect();
/// let mut world = ContextMemoized::new(scene.build(), &memos);
/// let c = world.command_space().parse("WWWWWWW").unwrap();
/// let mut rng = <e3d::rng::SessionRng as rand::SeedableRng>::seed_from_u64(0);
/// let b = world.draw_start(1, &mut rng).unwrap();
/// let first = world.execute_outcome_from(&b, &c).unwrap(); // simulated
/// assert_eq!(world.execute_outcome_from(&b, &c).unwrap(), first); // looked up
/// assert_eq!((memos[1].len(), memos[1].hits(), memos[0].len()), (1, 1, 0));
/// ```
pub struct ContextMemoized<'m, W> {
    world: W,
    memos: &'m [OutcomeMemo],
}

impl<'m, W: World> ContextMemoized<'m, W> {
    /// `world`, its outcomes from named contexts kept in `memos` (one per
    /// context of the world's command space: the caller's promise).
    pub fn new(world: W, memos: &'m [OutcomeMemo]) -> Self {
        ContextMemoized { world, memos }
    }
}

impl<W: World> World for ContextMemoized<'_, W> {
    super::forward!(world self => self.world);
}

impl<W: Episodic> Episodic for ContextMemoized<'_, W> {
    super::forward!(episodic self => self.world);

    /// From a named context's start, the memo's outcome, or the world's
    /// (then kept); from any other state, or on a world that is not
    /// deterministic (a `noise` section), the world's.
    fn execute_outcome_from(
        &mut self,
        from: &WorldState,
        command: &Command,
    ) -> Result<Outcome, WorldError> {
        let space = self.world.command_space();
        // a noisy world's commands draw anew: never kept
        let kept = from.context().filter(|_| self.world.is_deterministic());
        let memo = kept.and_then(|c| self.memos.get(c));
        let (Some(memo), true) = (memo, super::check_command(space, command).is_ok()) else {
            return self.world.execute_outcome_from(from, command);
        };
        let i = space.index_of(command);
        if let Some(o) = memo.get(i) {
            return Ok(o);
        }
        let o = self.world.execute_outcome_from(from, command)?;
        memo.insert(i, o);
        Ok(o)
    }
}
