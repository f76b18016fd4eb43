//! The outcome table: each command of a deterministic world executed once.

use super::{Outcome, World, WorldError};
use crate::command::{Command, CommandSpace};
use rayon::prelude::*;

/// The largest command space an [`OutcomeTable`] will enumerate.
pub const MAX_TABLE_COMMANDS: u64 = 1 << 22;

/// Every command of a deterministic world, executed once, its outcome kept.
///
/// A table is itself a [`World`]: executing a command is one look-up, with
/// the same outcome, bit for bit, as the world it was built from. Sessions
/// and sweeps share one table across threads (it is `Sync`).
///
/// ```
/// use e3d::{OutcomeTable, Scene, World};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let table = OutcomeTable::build(&mut scene.build()).unwrap();
/// assert_eq!(table.len(), 16384);
/// // exactly 9 commands end in the rewarded corner
/// assert_eq!(table.outcomes().filter(|o| o.reward > 0.0).count(), 9);
/// ```
#[derive(Debug, Clone)]
pub struct OutcomeTable {
    space: CommandSpace,
    num_effects: usize,
    outcomes: Vec<Outcome>,
}

impl OutcomeTable {
    /// Executes every command of `world` in index order.
    pub fn build(world: &mut dyn World) -> Result<OutcomeTable, WorldError> {
        let space = world.command_space().clone();
        let n = Self::check_size(&space)?;
        let mut outcomes = Vec::with_capacity(n as usize);
        let mut c = space.first();
        for i in 0..n {
            space.write_command_at(i, &mut c);
            outcomes.push(world.execute(&c)?);
        }
        Ok(OutcomeTable {
            num_effects: world.num_effects(),
            space,
            outcomes,
        })
    }

    /// Executes every command in parallel (rayon), one world per worker made
    /// by `make_world`. The table is identical to [`build`](Self::build)'s.
    pub fn build_parallel<W, F>(make_world: F) -> Result<OutcomeTable, WorldError>
    where
        W: World,
        F: Fn() -> W + Sync,
    {
        let probe = make_world();
        let space = probe.command_space().clone();
        let num_effects = probe.num_effects();
        drop(probe);
        let n = Self::check_size(&space)?;
        let chunk = 64u64;
        let chunks: Vec<Vec<Outcome>> = (0..n.div_ceil(chunk))
            .into_par_iter()
            .map_init(
                || (make_world(), space.first()),
                |(world, c), k| {
                    (k * chunk..((k + 1) * chunk).min(n))
                        .map(|i| {
                            space.write_command_at(i, c);
                            world.execute(c)
                        })
                        .collect::<Result<Vec<_>, _>>()
                },
            )
            .collect::<Result<_, _>>()?;
        Ok(OutcomeTable {
            space,
            num_effects,
            outcomes: chunks.into_iter().flatten().collect(),
        })
    }

    fn check_size(space: &CommandSpace) -> Result<u64, WorldError> {
        match space.num_commands() {
            Some(n) if n <= MAX_TABLE_COMMANDS => Ok(n),
            _ => Err(WorldError::Other(format!(
                "the command space is too large for an outcome table (more than {MAX_TABLE_COMMANDS} commands)"
            ))),
        }
    }

    /// The number of commands.
    pub fn len(&self) -> usize {
        self.outcomes.len()
    }

    /// Whether the table is empty (never, for a valid space).
    pub fn is_empty(&self) -> bool {
        self.outcomes.is_empty()
    }

    /// The outcome of the command with index `i` (see
    /// [`CommandSpace::index_of`]).
    pub fn get(&self, i: u64) -> &Outcome {
        &self.outcomes[i as usize]
    }

    /// Every outcome, in command index order.
    pub fn outcomes(&self) -> impl Iterator<Item = &Outcome> + '_ {
        self.outcomes.iter()
    }

    /// How many commands end in each effect.
    pub fn effect_counts(&self) -> Vec<u64> {
        let mut counts = vec![0u64; self.num_effects];
        for o in &self.outcomes {
            counts[o.effect] += 1;
        }
        counts
    }
}

impl World for OutcomeTable {
    fn command_space(&self) -> &CommandSpace {
        &self.space
    }

    fn num_effects(&self) -> usize {
        self.num_effects
    }

    #[inline]
    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        Ok(*self.lookup(command))
    }
}

impl OutcomeTable {
    /// The outcome of `command`, without `&mut`.
    #[inline]
    pub fn lookup(&self, command: &Command) -> &Outcome {
        &self.outcomes[self.space.index_of(command) as usize]
    }
}

/// A shared table is a world too (many sessions, one table).
impl World for &OutcomeTable {
    fn command_space(&self) -> &CommandSpace {
        &self.space
    }

    fn num_effects(&self) -> usize {
        self.num_effects
    }

    #[inline]
    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        Ok(*self.lookup(command))
    }
}
