//! The outcome memo: the commands sessions propose, each executed once and
//! kept (shared by every session and thread, capped, saved as a *partial*
//! table file), and [`Memoized`], any [`World`] looking its commands up
//! there first. Outcomes are the world's, bit for bit.

use super::{Outcome, World, WorldError};
use crate::command::{Command, CommandSpace};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;

/// The default cap on a memo's entries: 2^21 commands, about 100 to 200
/// MB.
pub const DEFAULT_MEMO_CAP: usize = 1 << 21;

/// The number of independently locked parts of a memo.
const SHARDS: usize = 16;

/// A hasher for command indices: one multiplication (Fibonacci hashing);
/// the indices are already distinct integers.
#[derive(Default, Clone, Copy)]
pub struct IndexHasher(u64);

impl Hasher for IndexHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
        }
    }
    fn write_u64(&mut self, i: u64) {
        self.0 = i.wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(29);
    }
}

type Shard = HashMap<u64, Outcome, BuildHasherDefault<IndexHasher>>;

/// The outcomes of the commands executed so far, by command index
/// ([`CommandSpace::index_of`]).
///
/// ```
/// use e3d::world::{Memoized, OutcomeMemo};
/// use e3d::{Scene, World};
/// let scene = Scene::builtin("puck_rooms").unwrap();
/// let memo = OutcomeMemo::new(&scene.command_space(), scene.num_effects(), 1000).unwrap();
/// let mut world = Memoized::new(scene.build(), &memo);
/// let c = world.command_space().parse("SEEEEES").unwrap();
/// let first = world.execute(&c).unwrap();   // simulated
/// let again = world.execute(&c).unwrap();   // looked up
/// assert_eq!(first, again);
/// assert_eq!((memo.len(), memo.hits(), memo.misses()), (1, 1, 1));
/// ```
#[derive(Debug)]
pub struct OutcomeMemo {
    space: CommandSpace,
    num_effects: usize,
    cap: usize,
    shards: Box<[Mutex<Shard>]>,
    len: AtomicUsize,
    hits: AtomicU64,
    misses: AtomicU64,
}

impl OutcomeMemo {
    /// An empty memo for the commands of `space`, holding at most `cap`
    /// outcomes (beyond it, new commands are executed but not kept).
    /// Refuses a space of more than 2^64 commands, whose indices do not fit
    /// a `u64`.
    pub fn new(space: &CommandSpace, num_effects: usize, cap: usize) -> Result<Self, WorldError> {
        if space.num_commands().is_none() {
            return Err(WorldError::Other(
                "the command space has more than 2^64 commands: too many for an outcome memo"
                    .into(),
            ));
        }
        Ok(OutcomeMemo {
            space: space.clone(),
            num_effects,
            cap,
            shards: (0..SHARDS).map(|_| Mutex::new(Shard::default())).collect(),
            len: AtomicUsize::new(0),
            hits: AtomicU64::new(0),
            misses: AtomicU64::new(0),
        })
    }

    fn shard(&self, index: u64) -> std::sync::MutexGuard<'_, Shard> {
        let k = (index.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 60) as usize % SHARDS;
        // a poisoned shard only means another thread panicked mid-insert of
        // a plain value: the map is still consistent
        self.shards[k].lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The command space.
    pub fn command_space(&self) -> &CommandSpace {
        &self.space
    }

    /// The number of effects of the world.
    pub fn num_effects(&self) -> usize {
        self.num_effects
    }

    /// The outcome of the command with index `index`, if kept; counts a
    /// hit or a miss.
    pub fn get(&self, index: u64) -> Option<Outcome> {
        let o = self.shard(index).get(&index).copied();
        let counter = if o.is_some() {
            &self.hits
        } else {
            &self.misses
        };
        counter.fetch_add(1, Ordering::Relaxed);
        o
    }

    /// The outcome of `index` without counting a hit or a miss.
    pub fn peek(&self, index: u64) -> Option<Outcome> {
        self.shard(index).get(&index).copied()
    }

    /// Keeps the outcome of the command with index `index`; `false` if the
    /// memo is full (the outcome is then not kept) or already held it.
    pub fn insert(&self, index: u64, outcome: Outcome) -> bool {
        if self.len.load(Ordering::Relaxed) >= self.cap {
            return false;
        }
        let mut shard = self.shard(index);
        if shard.contains_key(&index) {
            return false;
        }
        // the cap is checked again under the count, so it is never exceeded
        if self.len.fetch_add(1, Ordering::Relaxed) >= self.cap {
            self.len.fetch_sub(1, Ordering::Relaxed);
            return false;
        }
        shard.insert(index, outcome);
        true
    }

