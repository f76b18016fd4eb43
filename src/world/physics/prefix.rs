//! Simulating only what a command does not share with an earlier one.
//!
//! On a `Sequential` schedule, the state a command reaches at the end of
//! its phase `k` depends on its first `k` symbols alone. A world of one
//! copy keeps the Rapier sets it passed through at those phase ends
//! (every set, as a [`PhysicsState`](super::PhysicsState) does: contact
//! manifolds and warm-start impulses included), keyed by the prefix; a
//! later command with the same prefix restores the deepest one kept and
//! simulates only its remaining phases and the settle. The result is the
//! same bits as the whole rollout (Rapier's step reads only the sets, which
//! the snapshot restores whole; tested on every shipped sequential scene),
//! so this changes speed, never a result.
//!
//! The number of states kept is bounded by construction: prefixes of at
//! most `depth` slots, where `depth` is the deepest whose prefixes number
//! at most [`PREFIX_STATES`] in all. puck_rooms (7 slots of 4 symbols)
//! keeps prefixes of up to 5 slots (1364 states, about 25 MB) and simulates
//! 240 of the 540 steps of a command whose 5-slot prefix ran before.

use super::Sets;
use std::collections::HashMap;

/// The most phase-end states a world of one copy keeps by default.
pub const PREFIX_STATES: usize = 2048;

/// The phase-end states of the prefixes run so far (see the module).
#[derive(Default)]
pub(super) struct Prefixes {
    /// The number of symbols of each slot whose phase-end states may be
    /// kept (none on a simultaneous schedule).
    sizes: Vec<usize>,
    /// The longest prefix kept, in slots (0: none).
    depth: usize,
    states: HashMap<Vec<u8>, Sets>,
    /// The states of the command running now, kept once it ends cleanly.
    pending: Vec<(Vec<u8>, Sets)>,
}

impl Prefixes {
    /// Prefixes of slots whose alphabets have `sizes` symbols, on a
    /// sequential schedule (`sequential`), at most `capacity` states.
    pub(super) fn new(sizes: &[usize], sequential: bool, capacity: usize) -> Prefixes {
        // the last slot's state is the command's own: the memo's business
        let sizes = match sequential {
            true => sizes[..sizes.len().saturating_sub(1)].to_vec(),
            false => Vec::new(),
        };
        Prefixes {
            sizes,
            ..Prefixes::default()
        }
        .with_capacity(capacity)
    }

    /// The same prefixes, none kept yet, at most `capacity` states.
    pub(super) fn with_capacity(&self, capacity: usize) -> Prefixes {
        let (mut count, mut width, mut depth) = (0usize, 1usize, 0);
        for &n in &self.sizes {
            width = width.saturating_mul(n);
            count = count.saturating_add(width);
            if count > capacity {
                break;
            }
            depth += 1;
        }
        Prefixes {
            sizes: self.sizes.clone(),
            depth,
            ..Prefixes::default()
        }
    }

    /// The longest prefix kept, in slots (0: the cache is off).
    pub(super) fn depth(&self) -> usize {
        self.depth
    }

    /// The number of states kept.
    pub(super) fn len(&self) -> usize {
        self.states.len()
    }

    /// Every state kept.
    #[cfg(test)]
    pub(super) fn states(&self) -> impl Iterator<Item = &Sets> {
        self.states.values()
    }

    /// The deepest state kept of a prefix of `symbols`, and its length.
    pub(super) fn deepest(&self, symbols: &[u8]) -> Option<(usize, &Sets)> {
        (1..=self.depth.min(symbols.len()))
            .rev()
            .find_map(|k| self.states.get(&symbols[..k]).map(|s| (k, s)))
    }

    /// Whether the state at the end of the phase of slot `k - 1` of a
    /// command of `symbols` is to be noted: its prefix is kept, not known yet.
    pub(super) fn wants(&self, symbols: &[u8], k: usize) -> bool {
        k <= self.depth && !self.states.contains_key(&symbols[..k])
    }

    /// Notes `sets`, the state of the prefix of `k` slots of `symbols`.
    pub(super) fn note(&mut self, symbols: &[u8], k: usize, sets: Sets) {
        self.pending.push((symbols[..k].to_vec(), sets));
    }

    /// Keeps the noted states (`clean`: the command ran to its end without
    /// a failure or a missed limit gate), else forgets them.
    pub(super) fn settle(&mut self, clean: bool) {
        if clean {
            self.states.extend(self.pending.drain(..));
        } else {
            self.pending.clear();
        }
    }
}
