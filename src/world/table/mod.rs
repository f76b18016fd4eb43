//! The outcome table: each command of a deterministic world executed once.

use super::{Outcome, World, WorldError};
use crate::command::{Command, CommandSpace};
use crate::effect::Target;
use crate::scene::physics::noise_refusal;
use crate::scene::{Scene, WorldSpec};
use crate::world::Control;
use crate::world::PhysicsWorld;
use rayon::prelude::*;
use std::io;
use std::path::{Path, PathBuf};

mod contexts;
mod file;

pub use contexts::{seed0_start, start_contexts, ContextTables, StartContext, TabledContexts};
pub use file::CachedOutcomes;

/// The largest command space an [`OutcomeTable`] will enumerate.
pub const MAX_TABLE_COMMANDS: u64 = 1 << 22;

/// The copies per Rapier world [`OutcomeTable::build_scene`] uses for
/// physics scenes (measured on puck_rooms: see docs/benchmarks.md).
pub const TABLE_COPIES: usize = 32;

/// The copies per Rapier world a table of `scene` steps together:
/// [`TABLE_COPIES`] where the scene's copies are exact
/// ([`PhysicsSpec::copies_are_exact`](crate::scene::physics::PhysicsSpec::copies_are_exact)),
/// else 1. Batches run the same way (`e3d scene exec`, Python's
/// `execute_batch`), and the cost estimates of both are calibrated on it.
///
/// ```
/// use e3d::{world::table_copies, Scene};
/// assert_eq!(table_copies(&Scene::builtin("puck_rooms").unwrap()), 32);
/// assert_eq!(table_copies(&Scene::builtin("arm7").unwrap()), 1); // its copies are not exact
/// assert_eq!(table_copies(&Scene::builtin("two_rooms").unwrap()), 1); // a grid
/// ```
pub fn table_copies(scene: &Scene) -> usize {
    match &scene.spec().world {
        WorldSpec::Physics(p) if p.copies_are_exact() => TABLE_COPIES,
        _ => 1,
    }
}

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
    /// The place value of each slot in the mixed-radix index, so that a
    /// look-up is independent multiply-adds rather than a dependent chain.
    places: Places,
}

/// The place values and alphabet sizes of a command space's slots (see
/// [`places`]).
#[derive(Debug, Clone)]
struct Places {
    /// One place value per slot.
    each: Vec<u64>,
    /// One alphabet size per slot.
    sizes: Vec<u64>,
    /// The same in fixed arrays when there are at most [`SHORT`] slots
    /// (places 0 and sizes 1 beyond them): a look-up then unrolls, with no
    /// bounds checks.
    short: Option<([u64; SHORT], [u64; SHORT])>,
}

/// The most slots of the unrolled look-up.
const SHORT: usize = 8;

impl Places {
    /// The index of the command `symbols` (see [`CommandSpace::index_of`]),
    /// or `None` if it does not fit the space (a wrong length, or a symbol
    /// outside its slot's alphabet).
    #[inline(always)]
    fn index(&self, symbols: &[u8]) -> Option<u64> {
        if symbols.len() != self.each.len() {
            return None;
        }
        let (mut i, mut fits) = (0u64, true);
        match &self.short {
            // the same as the zip below, unrolled
            Some((p, k)) => {
                for j in 0..SHORT {
                    if j == symbols.len() {
                        break;
                    }
                    let s = symbols[j] as u64;
                    fits &= s < k[j];
                    i += s * p[j];
                }
            }
            _ => {
                for ((&s, &p), &k) in symbols.iter().zip(&self.each).zip(&self.sizes) {
                    fits &= (s as u64) < k;
                    i += s as u64 * p;
                }
            }
        }
        fits.then_some(i)
    }
}

/// For each of the `n` commands of `space`, the index of its
/// [`twin`](PhysicsWorld::twin) in `world`, if it has one.
fn twin_indices(world: &PhysicsWorld, space: &CommandSpace, n: u64) -> Vec<Option<u64>> {
    let mut c = space.first();
    (0..n)
        .map(|i| {
            space.write_command_at(i, &mut c);
            world.twin(&c).map(|t| space.index_of(&t))
        })
        .collect()
}

/// The place value of each slot in [`CommandSpace::index_of`].
fn places(space: &CommandSpace) -> Places {
    let mut each: Vec<u64> = space
        .sizes()
        .rev()
        .scan(1u64, |acc, k| {
            let place = *acc;
            *acc = acc.saturating_mul(k as u64);
            Some(place)
        })
        .collect();
    each.reverse();
    let sizes: Vec<u64> = space.sizes().map(|k| k as u64).collect();
    let short = (each.len() <= SHORT).then(|| {
        let (mut p, mut k) = ([0u64; SHORT], [1u64; SHORT]);
        p[..each.len()].copy_from_slice(&each);
        k[..sizes.len()].copy_from_slice(&sizes);
        (p, k)
    });
    Places { each, sizes, short }
}