    /// The number of outcomes kept.
    pub fn len(&self) -> usize {
        self.len.load(Ordering::Relaxed)
    }

    /// Whether no outcome is kept.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether it is full (new commands are no longer kept).
    pub fn is_full(&self) -> bool {
        self.len() >= self.cap
    }

    /// How many look-ups found their command.
    pub fn hits(&self) -> u64 {
        self.hits.load(Ordering::Relaxed)
    }

    /// How many look-ups did not (each then executed by the world).
    pub fn misses(&self) -> u64 {
        self.misses.load(Ordering::Relaxed)
    }

    /// Keeps every outcome of `entries` (command index and outcome, as a
    /// partial table file holds them), as far as the cap allows.
    pub fn extend(&self, entries: impl IntoIterator<Item = (u64, Outcome)>) {
        for (i, o) in entries {
            self.insert(i, o);
        }
    }

    /// Writes the kept outcomes as `scene`'s partial table file at `path`
    /// (whole or not at all), first taking in what the file holds now (so
    /// that runs sharing a folder add to each other's outcomes); returns
    /// the number of outcomes written. Runs saving into the same file
    /// take turns ([`FileLock`](crate::io::FileLock) on it), so that none
    /// loses what another added between its read and its write.
    pub fn save(&self, path: &std::path::Path, scene: &crate::Scene) -> std::io::Result<usize> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let _turn = crate::io::FileLock::exclusive(path)?;
        if let Ok(super::CachedOutcomes::Partial(e)) = super::OutcomeTable::read_file(path, scene) {
            self.extend(e);
        }
        let entries = self.entries();
        super::OutcomeTable::write_partial(path, scene, &entries)?;
        Ok(entries.len())
    }

    /// Every kept outcome with its command index, in index order.
    pub fn entries(&self) -> Vec<(u64, Outcome)> {
        let mut all: Vec<(u64, Outcome)> = Vec::with_capacity(self.len());
        for s in self.shards.iter() {
            let s = s.lock().unwrap_or_else(|e| e.into_inner());
            all.extend(s.iter().map(|(&i, &o)| (i, o)));
        }
        all.sort_unstable_by_key(|e| e.0);
        all
    }
}

/// A world whose outcomes go through an [`OutcomeMemo`]: each command is
/// looked up first, executed by the inner world only if it is not there,
/// and kept. Commands that fail are not kept (they fail again, the same
/// way, if proposed again).
pub struct Memoized<'m, W> {
    world: W,
    memo: &'m OutcomeMemo,
    /// Reused per batch: the position of each command's result, the
    /// commands to execute and their indices.
    slots: Vec<Slot>,
    misses: Vec<Command>,
    miss_index: Vec<u64>,
    pending: Pending,
    results: Vec<Result<Outcome, WorldError>>,
}

/// The position of each new command of a batch among its misses.
type Pending = HashMap<u64, usize, BuildHasherDefault<IndexHasher>>;

#[derive(Clone, Copy)]
enum Slot {
    Known(Outcome),
    /// The k-th command executed in this batch; `true`: the mirror image
    /// of the command asked for, whose outcome is reflected.
    Executed(usize, bool),
    /// Not in the command space: passed to the world, which says why.
    Bad,
}

impl<'m, W: World> Memoized<'m, W> {
    /// `world`, its outcomes kept in `memo` (a memo of the same command
    /// space: the caller's promise, checked in debug builds).
    pub fn new(world: W, memo: &'m OutcomeMemo) -> Self {
        debug_assert_eq!(world.command_space(), memo.command_space());
        Memoized {
            world,
            memo,
            slots: Vec::new(),
            misses: Vec::new(),
            miss_index: Vec::new(),
            pending: Pending::default(),
            results: Vec::new(),
        }
    }

    /// The inner world back, to be kept and wrapped again later (a pool
    /// of multi-copy worlds costs less than building one per batch); the
    /// memo keeps every outcome it was given.
    pub fn into_inner(self) -> W {
        self.world
    }

    /// The entry of `c` (`None`: it does not fit the space) and the
    /// command the world simulates in its place, if any: under a symmetry
    /// a command and its mirror image share the entry of the one simulated.
    fn key(&self, c: &Command) -> Option<(u64, Option<Command>)> {
        let space = self.world.command_space();
        super::check_command(space, c).ok()?;
        let mirror = self.world.mirror_of(c);
        let key = space.index_of(mirror.as_ref().unwrap_or(c));
        Some((key, mirror))
    }
}

