//! An archive of reached cells, Go-Explore style (after Ecoffet et al.
//! 2019, "Go-Explore: a new approach for hard-exploration problems",
//! arXiv 1901.10995): one command per reached cell; pick a cell, mutate
//! its command, execute it.

use super::mutation::{check_cells, kept_commands_state, Genome, SymbolGenome, ValueGenome};
use super::state::{LearnerState, StateShape};
use super::{ContinuousLearner, Learner, Params};
use crate::command::{Command, CommandSpace, ValueSpace};
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{Deserialize, Serialize};

/// One reached cell: the command kept for it, the reward it got, and how
/// many times the cell was chosen.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Entry<T> {
    command: Vec<T>,
    reward: f64,
    chosen: u64,
    /// `(1 + chosen)^(-rarity)`.
    weight: f64,
}

/// The archive, for either kind of command.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(bound = "")]
struct Core<G: Genome> {
    genome: G,
    cells: Vec<Option<Entry<G::Elem>>>,
    /// The reached cells, in the order they were first reached.
    reached: Vec<usize>,
    rarity: f64,
    /// The cell chosen for the last proposal (`None`: a uniform command).
    last_cell: Option<usize>,
}

impl<G: Genome> Core<G> {
    fn new(genome: G, num_effects: usize, rarity: f64) -> Self {
        Core {
            genome,
            cells: vec![None; num_effects],
            reached: Vec::new(),
            rarity,
            last_cell: None,
        }
    }

    fn choose(&mut self, rng: &mut SessionRng) -> Option<usize> {
        if self.reached.is_empty() {
            return None;
        }
        let i = if self.rarity == 0.0 {
            rng.random_range(0..self.reached.len())
        } else {
            let entry = |e: usize| self.cells[e].as_ref().expect("a reached cell");
            let total: f64 = self.reached.iter().map(|&e| entry(e).weight).sum();
            let u = rng.random::<f64>() * total;
            let mut acc = 0.0;
            let mut pick = self.reached.len() - 1;
            for (i, &e) in self.reached.iter().enumerate() {
                acc += entry(e).weight;
                if u < acc {
                    pick = i;
                    break;
                }
            }
            pick
        };
        Some(self.reached[i])
    }

    fn propose(&mut self, rng: &mut SessionRng, out: &mut Vec<G::Elem>) {
        self.last_cell = self.choose(rng);
        match self.last_cell {
            None => self.genome.random(rng, out),
            Some(e) => {
                let rarity = self.rarity;
                let entry = self.cells[e].as_mut().expect("a reached cell");
                entry.chosen += 1;
                entry.weight = (1.0 + entry.chosen as f64).powf(-rarity);
                out.clear();
                out.extend_from_slice(&entry.command);
                self.genome.mutate(rng, out);
            }
        }
    }

    fn learn(&mut self, command: &[G::Elem], outcome: &Outcome) {
        let e = outcome.effect;
        match &mut self.cells[e] {
            Some(entry) => {
                if outcome.reward > entry.reward {
                    entry.command.clear();
                    entry.command.extend_from_slice(command);
                    entry.reward = outcome.reward;
                }
            }
            slot @ None => {
                *slot = Some(Entry {
                    command: command.to_vec(),
                    reward: outcome.reward,
                    chosen: 0,
                    weight: 1.0,
                });
                self.reached.push(e);
            }
        }
    }

    fn command_of(&self, effect: usize) -> Option<&[G::Elem]> {
        self.cells
            .get(effect)?
            .as_ref()
            .map(|c| c.command.as_slice())
    }

    fn times_chosen(&self, effect: usize) -> u64 {
        self.cells
            .get(effect)
            .and_then(|c| c.as_ref())
            .map_or(0, |c| c.chosen)
    }
}