/// The outcomes of the commands `index(0..n)` of `space`, in order,
/// computed in parallel (rayon) in chunks of 64, each worker running `run`
/// (one result per command of a batch) on its own world made by `make`;
/// `control` is told of each chunk done and asked before each whether to
/// stop.
fn run_chunks<W, M, R>(
    space: &CommandSpace,
    n: u64,
    index: impl Fn(u64) -> u64 + Sync,
    make: M,
    run: R,
    control: &Control<'_>,
) -> Result<Vec<Outcome>, WorldError>
where
    M: Fn() -> W + Sync,
    R: Fn(&mut W, &[Command], &mut Vec<Result<Outcome, WorldError>>) + Sync,
{
    let chunk = 64u64;
    let chunks: Vec<Vec<Outcome>> = (0..n.div_ceil(chunk))
        .into_par_iter()
        .map_init(
            || (make(), Vec::new(), Vec::new()),
            |(world, cmds, out), k| {
                control.check()?;
                let range = k * chunk..((k + 1) * chunk).min(n);
                let done = range.end - range.start;
                cmds.resize_with(done as usize, || space.first());
                for (c, i) in cmds.iter_mut().zip(range) {
                    space.write_command_at(index(i), c);
                }
                out.clear();
                run(world, cmds, out);
                (control.progress)(done);
                out.drain(..).collect::<Result<Vec<_>, _>>()
            },
        )
        .collect::<Result<_, _>>()?;
    Ok(chunks.into_iter().flatten().collect())
}

/// Runs a batch of commands on a world, one result per command.
fn batch<W: World>(
    world: &mut W,
    commands: &[Command],
    out: &mut Vec<Result<Outcome, WorldError>>,
) {
    world.execute_batch(commands, out)
}

impl OutcomeTable {
    /// The table of `outcomes`, one per command of `space` in index order.
    fn new(space: CommandSpace, num_effects: usize, outcomes: Vec<Outcome>) -> OutcomeTable {
        OutcomeTable {
            places: places(&space),
            space,
            num_effects,
            outcomes,
        }
    }

    /// Executes every command of `world` in index order.
    pub fn build(world: &mut dyn World) -> Result<OutcomeTable, WorldError> {
        if !world.is_deterministic() {
            return Err(WorldError::Other(
                "this world is not deterministic (a scene's `noise` section): an outcome table cannot stand for its executions".into(),
            ));
        }
        let space = world.command_space().clone();
        let n = Self::check_size(&space)?;
        let mut c = space.first();
        let outcomes = (0..n)
            .map(|i| {
                space.write_command_at(i, &mut c);
                world.execute(&c)
            })
            .collect::<Result<_, _>>()?;
        Ok(Self::new(space, world.num_effects(), outcomes))
    }

    /// Executes every command in parallel (rayon), one world per worker made
    /// by `make_world`. The table is identical to [`build`](Self::build)'s.
    pub fn build_parallel<W, F>(make_world: F) -> Result<OutcomeTable, WorldError>
    where
        W: World,
        F: Fn() -> W + Sync,
    {
        Self::build_parallel_with(make_world, &Control::default())
    }

    /// [`build_parallel`](Self::build_parallel), telling `control` of the
    /// commands of each chunk done.
    fn build_parallel_with<W, F>(
        make_world: F,
        control: &Control<'_>,
    ) -> Result<OutcomeTable, WorldError>
    where
        W: World,
        F: Fn() -> W + Sync,
    {
        let probe = make_world();
        let space = probe.command_space().clone();
        let num_effects = probe.num_effects();
        drop(probe);
        let n = Self::check_size(&space)?;
        let outcomes = run_chunks(&space, n, |i| i, make_world, batch, control)?;
        Ok(Self::new(space, num_effects, outcomes))
    }

    /// The table of a scene, computed in parallel (rayon), [`TABLE_COPIES`]
    /// commands at once per Rapier world where the scene's copies are exact
    /// ([`PhysicsSpec::copies_are_exact`](crate::scene::physics::PhysicsSpec::copies_are_exact)),
    /// one command of each mirror-image pair simulated under a symmetry
    /// ([`PhysicsWorld::twin`]). The table is identical to
    /// [`build`](Self::build)'s.
    pub fn build_scene(scene: &Scene) -> Result<OutcomeTable, WorldError> {
        Self::build_scene_with(scene, &Control::default())
    }

