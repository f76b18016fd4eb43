//! Mutation of commands, shared by the learners that keep commands and
//! vary them ([`GoalBabbling`](super::GoalBabbling),
//! [`Archive`](super::Archive) and their continuous twins).
//!
//! - Symbols: [`mutate_symbols`] resamples exactly `k` distinct slots, each
//!   to another symbol of its alphabet (slots of one symbol cannot change
//!   and are never picked; `k` is capped at the number of the others).
//! - Values: [`mutate_values`] adds `N(0, sigma^2)` noise to every slot in
//!   the unit coordinates of its range (`-1` its min, `1` its max) and
//!   clamps to the range.

use super::gaussian::normal;
use super::state::{check_values, ensure};
use crate::command::ValueSpace;
use crate::rng::SessionRng;
use rand::RngExt;
use serde::{de::DeserializeOwned, Deserialize, Serialize};

/// Resamples exactly `min(k, m)` distinct slots of `symbols`, `m` the
/// number of slots whose alphabet has more than one symbol: the slots are
/// drawn without replacement (a partial Fisher-Yates shuffle of those
/// slots, one `random_range` each), and each takes a symbol other than
/// its own, uniformly (one `random_range` over `size - 1`). `sizes[i]` is
/// slot `i`'s alphabet size.
///
/// ```
/// use e3d::learner::mutation::mutate_symbols;
/// use e3d::rand::SeedableRng;
/// let sizes = [4, 4, 1, 4, 4];
/// let before = vec![0u8; 5];
/// let mut after = before.clone();
/// mutate_symbols(&sizes, 2, &mut e3d::SessionRng::seed_from_u64(3), &mut after, &mut Vec::new());
/// assert_eq!(before.iter().zip(&after).filter(|(a, b)| a != b).count(), 2);
/// assert_eq!(after[2], 0); // a slot of one symbol never changes
/// ```
pub fn mutate_symbols(
    sizes: &[usize],
    k: usize,
    rng: &mut SessionRng,
    symbols: &mut [u8],
    scratch: &mut Vec<usize>,
) {
    scratch.clear();
    scratch.extend((0..sizes.len()).filter(|&i| sizes[i] > 1));
    let k = k.min(scratch.len());
    for j in 0..k {
        let pick = rng.random_range(j..scratch.len());
        scratch.swap(j, pick);
        let slot = scratch[j];
        let old = symbols[slot] as usize;
        let mut new = rng.random_range(0..sizes[slot] - 1);
        if new >= old {
            new += 1;
        }
        symbols[slot] = new as u8;
    }
}

/// Adds `N(0, sigma^2)` to each value in the unit coordinates of its slot's
/// range (one standard normal per slot, Marsaglia's polar method as in
/// [`GaussianE3d`](super::GaussianE3d)) and clamps the result to the
/// range.
///
/// ```
/// use e3d::learner::mutation::mutate_values;
/// use e3d::rand::SeedableRng;
/// use e3d::command::ValueSpace;
/// let space = ValueSpace::new(vec![(0.0, 2.0); 3]).unwrap();
/// let mut v = vec![1.0, 0.0, 2.0];
/// mutate_values(&space, 0.1, &mut e3d::SessionRng::seed_from_u64(1), &mut v);
/// assert!(v.iter().all(|x| (0.0..=2.0).contains(x)));
/// assert!(v[0] != 1.0);
/// ```
pub fn mutate_values(space: &ValueSpace, sigma: f64, rng: &mut SessionRng, values: &mut [f64]) {
    for (slot, v) in values.iter_mut().enumerate() {
        let u = to_unit(space, slot, *v) + sigma * normal(rng);
        *v = space.from_unit(slot, u);
    }
}

/// The unit coordinate of value `v` in `slot`'s range.
pub(crate) fn to_unit(space: &ValueSpace, slot: usize, v: f64) -> f64 {
    let (lo, hi) = space.range(slot);
    2.0 * (v - lo) / (hi - lo) - 1.0
}

/// A uniform command of symbols (one `random_range` per slot, as
/// [`UniformPolicy`](super::UniformPolicy)).
pub(crate) fn random_symbols(sizes: &[usize], rng: &mut SessionRng, out: &mut Vec<u8>) {
    out.clear();
    out.extend(sizes.iter().map(|&k| rng.random_range(0..k) as u8));
}

