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

use super::state::{check_values, ensure};
use super::Params;
use crate::command::{CommandSpace, ValueSpace};
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

/// One standard normal draw (Marsaglia's polar method: two uniforms, a
/// square root and a logarithm per pair; the second of the pair is dropped
/// so that each draw consumes the generator the same way whatever came
/// before).
pub(crate) fn normal(rng: &mut SessionRng) -> f64 {
    loop {
        let u = 2.0 * rng.random::<f64>() - 1.0;
        let v = 2.0 * rng.random::<f64>() - 1.0;
        let s = u * u + v * v;
        if s > 0.0 && s < 1.0 {
            return u * (-2.0 * s.ln() / s).sqrt();
        }
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

/// A uniform command of symbols into `out` (one `random_range` per slot,
/// as [`UniformPolicy`](super::UniformPolicy)).
pub(crate) fn random_symbols(
    sizes: impl IntoIterator<Item = usize>,
    rng: &mut SessionRng,
    out: &mut Vec<u8>,
) {
    out.clear();
    out.extend(sizes.into_iter().map(|k| rng.random_range(0..k) as u8));
}

/// A uniform command of values into `out` (one `f64` per slot, as
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

/// What a learner of kept commands needs of a kind of command: a uniform
/// command and a mutation ([`SymbolGenome`]: `u8`; [`ValueGenome`]: `f64`).
pub trait Genome: Clone + Send + Serialize + DeserializeOwned {
    /// The element of a command.
    type Elem: Copy + PartialEq + Send + std::fmt::Debug + Serialize + DeserializeOwned;
    /// The space of the commands ([`CommandSpace`] or [`ValueSpace`]).
    type Space;
    /// The genome of `space`, mutating as `params` says (`k` or `sigma`).
    fn new(space: &Self::Space, params: &Params) -> Self;
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
pub struct SymbolGenome {
    sizes: Vec<usize>,
    k: usize,
    #[serde(skip)]
    scratch: Vec<usize>,
}

impl Genome for SymbolGenome {
    type Elem = u8;
    type Space = CommandSpace;
    fn new(space: &CommandSpace, params: &Params) -> Self {
        SymbolGenome {
            sizes: space.sizes().collect(),
            k: params.k,
            scratch: Vec::new(),
        }
    }
    fn random(&self, rng: &mut SessionRng, out: &mut Vec<u8>) {
        random_symbols(self.sizes.iter().copied(), rng, out)
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
pub struct ValueGenome {
    pub(crate) space: ValueSpace,
    sigma: f64,
}

impl Genome for ValueGenome {
    type Elem = f64;
    type Space = ValueSpace;
    fn new(space: &ValueSpace, params: &Params) -> Self {
        ValueGenome {
            space: space.clone(),
            sigma: params.sigma,
        }
    }
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

/// The cells a learner of kept commands reached, each with its entry `E`
/// (the command kept for it, and more), and the reached cells in the order
/// they were first reached.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub(crate) struct Cells<E> {
    pub cells: Vec<Option<E>>,
    pub order: Vec<usize>,
}

/// An entry of [`Cells`]: it keeps a command.
pub(crate) trait Kept<T> {
    fn command(&self) -> &[T];
}

impl<E> Cells<E> {
    /// `n` cells, none reached.
    pub fn new(n: usize) -> Self {
        let cells = (0..n).map(|_| None).collect();
        Cells {
            cells,
            order: Vec::new(),
        }
    }

    /// The entry of reached cell `e`.
    pub fn get(&self, e: usize) -> &E {
        self.cells[e].as_ref().expect("a reached cell")
    }

    /// Updates the entry of cell `e`, or makes it (`first`) if `e` was not
    /// reached yet.
    pub fn keep(&mut self, e: usize, first: impl FnOnce() -> E, update: impl FnOnce(&mut E)) {
        match &mut self.cells[e] {
            Some(entry) => update(entry),
            slot @ None => {
                *slot = Some(first());
                self.order.push(e);
            }
        }
    }

    /// The command kept for cell `e`, if it was reached.
    pub fn command_of<T>(&self, e: usize) -> Option<&[T]>
    where
        E: Kept<T>,
    {
        self.cells.get(e)?.as_ref().map(Kept::command)
    }

    /// Checks cells read from a state (`what`: the learner, named in the
    /// error): some cells, each command of `slots` slots, `order` the
    /// reached cells each once, `last` a reached cell.
    pub fn check<T>(&self, what: &str, slots: usize, last: Option<usize>) -> Result<(), String>
    where
        E: Kept<T>,
    {
        let cells = &self.cells;
        let kept = |e: &usize| cells.get(*e).is_some_and(Option::is_some);
        let ok = !cells.is_empty()
            && cells.iter().flatten().all(|c| c.command().len() == slots)
            && self.order.iter().all(kept)
            && self.order.len() == cells.iter().flatten().count()
            && last.as_ref().is_none_or(kept);
        ensure(ok, || {
            format!(
                "{what} whose commands or reached cells do not fit {} cells of {slots} slots",
                cells.len()
            )
        })
    }
}

/// The mean and (population) standard deviation of `xs`; the middle of
/// `range` and 0 when there are none.
pub(crate) fn spread(xs: impl Iterator<Item = f64>, range: (f64, f64)) -> (f64, f64) {
    let (mut n, mut sum, mut sq) = (0.0, 0.0, 0.0);
    for x in xs {
        n += 1.0;
        sum += x;
        sq += x * x;
    }
    if n == 0.0 {
        return ((range.0 + range.1) / 2.0, 0.0);
    }
    let mean = sum / n;
    (mean, (sq / n - mean * mean).max(0.0).sqrt())
}

/// A learner of kept commands, `$of<G>` (with `genome`, `cells`,
/// `command_of`, `check`, and `draw` and `keep` proposing and learning a
/// command's elements), as a [`Learner`]
/// over symbols and a [`ContinuousLearner`] over values, and its
/// [`LearnerState`] of kind `$kind` (`$kind_values` over values).
///
/// [`Learner`]: super::Learner
/// [`ContinuousLearner`]: super::ContinuousLearner
/// [`LearnerState`]: super::LearnerState
macro_rules! kept_commands {
    ($of:ident $kind:literal) => {
        impl Learner for $of<SymbolGenome> {
            fn name(&self) -> &str {
                $kind
            }
            fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
                self.draw(rng, &mut command.symbols);
            }
            fn learn(&mut self, command: &Command, outcome: &Outcome) {
                self.keep(&command.symbols, outcome);
            }
        }

        impl ContinuousLearner for $of<ValueGenome> {
            fn value_space(&self) -> Option<&ValueSpace> {
                Some(&self.genome.space)
            }
            fn name(&self) -> &str {
                $kind
            }
            fn propose(&mut self, rng: &mut SessionRng, values: &mut Vec<f64>) {
                self.draw(rng, values);
            }
            fn learn(&mut self, values: &[f64], outcome: &Outcome) {
                self.keep(values, outcome);
            }
            /// No Gaussian: the mean and standard deviation of the slot's
            /// values over the kept commands (the middle of the range and
            /// 0 while there are none).
            fn slot_gaussian(&self, slot: usize) -> (f64, f64) {
                let kept = self.cells.order.iter().filter_map(|&e| self.command_of(e));
                spread(kept.map(|c| c[slot]), self.genome.space.range(slot))
            }
        }

        kept_commands!(@state $of SymbolGenome $kind);
        kept_commands!(@state $of ValueGenome concat!($kind, "_values"));
    };
    (@state $of:ident $genome:ident $kind:expr) => {
        impl LearnerState for $of<$genome> {
            const KIND: &'static str = $kind;
            fn shape(&self) -> StateShape {
                StateShape::of(self.genome.sizes(), Some(self.cells.cells.len()))
            }
            fn validate(&self) -> Result<(), String> {
                self.check()
            }
        }
    };
}
pub(crate) use kept_commands;
