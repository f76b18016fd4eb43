//! Archives of reached cells: Go-Explore style (after Ecoffet et al.
//! 2019, "Go-Explore: a new approach for hard-exploration problems",
//! arXiv 1901.10995), weighting cells by how often they were chosen or
//! reached, and MAP-Elites (after Mouret and Clune 2015, "Illuminating
//! search spaces by mapping elites", arXiv 1504.04909): one command per
//! reached cell; pick a cell, mutate its command, execute it.

use super::effort::{Effort, Effortful};
use super::mutation::{kept_commands, spread, Cells, Genome, Kept, SymbolGenome, ValueGenome};
use super::state::{ensure, LearnerState, StateShape};
use super::{draw_weighted, ContinuousLearner, Learner, Params};
use crate::command::{Command, ValueSpace};
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{de::DeserializeOwned, Deserialize, Serialize};

/// One reached cell: the command kept for it (its elite), the elite's
/// quality, and how many times the cell was counted (chosen or reached).
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Entry<T> {
    command: Vec<T>,
    /// The reward (archives) or the effort quality (MAP-Elites) of
    /// `command`.
    quality: f64,
    /// Times chosen ([`Chosen`]) or reached ([`Reached`]).
    count: u64,
    /// `(1 + count)^(-rarity)`.
    weight: f64,
}

impl<T> Kept<T> for Entry<T> {
    fn command(&self) -> &[T] {
        &self.command
    }
}

/// How an archive picks the cell whose command it mutates, and what makes
/// a command its cell's elite: [`Chosen`], [`Reached`] (the archives) or
/// [`Elites`] (MAP-Elites).
pub trait Variant: std::fmt::Debug + Clone + Send + Serialize + DeserializeOwned {
    /// Whether a cell's count is of the times it was chosen (`Some(true)`),
    /// reached (`Some(false)`), or not kept: cells are picked uniformly
    /// (`None`).
    const COUNTS_CHOSEN: Option<bool>;
    /// The variant, measuring no effort yet.
    fn new() -> Self;
    /// The quality of `command`, which ended in `outcome`: a better one
    /// replaces its cell's elite.
    fn quality<T>(&self, command: &[T], outcome: &Outcome) -> f64
    where
        [T]: Effortful;
    /// Whether the next proposal is a uniform command even though some
    /// cell was reached (the initial random commands).
    fn uniform_next(&mut self) -> bool {
        false
    }
    /// The cells a pick is among and their weights, when they are those
    /// of the start of a batch ([`Reached`]); `None`: the archive as it is.
    fn frozen(&self) -> Option<(&[usize], &[f64])> {
        None
    }
    /// After each trial learned: the reached cells in order, and the
    /// weight of each.
    fn learned(&mut self, _order: &[usize], _weight: impl Fn(usize) -> f64) {}
    /// Checks a variant read from a state.
    fn check(&self) -> Result<(), String> {
        Ok(())
    }
}

/// The archive that weights a cell by how often it was chosen.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct Chosen;

/// The batch of [`Reached`]: the trials whose picks share the archive
/// (its cells and their weights) of the batch's start, as Go-Explore's
/// parallel workers do (docs/algorithms.md, "Two archives").
pub const REACHED_BATCH: usize = 64;

/// The archive that weights a cell by how often it was reached, its
/// picks in batches ([`REACHED_BATCH`] trials by default): every pick of
/// a batch is among the cells, with the weights, of the batch's start.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Reached {
    /// The trials of a batch.
    batch: usize,
    /// The trials learned.
    learned: u64,
    /// The reached cells at the start of the batch, in order.
    cells: Vec<usize>,
    /// Their weights then.
    weights: Vec<f64>,
}

impl Variant for Chosen {
    const COUNTS_CHOSEN: Option<bool> = Some(true);
    fn new() -> Self {
        Chosen
    }
    fn quality<T>(&self, _: &[T], outcome: &Outcome) -> f64 {
        outcome.reward
    }
}

impl Variant for Reached {
    const COUNTS_CHOSEN: Option<bool> = Some(false);
    fn new() -> Self {
        Reached {
            batch: REACHED_BATCH,
            learned: 0,
            cells: Vec::new(),
            weights: Vec::new(),
        }
    }
    fn quality<T>(&self, _: &[T], outcome: &Outcome) -> f64 {
        outcome.reward
    }
    fn frozen(&self) -> Option<(&[usize], &[f64])> {
        Some((&self.cells, &self.weights))
    }
    fn learned(&mut self, order: &[usize], weight: impl Fn(usize) -> f64) {
        self.learned += 1;
        if self.learned % self.batch as u64 == 0 {
            self.cells = order.to_vec();
            self.weights = order.iter().map(|&e| weight(e)).collect();
        }
    }
    fn check(&self) -> Result<(), String> {
        let ok = self.batch >= 1 && self.cells.len() == self.weights.len();
        let weights = self.weights.iter().all(|w| w.is_finite() && *w > 0.0);
        ensure(ok && weights, || {
            format!(
                "a reached archive's batch of {} trials, {} cells and {} weights",
                self.batch,
                self.cells.len(),
                self.weights.len()
            )
        })
    }
}

