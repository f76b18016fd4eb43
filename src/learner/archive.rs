//! An archive of reached cells, Go-Explore style (after Ecoffet et al.
//! 2019, "Go-Explore: a new approach for hard-exploration problems",
//! arXiv 1901.10995): one command per reached cell; pick a cell, mutate
//! its command, execute it.

use super::mutation::{kept_commands, spread, Cells, Genome, Kept, SymbolGenome, ValueGenome};
use super::state::{LearnerState, StateShape};
use super::{draw_weighted, ContinuousLearner, Learner, Params};
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

impl<T> Kept<T> for Entry<T> {
    fn command(&self) -> &[T] {
        &self.command
    }
}

/// An archive of reached cells, Go-Explore style, over commands of
/// symbols ([`Archive`]) or of values ([`ArchiveValues`]).
///
/// The archive keeps one command per reached cell (the first that reached
/// it, replaced only by one with a higher reward). Each trial picks a
/// reached cell with weight `(1 + times picked)^(-rarity)` (one `f64`; one
/// integer when [`Params::rarity`] is 0) and proposes its command mutated
/// (docs/algorithms.md, "Archive of reached cells"); a uniform command
/// while the archive is empty.
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
    cells: Cells<Entry<G::Elem>>,
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
            cells: Cells::new(num_effects),
            rarity: params.rarity,
            last_cell: None,
        }
    }

    /// The reached cells, in the order they were first reached.
    pub fn reached(&self) -> &[usize] {
        &self.cells.order
    }

    /// The cell picked for the last proposal (`None`: the archive was
    /// empty and the command uniform).
    pub fn last_cell(&self) -> Option<usize> {
        self.last_cell
    }

    fn choose(&mut self, rng: &mut SessionRng) -> Option<usize> {
        let reached = &self.cells.order;
        if reached.is_empty() {
            return None;
        }
        let i = if self.rarity == 0.0 {
            rng.random_range(0..reached.len())
        } else {
            draw_weighted(reached.iter().map(|&e| self.cells.get(e).weight), rng)
        };
        Some(reached[i])
    }

    fn draw(&mut self, rng: &mut SessionRng, out: &mut Vec<G::Elem>) {
        self.last_cell = self.choose(rng);
        match self.last_cell {
            None => self.genome.random(rng, out),
            Some(e) => {
                let rarity = self.rarity;
                let entry = self.cells.cells[e].as_mut().expect("a reached cell");
                entry.chosen += 1;
                entry.weight = (1.0 + entry.chosen as f64).powf(-rarity);
                out.clear();
                out.extend_from_slice(&entry.command);
                self.genome.mutate(rng, out);
            }
        }
    }

    fn keep(&mut self, command: &[G::Elem], outcome: &Outcome) {
        let reward = outcome.reward;
        let first = || Entry {
            command: command.to_vec(),
            reward,
            chosen: 0,
            weight: 1.0,
        };
        self.cells.keep(outcome.effect, first, |entry| {
            if reward > entry.reward {
                entry.command.clear();
                entry.command.extend_from_slice(command);
                entry.reward = reward;
            }
        })
    }

    /// The command kept for cell `effect`, if it was reached.
    pub fn command_of(&self, effect: usize) -> Option<&[G::Elem]> {
        self.cells.command_of(effect)
    }

    /// How many times cell `effect` was picked.
    pub fn times_chosen(&self, effect: usize) -> u64 {
        (self.cells.cells.get(effect))
            .and_then(|c| c.as_ref())
            .map_or(0, |c| c.chosen)
    }

    /// Checks an archive read from a state.
    fn check(&self) -> Result<(), String> {
        self.genome.validate()?;
        let n = self.genome.sizes().len();
        self.cells.check("an archive", n, self.last_cell)
    }
}

kept_commands!(ArchiveOf "archive");
