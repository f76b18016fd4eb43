//! An archive of reached cells, Go-Explore style (after Ecoffet et al.
//! 2019, "Go-Explore: a new approach for hard-exploration problems",
//! arXiv 1901.10995): one command per reached cell; pick a cell, mutate
//! its command, execute it.

use super::mutation::{check_cells, kept_commands, spread, Genome, SymbolGenome, ValueGenome};
use super::state::{LearnerState, StateShape};
use super::{ContinuousLearner, Learner, Params};
use crate::command::{Command, ValueSpace};
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

/// An archive of reached cells, Go-Explore style, over commands of
/// symbols ([`Archive`]) or of values ([`ArchiveValues`]).
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
/// Over values, a mutation adds `N(0, sigma^2)` to every value in the unit
/// coordinates of its range ([`Params::sigma`], default 0.1;
/// [`mutate_values`](super::mutation::mutate_values)).
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
#[serde(bound = "")]
pub struct ArchiveOf<G: Genome> {
    genome: G,
    cells: Vec<Option<Entry<G::Elem>>>,
    /// The reached cells, in the order they were first reached.
    reached: Vec<usize>,
    rarity: f64,
    /// The cell chosen for the last proposal (`None`: a uniform command).
    last_cell: Option<usize>,
}

/// The archive over commands of symbols.
pub type Archive = ArchiveOf<SymbolGenome>;

/// [`Archive`] over continuous commands: a mutation adds `N(0, sigma^2)`
/// to every value in the unit coordinates of its range.
pub type ArchiveValues = ArchiveOf<ValueGenome>;

impl<G: Genome> ArchiveOf<G> {
    /// An empty archive for `space` and `num_effects` cells, mutating
    /// `params.k` slots (symbols) or with `params.sigma` (values), and
    /// picking cells with `params.rarity`.
    pub fn new(space: &G::Space, num_effects: usize, params: &Params) -> Self {
        ArchiveOf {
            genome: G::new(space, params),
            cells: vec![None; num_effects],
            reached: Vec::new(),
            rarity: params.rarity,
            last_cell: None,
        }
    }

    /// The reached cells, in the order they were first reached.
    pub fn reached(&self) -> &[usize] {
        &self.reached
    }

    /// The cell picked for the last proposal (`None`: the archive was
    /// empty and the command uniform).
    pub fn last_cell(&self) -> Option<usize> {
        self.last_cell
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

    fn draw(&mut self, rng: &mut SessionRng, out: &mut Vec<G::Elem>) {
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

    fn keep(&mut self, command: &[G::Elem], outcome: &Outcome) {
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

    /// The command kept for cell `effect`, if it was reached.
    pub fn command_of(&self, effect: usize) -> Option<&[G::Elem]> {
        self.cells
            .get(effect)?
            .as_ref()
            .map(|c| c.command.as_slice())
    }

    /// How many times cell `effect` was picked.
    pub fn times_chosen(&self, effect: usize) -> u64 {
        self.cells
            .get(effect)
            .and_then(|c| c.as_ref())
            .map_or(0, |c| c.chosen)
    }

    /// Checks an archive read from a state.
    fn check(&self) -> Result<(), String> {
        self.genome.validate()?;
        let n = self.genome.sizes().len();
        let (cells, reached) = (&self.cells, &self.reached);
        check_cells("an archive", n, cells, reached, self.last_cell, |e| {
            e.command.len()
        })
    }
}

kept_commands!(ArchiveOf "archive" reached);