/// The random commands MAP-Elites proposes before it mutates elites.
pub const MAP_ELITES_INITIAL: u32 = 10;

/// MAP-Elites' elites: by effort quality, after
/// [`MAP_ELITES_INITIAL`] uniform commands.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Elites {
    /// The effort of the scene's commands (none: every command has the
    /// quality 0, and each cell keeps its first command).
    effort: Option<Effort>,
    /// The uniform commands still to propose.
    initial: u32,
}

impl Variant for Elites {
    const COUNTS_CHOSEN: Option<bool> = None;
    fn new() -> Self {
        Elites {
            effort: None,
            initial: MAP_ELITES_INITIAL,
        }
    }
    fn quality<T>(&self, command: &[T], _: &Outcome) -> f64
    where
        [T]: Effortful,
    {
        let q = self.effort.as_ref().and_then(|e| e.quality(command));
        q.unwrap_or(0.0)
    }
    fn uniform_next(&mut self) -> bool {
        let first = self.initial > 0;
        self.initial = self.initial.saturating_sub(1);
        first
    }
    fn check(&self) -> Result<(), String> {
        self.effort.as_ref().map_or(Ok(()), Effort::check)
    }
}

/// An archive of reached cells over commands of symbols ([`Archive`],
/// [`ArchiveReached`], [`MapElites`]) or of values (their `...Values`
/// twins), its [`Variant`] `V` saying how cells are picked and elites
/// kept.
///
/// The archive keeps one command per reached cell (the first that reached
/// it, replaced only by one of a higher quality: the reward for the
/// archives, the effort quality for MAP-Elites). Each trial picks a
/// reached cell, with weight `(1 + n)^(-rarity)`, `n` the times it was
/// chosen ([`Chosen`]) or reached ([`Reached`]) (one `f64`; one integer
/// when [`Params::rarity`] is 0), or uniformly (MAP-Elites: one integer),
/// and proposes its command mutated (docs/algorithms.md, "Archive of
/// reached cells", "MAP-Elites"); a uniform command while the archive is
/// empty, and for MAP-Elites' first [`MAP_ELITES_INITIAL`] trials.
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
pub struct ArchiveOf<G: Genome, V: Variant = Chosen> {
    genome: G,
    cells: Cells<Entry<G::Elem>>,
    rarity: f64,
    /// The cell chosen for the last proposal (`None`: a uniform command).
    last_cell: Option<usize>,
    variant: V,
}

/// The archive over commands of symbols, weighting cells by the times
/// they were chosen (`archive`).
pub type Archive = ArchiveOf<SymbolGenome>;

/// [`Archive`] over continuous commands: a mutation adds `N(0, sigma^2)`
/// to every value in the unit coordinates of its range.
pub type ArchiveValues = ArchiveOf<ValueGenome>;

/// The archive weighting cells by the times they were reached, over any
/// kind of command (`archive_reached`).
pub type ArchiveReachedOf<G> = ArchiveOf<G, Reached>;

/// [`ArchiveReachedOf`] over commands of symbols.
pub type ArchiveReached = ArchiveReachedOf<SymbolGenome>;

/// [`ArchiveReachedOf`] over continuous commands.
pub type ArchiveReachedValues = ArchiveReachedOf<ValueGenome>;

/// MAP-Elites over any kind of command (`map_elites`): cells picked
/// uniformly, elites by effort quality ([`Effort`]).
///
/// ```
/// use e3d::learner::{Effort, MapElites, MAP_ELITES_INITIAL};
/// use e3d::rand::SeedableRng;
/// use e3d::{Learner, Outcome, Params, SessionRng};
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(3, &['-', '0', '+']).unwrap();
/// let effort = Effort::Symbols(vec![vec![1.0, 0.0, 1.0]; 3]); // |torque| 1 or 0
/// let mut m = MapElites::new(&space, 4, &Params::TASK1).with_effort(Some(effort));
/// let o = Outcome { effect: 1, reward: 0.0, point: [0.0; 2] };
/// m.learn(&space.parse("+-+").unwrap(), &o);
/// m.learn(&space.parse("+0-").unwrap(), &o); // less effort: the new elite
/// m.learn(&space.parse("+--").unwrap(), &o); // more: ignored
/// assert_eq!(m.command_of(1), Some(&space.parse("+0-").unwrap().symbols[..]));
/// assert_eq!(m.elite_quality(1), Some(1.0 - 2.0 / 3.0));
/// let mut rng = SessionRng::seed_from_u64(0);
/// let mut c = space.first();
/// for _ in 0..MAP_ELITES_INITIAL {
///     m.propose(&mut rng, &mut c);
///     assert_eq!(m.last_cell(), None); // the initial random commands
/// }
/// m.propose(&mut rng, &mut c);
/// assert_eq!(m.last_cell(), Some(1));
/// ```
pub type MapElitesOf<G> = ArchiveOf<G, Elites>;

/// [`MapElitesOf`] over commands of symbols.
pub type MapElites = MapElitesOf<SymbolGenome>;

