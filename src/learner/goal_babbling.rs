//! Goal babbling with a nearest-neighbour inverse model (after Forestier,
//! Mollard and Oudeyer 2017, "Intrinsically Motivated Goal Exploration
//! Processes with Automatic Curriculum Learning", arXiv 1708.02190, and
//! explauto): sample a goal effect, take the known command whose outcome
//! is nearest to it, mutate it, execute it, remember what it reached.

use super::mutation::{kept_commands, spread, Cells, Genome, Kept, SymbolGenome, ValueGenome};
use super::state::{ensure, LearnerState, StateShape};
use super::{draw_weighted, ContinuousLearner, Learner, Params};
use crate::command::{Command, ValueSpace};
use crate::rng::SessionRng;
use crate::world::Outcome;
use rand::RngExt;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// Goals are drawn in the box of the known outcomes widened by this share
/// of its size on each side, so that some goals lie beyond what was
/// reached and pull the search outwards.
pub const GOAL_MARGIN: f64 = 0.1;

/// Learning-progress goal selection splits the goal box into
/// `PROGRESS_BINS x PROGRESS_BINS` regions.
pub const PROGRESS_BINS: usize = 4;

/// The competences a region keeps for its learning progress (the older
/// half against the newer half).
pub const PROGRESS_WINDOW: usize = 20;

/// A reached cell: where its command ended, and the command.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct Known<T> {
    point: [f64; 2],
    command: Vec<T>,
}

impl<T> Kept<T> for Known<T> {
    fn command(&self) -> &[T] {
        &self.command
    }
}

/// Goal babbling with a nearest-neighbour inverse model, over commands of
/// symbols ([`GoalBabbling`]) or of values ([`GoalBabblingValues`]).
///
/// The effect space is the plane of the terminal point: a cell's known
/// outcome is where the command kept for it ended (on a grid, the cell's
/// centre). Each trial:
///
/// ```text
/// if no cell is known: a uniform command
/// else:
///     box <- the box of the known outcomes, widened by 10% of its size on each side
///     goal g ~ uniform(box)        (or by learning progress, below)
///     c <- the known cell whose outcome is nearest to g (ties: the first reached)
///     propose the command of c with k slots resampled (Params::k)
/// after the trial, ending in cell e at point x:
///     cell e's command <- this command, its outcome <- x (the most recent one)
/// ```
///
/// With probability [`Params::goal_progress`], a goal is drawn in a
/// region of the box chosen by learning progress (explauto's "discretized
/// progress"; docs/algorithms.md, "Goal babbling"). Its draws: two `f64`
/// per goal (one more, and one for the region, by learning progress),
/// then the mutation's.
///
/// ```
/// use e3d::learner::GoalBabbling;
/// use e3d::rand::SeedableRng;
/// use e3d::{Command, Learner, Outcome, Params, SessionRng};
/// use e3d::command::CommandSpace;
/// let space = CommandSpace::repeat(3, &['a', 'b', 'c']).unwrap();
/// let mut g = GoalBabbling::new(&space, 4, &Params::TASK1);
/// g.learn(&Command::new(vec![0, 0, 0]), &Outcome { effect: 1, reward: 0.0, point: [0.0, 0.0] });
/// g.learn(&Command::new(vec![2, 2, 2]), &Outcome { effect: 3, reward: 0.0, point: [4.0, 0.0] });
/// assert_eq!(g.nearest([1.0, 0.0]), Some(1));
/// assert_eq!(g.nearest([3.0, 1.0]), Some(3));
/// let mut c = space.first();
/// g.propose(&mut SessionRng::seed_from_u64(1), &mut c);
/// let parent = g.last_parent().unwrap();
/// assert_eq!(g.nearest(g.last_goal().unwrap()), Some(parent));
/// ```
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(bound = "")]
pub struct GoalBabblingOf<G: Genome> {
    genome: G,
    cells: Cells<Known<G::Elem>>,
    lo: [f64; 2],
    hi: [f64; 2],
    goal_progress: f64,
    /// Per region, the last competences `-|goal - reached|`.
    competence: Vec<VecDeque<f64>>,
    last_goal: Option<[f64; 2]>,
    last_region: usize,
    last_parent: Option<usize>,
}

/// Goal babbling over commands of symbols.
pub type GoalBabbling = GoalBabblingOf<SymbolGenome>;

/// [`GoalBabbling`] over continuous commands: a mutation adds `N(0,
/// sigma^2)` to every value in the unit coordinates of its range.
pub type GoalBabblingValues = GoalBabblingOf<ValueGenome>;

impl<G: Genome> GoalBabblingOf<G> {
    /// A learner that knows nothing yet, for `space` and `num_effects`
    /// cells, mutating `params.k` slots (symbols) or with `params.sigma`
    /// (values), with `params.goal_progress`.
    pub fn new(space: &G::Space, num_effects: usize, params: &Params) -> Self {
        GoalBabblingOf {
            genome: G::new(space, params),
            cells: Cells::new(num_effects),
            lo: [f64::INFINITY; 2],
            hi: [f64::NEG_INFINITY; 2],
            goal_progress: params.goal_progress,
            competence: vec![VecDeque::new(); PROGRESS_BINS * PROGRESS_BINS],
            last_goal: None,
            last_region: 0,
            last_parent: None,
        }
    }

    /// A region's learning progress: `|mean of the newer half - mean of
    /// the older half|` of its last [`PROGRESS_WINDOW`] competences (0
    /// with fewer than 2).
    fn progress(&self, region: usize) -> f64 {
        let c = &self.competence[region];
        if c.len() < 2 {
            return 0.0;
        }
        let half = c.len() / 2;
        let old: f64 = c.iter().take(half).sum::<f64>() / half as f64;
        let new: f64 = c.iter().skip(half).sum::<f64>() / (c.len() - half) as f64;
        (new - old).abs()
    }