impl<W: World> World for Memoized<'_, W> {
    fn command_space(&self) -> &CommandSpace {
        self.world.command_space()
    }

    fn num_effects(&self) -> usize {
        self.world.num_effects()
    }

    fn is_deterministic(&self) -> bool {
        self.world.is_deterministic()
    }

    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        let Some((key, mirror)) = self.key(command) else {
            return self.world.execute(command);
        };
        let reflect = |w: &W, o| match mirror {
            Some(_) => w.mirror_outcome(o),
            None => o,
        };
        if let Some(o) = self.memo.get(key) {
            return Ok(reflect(&self.world, o));
        }
        let o = self.world.execute(command)?;
        self.memo.insert(key, reflect(&self.world, o));
        Ok(o)
    }

    /// Looks every command up, executes the missing ones (each distinct
    /// command once, however many times the batch holds it) in one batch
    /// of the inner world, and keeps their outcomes.
    fn execute_batch(&mut self, commands: &[Command], out: &mut Vec<Result<Outcome, WorldError>>) {
        self.slots.clear();
        self.misses.clear();
        self.miss_index.clear();
        self.pending.clear();
        for c in commands {
            let slot = match self.key(c) {
                // not in the command space: the world says why
                None => Slot::Bad,
                Some((key, mirror)) => {
                    let reflect = mirror.is_some();
                    match self.pending.get(&key) {
                        // proposed twice in this batch: executed once
                        Some(&k) => Slot::Executed(k, reflect),
                        None => match self.memo.get(key) {
                            Some(o) if reflect => Slot::Known(self.world.mirror_outcome(o)),
                            Some(o) => Slot::Known(o),
                            None => {
                                self.pending.insert(key, self.misses.len());
                                self.misses.push(mirror.unwrap_or_else(|| c.clone()));
                                self.miss_index.push(key);
                                Slot::Executed(self.misses.len() - 1, reflect)
                            }
                        },
                    }
                }
            };
            self.slots.push(slot);
        }
        self.results.clear();
        if !self.misses.is_empty() {
            self.world.execute_batch(&self.misses, &mut self.results);
        }
        for (&i, r) in self.miss_index.iter().zip(&self.results) {
            if let Ok(o) = r {
                self.memo.insert(i, *o);
            }
        }
        out.reserve(commands.len());
        for (c, slot) in commands.iter().zip(&self.slots) {
            out.push(match *slot {
                Slot::Known(o) => Ok(o),
                Slot::Executed(k, false) => self.results[k].clone(),
                Slot::Executed(k, true) => match &self.results[k] {
                    Ok(o) => Ok(self.world.mirror_outcome(*o)),
                    // the error as the world words it for this command
                    Err(_) => self.world.execute(c),
                },
                Slot::Bad => self.world.execute(c),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scene;

    #[test]
    fn a_full_memo_keeps_no_more_and_still_answers() {
        let scene = Scene::builtin("two_rooms").unwrap();
        let space = scene.command_space();
        let memo = OutcomeMemo::new(&space, scene.num_effects(), 3).unwrap();
        let mut plain = scene.build();
        let mut world = Memoized::new(scene.build(), &memo);
        for i in 0..10u64 {
            let c = space.command_at(i * 7);
            assert_eq!(world.execute(&c).unwrap(), plain.execute(&c).unwrap());
        }
        assert_eq!(memo.len(), 3);
        assert!(memo.is_full());
        let kept: Vec<u64> = memo.entries().iter().map(|e| e.0).collect();
        assert_eq!(kept, vec![0, 7, 14]);
    }

    #[test]
    fn a_batch_executes_each_new_command_once_and_keeps_bad_ones_apart() {
        let scene = Scene::builtin("two_rooms").unwrap();
        let space = scene.command_space();
        let memo = OutcomeMemo::new(&space, scene.num_effects(), 100).unwrap();
        let mut world = Memoized::new(scene.build(), &memo);
        let a = space.parse("EEEEEEE").unwrap();
        let b = space.parse("SSSSSSS").unwrap();
        let bad = Command::new(vec![9; 7]);
        world.execute(&a).unwrap();
        let mut out = Vec::new();
        world.execute_batch(&[a.clone(), b.clone(), bad, b.clone(), a.clone()], &mut out);
        let mut plain = scene.build();
        assert_eq!(out[0], plain.execute(&a));
        assert_eq!(out[1], plain.execute(&b));
        assert!(matches!(out[2], Err(WorldError::BadCommand { .. })));
        assert_eq!(out[3], out[1]);
        assert_eq!(out[4], out[0]);
        // a then a, b (new) and a again were looked up; b once executed
        assert_eq!(memo.len(), 2);
        assert_eq!(memo.misses(), 2);
        assert_eq!(memo.hits(), 2);
    }
}