/// [`MapElitesOf`] over continuous commands.
pub type MapElitesValues = MapElitesOf<ValueGenome>;

impl<G: Genome> ArchiveReachedOf<G> {
    /// The same archive, its picks in batches of `batch` trials (at least
    /// 1: every pick sees the archive as it is; default
    /// [`REACHED_BATCH`]).
    pub fn with_batch(mut self, batch: usize) -> Self {
        self.variant.batch = batch.max(1);
        self
    }
}

impl<G: Genome> MapElitesOf<G> {
    /// The same MAP-Elites, its elites kept by the effort quality of
    /// `effort` (the scene's: [`Effort::of_scene`]); `None`: every command
    /// has the quality 0 (each cell keeps its first command).
    pub fn with_effort(mut self, effort: Option<Effort>) -> Self {
        self.variant.effort = effort;
        self
    }
}

impl<G: Genome, V: Variant> ArchiveOf<G, V>
where
    [G::Elem]: Effortful,
{
    /// An empty archive for `space` and `num_effects` cells, mutating
    /// `params.k` slots (symbols) or with `params.sigma` (values), and
    /// picking cells with `params.rarity` (not MAP-Elites: uniformly).
    pub fn new(space: &G::Space, num_effects: usize, params: &Params) -> Self {
        ArchiveOf {
            genome: G::new(space, params),
            cells: Cells::new(num_effects),
            rarity: params.rarity,
            last_cell: None,
            variant: V::new(),
        }
    }

    /// The reached cells, in the order they were first reached.
    pub fn reached(&self) -> &[usize] {
        &self.cells.order
    }

    /// The cell picked for the last proposal (`None`: a uniform command).
    pub fn last_cell(&self) -> Option<usize> {
        self.last_cell
    }

    fn choose(&mut self, rng: &mut SessionRng) -> Option<usize> {
        if self.variant.uniform_next() {
            return None;
        }
        let (reached, frozen) = match self.variant.frozen() {
            Some((cells, weights)) => (cells, Some(weights)),
            None => (&self.cells.order[..], None),
        };
        if reached.is_empty() {
            return None;
        }
        let i = if self.rarity == 0.0 || V::COUNTS_CHOSEN.is_none() {
            rng.random_range(0..reached.len())
        } else if let Some(weights) = frozen {
            draw_weighted(weights.iter().copied(), rng)
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
                if V::COUNTS_CHOSEN == Some(true) {
                    entry.count += 1;
                    entry.weight = (1.0 + entry.count as f64).powf(-rarity);
                }
                out.clear();
                out.extend_from_slice(&entry.command);
                self.genome.mutate(rng, out);
            }
        }
    }

    fn keep(&mut self, command: &[G::Elem], outcome: &Outcome) {
        let quality = self.variant.quality(command, outcome);
        let reached = V::COUNTS_CHOSEN == Some(false);
        let rarity = self.rarity;
        let first = || Entry {
            command: command.to_vec(),
            quality,
            count: reached as u64,
            weight: if reached { 2f64.powf(-rarity) } else { 1.0 },
        };
        self.cells.keep(outcome.effect, first, |entry| {
            if reached {
                entry.count += 1;
                entry.weight = (1.0 + entry.count as f64).powf(-rarity);
            }
            if quality > entry.quality {
                entry.command.clear();
                entry.command.extend_from_slice(command);
                entry.quality = quality;
            }
        });
        let cells = &self.cells;
        (self.variant).learned(&cells.order, |e| cells.get(e).weight);
    }

    /// The command kept for cell `effect` (its elite), if it was reached.
    pub fn command_of(&self, effect: usize) -> Option<&[G::Elem]> {
        self.cells.command_of(effect)
    }

    /// The quality of cell `effect`'s elite (the reward for the archives,
    /// the effort quality for MAP-Elites), if it was reached.
    pub fn elite_quality(&self, effect: usize) -> Option<f64> {
        let cell = self.cells.cells.get(effect)?.as_ref()?;
        Some(cell.quality)
    }

    /// How many times cell `effect` was picked ([`Archive`]) or reached
    /// ([`ArchiveReached`]); 0 for MAP-Elites, which keeps no count.
    pub fn times_chosen(&self, effect: usize) -> u64 {
        (self.cells.cells.get(effect))
            .and_then(|c| c.as_ref())
            .map_or(0, |c| c.count)
    }

    /// Checks an archive read from a state.
    fn check(&self) -> Result<(), String> {
        self.genome.validate()?;
        self.variant.check()?;
        if let Some((frozen, _)) = self.variant.frozen() {
            let reached = |e: &usize| self.cells.cells.get(*e).is_some_and(|c| c.is_some());
            ensure(frozen.iter().all(reached), || {
                format!("a batch's cells {frozen:?}, not all reached")
            })?;
        }
        let n = self.genome.sizes().len();
        self.cells.check("an archive", n, self.last_cell)
    }
}

kept_commands!(ArchiveOf "archive");
kept_commands!(ArchiveReachedOf "archive_reached");
kept_commands!(MapElitesOf "map_elites");
