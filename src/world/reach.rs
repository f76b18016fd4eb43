//! What a whole command space reaches: per-cell counts and the rule that
//! picks arm7's rewarded cell (docs/canonical-scenes.md, section 3).

use super::OutcomeTable;
use crate::effect::EffectGrid;

/// The cell picked by [`farthest_reached_cell`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FarthestCell {
    /// Row of the cell (row 0 at the top).
    pub row: usize,
    /// Column of the cell.
    pub col: usize,
    /// The effect index `row * cols + col`.
    pub effect: usize,
    /// Distance in metres from the reference point to the cell's centre.
    pub distance: f64,
    /// How many commands end in the cell.
    pub commands: u64,
    /// How many cells are reached by at least one command.
    pub reached_cells: usize,
}

/// The rule of docs/canonical-scenes.md for a hard-to-reach reward cell: among the cells
/// reached by at least one command of `table`, the one whose centre is
/// farthest from `from`; ties go to the cell reached by the fewest
/// commands, then to the lowest index. `None` if the table is empty.
///
/// ```
/// use e3d::world::farthest_reached_cell;
/// use e3d::{OutcomeTable, Scene};
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let table = OutcomeTable::build(&mut scene.build()).unwrap();
/// let c = farthest_reached_cell(&table, &scene.effect_grid(), [0.5, 2.5]).unwrap();
/// assert_eq!((c.row, c.col), (2, 5));
/// ```
pub fn farthest_reached_cell(
    table: &OutcomeTable,
    grid: &EffectGrid,
    from: [f64; 2],
) -> Option<FarthestCell> {
    let counts = table.effect_counts();
    let reached_cells = counts.iter().filter(|&&c| c > 0).count();
    let mut best: Option<FarthestCell> = None;
    for (e, &n) in counts.iter().enumerate() {
        if n == 0 {
            continue;
        }
        let (row, col) = (e / grid.cols, e % grid.cols);
        let c = grid.center(row, col);
        let distance = (c[0] - from[0]).hypot(c[1] - from[1]);
        let better = match &best {
            None => true,
            // cell centres sit on a lattice: distances of equal cells agree
            // to far better than 1e-9 m
            Some(b) if (distance - b.distance).abs() > 1e-9 => distance > b.distance,
            // a tie: fewer commands, then (by the scan order) the lower index
            Some(b) => n < b.commands,
        };
        if better {
            best = Some(FarthestCell {
                row,
                col,
                effect: e,
                distance,
                commands: n,
                reached_cells,
            });
        }
    }
    best
}

/// What a sample of commands reaches: the cheap estimate of
/// `e3d scene check` (see [`sample_reach`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ReachSample {
    /// The commands executed (with repeats, unless `exhaustive`).
    pub samples: u64,
    /// Whether every command of the space was executed once (the space
    /// holds no more commands than were asked for): the counts are exact.
    pub exhaustive: bool,
    /// Per effect, how many of the executed commands ended in it.
    pub counts: Vec<u64>,
    /// Seconds the executions took (one thread).
    pub seconds: f64,
}

impl ReachSample {
    /// How many cells at least one executed command reached.
    pub fn reached_cells(&self) -> usize {
        self.counts.iter().filter(|&&c| c > 0).count()
    }

    /// How many executed commands ended in one of `effects`.
    pub fn hits(&self, effects: &[usize]) -> u64 {
        effects.iter().filter_map(|&e| self.counts.get(e)).sum()
    }
}

/// Executes `samples` commands of `scene` drawn uniformly at random (each
/// slot's symbol independently, so commands may repeat; seeded by `seed`
/// with [`SessionRng`](crate::SessionRng)) and counts the cells they end
/// in. A space of at most `samples` commands is executed whole instead,
/// each command once, and the counts are exact. Commands are executed in
/// batches of 32 (the [`World::execute_batch`](crate::World::execute_batch)
/// of the scene's world), on this thread.
///
/// ```
/// use e3d::world::sample_reach;
/// use e3d::Scene;
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let s = sample_reach(&scene, 200, 0).unwrap();
/// assert_eq!((s.samples, s.exhaustive), (200, false));
/// assert_eq!(s.counts.iter().sum::<u64>(), 200);
/// assert!(s.reached_cells() > 1 && s.reached_cells() <= 18);
/// ```
pub fn sample_reach(
    scene: &crate::Scene,
    samples: u64,
    seed: u64,
) -> Result<ReachSample, crate::WorldError> {
    sample_reach_with(scene, samples, seed, &crate::world::Control::default())
}

/// [`sample_reach`] under `control`: told of `k` more commands executed
/// after each batch (of [`ReachSample::samples`] in all: `samples`, or
/// the size of a space that holds no more), asked before each batch
/// whether to stop. The sample is the same.
pub fn sample_reach_with(
    scene: &crate::Scene,
    samples: u64,
    seed: u64,
    control: &crate::world::Control<'_>,
) -> Result<ReachSample, crate::WorldError> {
    use crate::ContinuousLearner;
    use rand::SeedableRng;
    let space = scene.command_space();
    let continuous = scene.as_continuous();
    let exhaustive = continuous.is_none() && space.num_commands().is_some_and(|n| n <= samples);
    let total = if exhaustive {
        space.num_commands().unwrap_or(0)
    } else {
        samples
    };
    let mut rng = crate::SessionRng::seed_from_u64(seed);
    let sizes: Vec<usize> = space.sizes().collect();
    // the results of the commands from the `done`-th on: a batch of 32,
    // or one continuous command drawn by the uniform sampler
    // ([`UniformValues`](crate::learner::UniformValues)) on live physics
    type Out = Vec<Result<crate::Outcome, crate::WorldError>>;
    type Next<'a> = Box<dyn FnMut(u64, &mut Out) + 'a>;
    let mut next: Next = match continuous {
        Some(c) => {
            let (mut world, mut v) = (c.physics().world(1), Vec::new());
            let mut sampler = crate::learner::UniformValues::new(c.values());
            Box::new(move |_, out| {
                sampler.propose(&mut rng, &mut v);
                out.push(world.execute_values(&v));
            })
        }
        None => {
            let (mut world, mut batch) = (scene.build(), Vec::with_capacity(32));
            Box::new(move |done, out| {
                batch.clear();
                while batch.len() < 32 && done + (batch.len() as u64) < total {
                    let k = done + batch.len() as u64;
                    batch.push(match exhaustive {
                        true => space.command_at(k),
                        false => draw(&sizes, &mut rng),
                    });
                }
                world.execute_batch(&batch, out);
            })
        }
    };
    let mut counts = vec![0u64; scene.num_effects()];
    let start = std::time::Instant::now();
    let (mut out, mut done) = (Vec::with_capacity(32), 0u64);
    while done < total {
        control.check()?;
        out.clear();
        next(done, &mut out);
        let k = out.len() as u64;
        for r in out.drain(..) {
            counts[r?.effect] += 1;
        }
        done += k;
        (control.progress)(k);
    }
    Ok(ReachSample {
        samples: total,
        exhaustive,
        counts,
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// A command of slots of `sizes` symbols, each drawn uniformly with `rng`.
pub(super) fn draw(sizes: &[usize], rng: &mut crate::SessionRng) -> crate::Command {
    use rand::RngExt;
    let symbols = sizes.iter().map(|&k| rng.random_range(0..k) as u8);
    crate::Command::new(symbols.collect())
}