/// An archive of reached cells, Go-Explore style, over commands of
/// symbols.
///
/// The archive keeps **one command per reached cell** (the first that
/// reached it, replaced only by one that reached it with a higher reward).
/// Each trial:
///
/// ```text
/// if the archive is empty: a uniform command
/// else:
///     pick a reached cell c with probability proportional to (1 + n_c)^(-rarity),
///         n_c the times c was picked before (rarity 0: uniformly)
///     n_c <- n_c + 1
///     propose the command of c with k slots resampled (Params::k)
/// after the trial, ending in cell e with reward r:
///     if e is not in the archive, or r > the reward kept for e: keep the command for e
/// ```
///
/// `rarity` is [`Params::rarity`] (default 0.5, Go-Explore's
/// `1/sqrt(n + 1)` weight), `k` is [`Params::k`] (default 2). Its draws:
/// one `f64` per trial to pick a cell (one integer when `rarity` is 0),
/// then two integers per mutated slot ([`mutate_symbols`](super::mutation::mutate_symbols)).
///
/// ```
/// use e3d::learner::Archive;
/// use e3d::rand::SeedableRng;
/// use e3d::{Command, Learner, Outcome, Params, SessionRng};
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(3, &['a', 'b', 'c']).unwrap();
/// let mut a = Archive::new(&space, 5, &Params::TASK1);
/// let mut rng = SessionRng::seed_from_u64(0);
/// let mut c = space.first();
/// a.propose(&mut rng, &mut c); // the archive is empty: a uniform command
/// a.learn(&c, &Outcome { effect: 2, reward: 0.0, point: [0.0; 2] });
/// assert_eq!(a.command_of(2), Some(&c.symbols[..]));
/// a.propose(&mut rng, &mut c); // cell 2's command, one slot changed
/// assert_eq!(a.last_cell(), Some(2));
/// assert_eq!(a.reached(), [2]);
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Archive {
    core: Core<SymbolGenome>,
}

impl Archive {
    /// An empty archive for `space` and `num_effects` cells, mutating
    /// `params.k` slots and picking cells with `params.rarity`.
    pub fn new(space: &CommandSpace, num_effects: usize, params: &Params) -> Self {
        Archive {
            core: Core::new(
                SymbolGenome::new(space.sizes().collect(), params.k),
                num_effects,
                params.rarity,
            ),
        }
    }

    /// The command kept for cell `effect`, if it was reached.
    pub fn command_of(&self, effect: usize) -> Option<&[u8]> {
        self.core.command_of(effect)
    }

    /// The reached cells, in the order they were first reached.
    pub fn reached(&self) -> &[usize] {
        &self.core.reached
    }

    /// How many times cell `effect` was picked.
    pub fn times_chosen(&self, effect: usize) -> u64 {
        self.core.times_chosen(effect)
    }

    /// The cell picked for the last proposal (`None`: the archive was
    /// empty and the command uniform).
    pub fn last_cell(&self) -> Option<usize> {
        self.core.last_cell
    }
}

impl Learner for Archive {
    fn name(&self) -> &str {
        "archive"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        self.core.propose(rng, &mut command.symbols);
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        self.core.learn(&command.symbols, outcome);
    }
}

/// [`Archive`] over continuous commands: the same archive, a mutation adds
/// `N(0, sigma^2)` to every value in the unit coordinates of its range
/// ([`Params::sigma`], default 0.1; [`mutate_values`](super::mutation::mutate_values)).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ArchiveValues {
    core: Core<ValueGenome>,
}

impl ArchiveValues {
    /// An empty archive for `space` and `num_effects` cells, with
    /// `params.sigma` and `params.rarity`.
    pub fn new(space: &ValueSpace, num_effects: usize, params: &Params) -> Self {
        ArchiveValues {
            core: Core::new(
                ValueGenome {
                    space: space.clone(),
                    sigma: params.sigma,
                },
                num_effects,
                params.rarity,
            ),
        }
    }

    /// The values kept for cell `effect`, if it was reached.
    pub fn command_of(&self, effect: usize) -> Option<&[f64]> {
        self.core.command_of(effect)
    }

    /// The reached cells, in the order they were first reached.
    pub fn reached(&self) -> &[usize] {
        &self.core.reached
    }
}

impl ContinuousLearner for ArchiveValues {
    fn value_space(&self) -> Option<&ValueSpace> {
        Some(&self.core.genome.space)
    }

    fn name(&self) -> &str {
        "archive"
    }

    fn propose(&mut self, rng: &mut SessionRng, values: &mut Vec<f64>) {
        self.core.propose(rng, values);
    }

    fn learn(&mut self, values: &[f64], outcome: &Outcome) {
        self.core.learn(values, outcome);
    }

    /// The archive is no Gaussian: the mean and standard deviation of the
    /// slot's values over the reached cells' commands (the middle of the
    /// range and 0 while the archive is empty).
    fn slot_gaussian(&self, slot: usize) -> (f64, f64) {
        spread(
            self.core
                .reached
                .iter()
                .filter_map(|&e| self.core.command_of(e).map(|c| c[slot])),
            self.core.genome.space.range(slot),
        )
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

impl<G: Genome> Core<G> {
    /// Checks an archive read from a state.
    fn validate(&self) -> Result<(), String> {
        self.genome.validate()?;
        let n = self.genome.sizes().len();
        let (cells, reached) = (&self.cells, &self.reached);
        check_cells("an archive", n, cells, reached, self.last_cell, |e| {
            e.command.len()
        })
    }
}

kept_commands_state!(Archive "archive", ArchiveValues "archive_values");