    fn sample_goal(&mut self, rng: &mut SessionRng) -> [f64; 2] {
        // the goal box: the known outcomes' box widened by GOAL_MARGIN
        let (mut lo, mut hi) = (self.lo, self.hi);
        for a in 0..2 {
            let m = GOAL_MARGIN * (hi[a] - lo[a]);
            lo[a] -= m;
            hi[a] += m;
        }
        let (mut glo, mut ghi) = (lo, hi);
        if self.goal_progress > 0.0 && rng.random::<f64>() < self.goal_progress {
            let lp: Vec<f64> = (0..self.competence.len())
                .map(|r| self.progress(r))
                .collect();
            let total: f64 = lp.iter().sum();
            let region = if total > 0.0 {
                draw_weighted(lp.iter().copied(), rng)
            } else {
                rng.random_range(0..lp.len())
            };
            let (bx, by) = (region % PROGRESS_BINS, region / PROGRESS_BINS);
            for (a, b) in [bx, by].into_iter().enumerate() {
                let w = (hi[a] - lo[a]) / PROGRESS_BINS as f64;
                glo[a] = lo[a] + b as f64 * w;
                ghi[a] = glo[a] + w;
            }
        }
        let gx = glo[0] + (ghi[0] - glo[0]) * rng.random::<f64>();
        let gy = glo[1] + (ghi[1] - glo[1]) * rng.random::<f64>();
        let bin = |a: usize, p: f64| {
            let w = hi[a] - lo[a];
            let b = ((p - lo[a]) / w * PROGRESS_BINS as f64) as usize;
            if w > 0.0 {
                b.min(PROGRESS_BINS - 1)
            } else {
                0
            }
        };
        self.last_region = bin(1, gy) * PROGRESS_BINS + bin(0, gx);
        [gx, gy]
    }

    /// The command kept for cell `effect` (the last that reached it).
    pub fn command_of(&self, effect: usize) -> Option<&[G::Elem]> {
        self.cells.command_of(effect)
    }

    /// The goal of the last proposal (`None` until a cell is known, and
    /// after a `learn`).
    pub fn last_goal(&self) -> Option<[f64; 2]> {
        self.last_goal
    }

    /// The cell whose command the last proposal mutated.
    pub fn last_parent(&self) -> Option<usize> {
        self.last_parent
    }

    /// The reached cells, in the order they were first reached.
    pub fn known(&self) -> &[usize] {
        &self.cells.order
    }

    /// The reached cell whose known outcome is nearest to `goal`
    /// (Euclidean; ties: the first reached); `None` only when no cell is
    /// known (distances that overflow to infinity still rank, NaN last).
    pub fn nearest(&self, goal: [f64; 2]) -> Option<usize> {
        let mut best = None;
        let mut best_d = f64::NAN;
        for &e in &self.cells.order {
            let p = self.cells.get(e).point;
            let d = (p[0] - goal[0]).powi(2) + (p[1] - goal[1]).powi(2);
            if best.is_none() || d.total_cmp(&best_d).is_lt() {
                best_d = d;
                best = Some(e);
            }
        }
        best
    }

    fn draw(&mut self, rng: &mut SessionRng, out: &mut Vec<G::Elem>) {
        if self.cells.order.is_empty() {
            self.last_goal = None;
            self.last_parent = None;
            self.genome.random(rng, out);
            return;
        }
        let goal = self.sample_goal(rng);
        let parent = self.nearest(goal).expect("a known cell");
        self.last_goal = Some(goal);
        self.last_parent = Some(parent);
        out.clear();
        out.extend_from_slice(&self.cells.get(parent).command);
        self.genome.mutate(rng, out);
    }

    fn keep(&mut self, command: &[G::Elem], outcome: &Outcome) {
        let p = outcome.point;
        if let Some(goal) = self.last_goal.take() {
            if self.goal_progress > 0.0 {
                let d = ((p[0] - goal[0]).powi(2) + (p[1] - goal[1]).powi(2)).sqrt();
                let c = &mut self.competence[self.last_region];
                if c.len() == PROGRESS_WINDOW {
                    c.pop_front();
                }
                c.push_back(-d);
            }
        }
        let first = || Known {
            point: p,
            command: command.to_vec(),
        };
        self.cells.keep(outcome.effect, first, |k| {
            k.point = p;
            k.command.clear();
            k.command.extend_from_slice(command);
        });
        for (a, &x) in p.iter().enumerate() {
            self.lo[a] = self.lo[a].min(x);
            self.hi[a] = self.hi[a].max(x);
        }
    }

    /// Checks goal babbling read from a state.
    fn check(&self) -> Result<(), String> {
        self.genome.validate()?;
        // a point that is not a number reaches no goal: a proposal would
        // find no nearest known cell
        let finite = |p: &[f64; 2]| p.iter().all(|x| x.is_finite());
        let numbers = self.cells.cells.iter().flatten().all(|k| finite(&k.point))
            && self.last_goal.as_ref().is_none_or(finite)
            && self.competence.iter().flatten().all(|x| x.is_finite());
        ensure(numbers, || {
            "goal babbling with a point, goal or competence that is not a finite number".into()
        })?;
        let n = self.genome.sizes().len();
        self.cells.check("goal babbling", n, self.last_parent)?;
        ensure(
            self.competence.len() == PROGRESS_BINS * PROGRESS_BINS
                && self.last_region < self.competence.len(),
            || format!("goal babbling of {} regions", self.competence.len()),
        )
    }
}

kept_commands!(GoalBabblingOf "goal_babbling");