/// A uniform command of values (one `f64` per slot, as
/// [`UniformValues`](super::UniformValues)).
pub(crate) fn random_values(space: &ValueSpace, rng: &mut SessionRng, out: &mut Vec<f64>) {
    out.clear();
    out.extend(
        space
            .ranges()
            .iter()
            .map(|&(lo, hi)| lo + (hi - lo) * rng.random::<f64>()),
    );
}

/// What a learner of kept commands needs of a command type: a uniform
/// command and a mutation (symbols: `u8`; values: `f64`).
pub(crate) trait Genome: Clone + Send + Serialize + DeserializeOwned {
    /// The element of a command.
    type Elem: Copy + PartialEq + Send + std::fmt::Debug + Serialize + DeserializeOwned;
    /// A uniform command into `out`.
    fn random(&self, rng: &mut SessionRng, out: &mut Vec<Self::Elem>);
    /// Mutates `cmd` in place.
    fn mutate(&mut self, rng: &mut SessionRng, cmd: &mut [Self::Elem]);
    /// The alphabet size of each slot (0 for a slot of values).
    fn sizes(&self) -> Vec<usize>;
    /// Checks a genome read from a state.
    fn validate(&self) -> Result<(), String>;
}

/// Commands of symbols, mutated by resampling `k` slots.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct SymbolGenome {
    pub(crate) sizes: Vec<usize>,
    pub(crate) k: usize,
    #[serde(skip)]
    scratch: Vec<usize>,
}

impl SymbolGenome {
    pub(crate) fn new(sizes: Vec<usize>, k: usize) -> Self {
        SymbolGenome {
            sizes,
            k,
            scratch: Vec::new(),
        }
    }
}

impl Genome for SymbolGenome {
    type Elem = u8;
    fn random(&self, rng: &mut SessionRng, out: &mut Vec<u8>) {
        random_symbols(&self.sizes, rng, out)
    }
    fn mutate(&mut self, rng: &mut SessionRng, cmd: &mut [u8]) {
        mutate_symbols(&self.sizes, self.k, rng, cmd, &mut self.scratch)
    }
    fn sizes(&self) -> Vec<usize> {
        self.sizes.clone()
    }
    fn validate(&self) -> Result<(), String> {
        let sizes = &self.sizes;
        ensure(
            !sizes.is_empty() && sizes.iter().all(|&n| (1..=256).contains(&n)),
            || format!("slots of alphabet sizes {sizes:?}"),
        )
    }
}

/// Commands of values, mutated by Gaussian noise of `sigma` (unit
/// coordinates).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct ValueGenome {
    pub(crate) space: ValueSpace,
    pub(crate) sigma: f64,
}

impl Genome for ValueGenome {
    type Elem = f64;
    fn random(&self, rng: &mut SessionRng, out: &mut Vec<f64>) {
        random_values(&self.space, rng, out)
    }
    fn mutate(&mut self, rng: &mut SessionRng, cmd: &mut [f64]) {
        mutate_values(&self.space, self.sigma, rng, cmd)
    }
    fn sizes(&self) -> Vec<usize> {
        vec![0; self.space.num_slots()]
    }
    fn validate(&self) -> Result<(), String> {
        check_values(&self.space)
    }
}

/// Checks kept commands read from a state (`what`: the learner, named
/// in the error): some cells, each kept command of `slots` slots, `order`
/// the kept cells each once, `last` a kept cell.
pub(crate) fn check_cells<T>(
    what: &str,
    slots: usize,
    cells: &[Option<T>],
    order: &[usize],
    last: Option<usize>,
    len: impl Fn(&T) -> usize,
) -> Result<(), String> {
    let kept = |e: &usize| cells.get(*e).is_some_and(Option::is_some);
    let ok = !cells.is_empty()
        && cells.iter().flatten().all(|c| len(c) == slots)
        && order.iter().all(kept)
        && order.len() == cells.iter().flatten().count()
        && last.as_ref().is_none_or(kept);
    ensure(ok, || {
        format!(
            "{what} whose commands or reached cells do not fit {} cells of {slots} slots",
            cells.len()
        )
    })
}

/// [`LearnerState`](super::LearnerState) for learners of kept commands
/// (a `core` with a `genome` and `cells`, and `Core::validate`), by kind.
macro_rules! kept_commands_state {
    ($($learner:ident $kind:literal),*) => {$(
        impl LearnerState for $learner {
            const KIND: &'static str = $kind;
            fn shape(&self) -> StateShape {
                StateShape::of(self.core.genome.sizes(), Some(self.core.cells.len()))
            }
            fn validate(&self) -> Result<(), String> {
                self.core.validate()
            }
        }
    )*};
}
pub(crate) use kept_commands_state;