    /// [`build_scene`](Self::build_scene) under `control`: told from the
    /// workers of the commands of each chunk simulated (they add up to
    /// [`simulated_commands`](Self::simulated_commands)), asked before each
    /// chunk whether to stop (then the error is [`WorldError::Stopped`]).
    /// The table is the same, bit for bit.
    pub fn build_scene_with(
        scene: &Scene,
        control: &Control<'_>,
    ) -> Result<OutcomeTable, WorldError> {
        Self::complete_with(scene, &[], control)
    }

    /// [`build_scene_with`](Self::build_scene_with) from the outcomes
    /// `known` (command index and outcome: a partial table file),
    /// simulating only the commands they lack. The table is the same, bit
    /// for bit, when `known` holds the world's own outcomes.
    pub fn complete_with(
        scene: &Scene,
        known: &[(u64, Outcome)],
        control: &Control<'_>,
    ) -> Result<OutcomeTable, WorldError> {
        let WorldSpec::Physics(spec) = &scene.spec().world else {
            // a grid's table costs microseconds
            return Self::build_parallel_with(|| scene.build(), control);
        };
        if spec.active_noise().is_some() {
            let refusal = noise_refusal(&scene.spec().name, "an outcome table");
            return Err(WorldError::Other(refusal));
        }
        let space = scene.command_space();
        let n = Self::check_size(&space)?;
        let mut outcomes: Vec<Option<Outcome>> = vec![None; n as usize];
        for &(i, o) in known.iter().filter(|e| e.0 < n) {
            outcomes[i as usize] = Some(o);
        }
        let probe = PhysicsWorld::of(scene, spec, 1);
        let twins = match spec.symmetry {
            Some(_) => twin_indices(&probe, &space, n),
            None => Vec::new(),
        };
        let twin = |i: u64| twins.get(i as usize).copied().flatten();
        let missing: Vec<u64> = (0..n)
            .filter(|&i| outcomes[i as usize].is_none() && twin(i).is_none())
            .collect();
        let copies = table_copies(scene);
        let make = || PhysicsWorld::of(scene, spec, copies);
        let index = |k: u64| missing[k as usize];
        let results = run_chunks(&space, missing.len() as u64, index, make, batch, control)?;
        for (&i, o) in missing.iter().zip(results) {
            outcomes[i as usize] = Some(o);
        }
        // a twin's index is below its command's: filled in index order
        for i in 0..n {
            if let (None, Some(t)) = (outcomes[i as usize], twin(i)) {
                let o = outcomes[t as usize].expect("a twin is known or simulated");
                outcomes[i as usize] = Some(probe.reflect_outcome(o));
            }
        }
        let outcomes = outcomes.into_iter().map(|o| o.expect("every command"));
        Ok(Self::new(space, scene.num_effects(), outcomes.collect()))
    }

    /// How many commands [`build_scene`](Self::build_scene) simulates for
    /// `scene`: every command, or one of each mirror-image pair for a
    /// physics scene with a [`Symmetry`](crate::scene::Symmetry) (arm7:
    /// 1094 of 2187). `None` for a space too large for a table.
    pub fn simulated_commands(scene: &Scene) -> Option<u64> {
        let space = scene.command_space();
        let n = Self::check_size(&space).ok()?;
        match &scene.spec().world {
            WorldSpec::Physics(p) if p.symmetry.is_some() => {
                let probe = PhysicsWorld::of(scene, p, 1);
                let twins = twin_indices(&probe, &space, n);
                Some(twins.iter().filter(|t| t.is_none()).count() as u64)
            }
            _ => Some(n),
        }
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

    /// The number of effects some command reaches.
    pub fn reachable_effects(&self) -> usize {
        self.effect_counts().iter().filter(|&&c| c > 0).count()
    }

    /// The effects some command reaches, in increasing order (its length
    /// is [`reachable_effects`](Self::reachable_effects)).
    pub fn reachable(&self) -> Vec<usize> {
        let counts = self.effect_counts();
        (0..counts.len()).filter(|&e| counts[e] > 0).collect()
    }

    /// The target `p*` uniform over the reachable effects only
    /// ([`Target::Weights`] of 1 on each effect some command reaches, 0 on
    /// the others), where `Target::Uniform` spreads it over every effect
    /// (docs/algorithms.md, "E3D").
    ///
    /// ```
    /// use e3d::{OutcomeTable, Scene, Target};
    /// let scene = Scene::builtin("four_rooms").unwrap();
    /// let table = OutcomeTable::build(&mut *scene.build()).unwrap();
    /// let target = table.reachable_target();
    /// let p = target.probs(36).unwrap();
    /// assert_eq!(p.iter().filter(|&&v| v > 0.0).count(), 13);
    /// assert!(p.iter().all(|&v| v == 0.0 || (v - 1.0 / 13.0).abs() < 1e-15));
    /// ```
    pub fn reachable_target(&self) -> Target {
        let weights = self
            .effect_counts()
            .iter()
            .map(|&c| if c > 0 { 1.0 } else { 0.0 })
            .collect();
        Target::Weights(weights)
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

impl OutcomeTable {
    /// The outcome of `command`, without `&mut`; a command that does not
    /// fit the table's space is a [`WorldError::BadCommand`], as in every
    /// world.
    ///
    /// ```
    /// use e3d::{Command, OutcomeTable, Scene, World, WorldError};
    /// let scene = Scene::builtin("two_rooms").unwrap();
    /// let table = OutcomeTable::build(&mut scene.build()).unwrap();
    /// let c = scene.command_space().parse("EEEEEEE").unwrap();
    /// assert_eq!(table.lookup(&c).unwrap(), &scene.build().execute(&c).unwrap());
    /// let bad = Command::new(vec![0, 1, 9, 0, 0, 0, 0]);
    /// assert!(matches!(table.lookup(&bad), Err(WorldError::BadCommand { .. })));
    /// ```
    #[inline]
    pub fn lookup(&self, command: &Command) -> Result<&Outcome, WorldError> {
        match self.places.index(&command.symbols) {
            Some(i) => Ok(&self.outcomes[i as usize]),
            None => Err(bad_command(&self.space, command)),
        }
    }
}

/// The error of a command that does not fit `space` (kept out of the
/// look-up's hot path).
#[cold]
fn bad_command(space: &CommandSpace, command: &Command) -> WorldError {
    match super::check_command(space, command) {
        Err(e) => e,
        Ok(()) => unreachable!("a command that fits has an index"),
    }
}

/// A table is a world, and so is a shared one (many sessions, one
/// table): a look-up per command.
macro_rules! table_world {
    ($($t:ty),*) => {$(
        impl World for $t {
            fn command_space(&self) -> &CommandSpace {
                &self.space
            }

            fn num_effects(&self) -> usize {
                self.num_effects
            }

            #[inline]
            fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
                self.lookup(command).copied()
            }
        }
    )*};
}

table_world!(OutcomeTable, &OutcomeTable);

#[cfg(test)]
mod tests {
    use super::*;

    /// The unrolled look-up (at most 8 slots) and the general one give
    /// `CommandSpace::index_of`, over mixed alphabets of 1 to 11 slots.
    #[test]
    fn places_give_the_index_of_every_command() {
        for n in 1..=11usize {
            let alphabets: Vec<Vec<char>> = (0..n)
                .map(|slot| ('a'..='z').take(1 + (slot * 7 + 2) % 5).collect())
                .collect();
            let space = CommandSpace::new(alphabets).unwrap();
            let p = places(&space);
            assert_eq!(p.short.is_some(), n <= SHORT);
            let total = space.num_commands().unwrap();
            let mut c = space.first();
            for i in (0..total).step_by((total / 500).max(1) as usize) {
                space.write_command_at(i, &mut c);
                assert_eq!(p.index(&c.symbols), Some(i), "{n} slots");
                assert_eq!(space.index_of(&c), i);
            }
            // a symbol beyond its alphabet, in the first and the last slot,
            // and a wrong length, have no index (unrolled and general)
            let mut bad = space.first();
            bad.symbols[0] = space.alphabet(0).len() as u8;
            assert_eq!(p.index(&bad.symbols), None, "{n} slots");
            let mut bad = space.first();
            bad.symbols[n - 1] = space.alphabet(n - 1).len() as u8;
            assert_eq!(p.index(&bad.symbols), None, "{n} slots");
            assert_eq!(p.index(&vec![0; n + 1]), None, "{n} slots");
            assert_eq!(p.index(&vec![0; n - 1]), None, "{n} slots");
        }
    }

    #[test]
    fn a_cached_table_reads_back_identical_and_refuses_other_scenes() {
        let scene = Scene::builtin("two_rooms").unwrap();
        let dir = std::env::temp_dir().join(format!("e3d-table-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let built = OutcomeTable::cached(&scene, &dir).unwrap();
        let path = OutcomeTable::cache_path(&scene, &dir);
        assert!(path.exists());
        let read = OutcomeTable::load(&path, &scene).unwrap();
        assert_eq!(read.outcomes, built.outcomes);
        assert_eq!(
            read.outcomes,
            OutcomeTable::build(&mut scene.build()).unwrap().outcomes
        );
        let mut other = scene.to_spec();
        other.reward.value = 2.0;
        let other = other.validate().unwrap();
        assert_ne!(OutcomeTable::key(&other), OutcomeTable::key(&scene));
        assert!(OutcomeTable::load(&path, &other).is_err());
        std::fs::write(&path, b"garbage").unwrap();
        assert!(OutcomeTable::load(&path, &scene).is_err());
        // a broken cache file is rebuilt, not trusted
        assert_eq!(
            OutcomeTable::cached(&scene, &dir).unwrap().outcomes,
            built.outcomes
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
