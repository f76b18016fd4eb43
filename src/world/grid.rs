//! The grid world: the paper's degenerate kinematic scene.

use super::{Episodic, Outcome, World, WorldError, WorldState};
use crate::command::{Command, CommandSpace};
use crate::effect::EffectGrid;
use crate::rng::SessionRng;
use crate::scene::{Action, GridSpec, Scene, WorldSpec};
use rand::RngExt;

/// A grid world built from a scene: precomputed transitions, so executing a
/// command is `n` table look-ups.
#[derive(Debug, Clone)]
pub struct GridWorld {
    space: CommandSpace,
    grid: EffectGrid,
    start: usize,
    /// `next[kind * cells + cell]`: the cell after a move of kind `kind`
    /// (see [`MOVES`]) from `cell`.
    next: Vec<u32>,
    /// `kind[slot_offset[slot] + symbol]`: the move kind of each symbol.
    kind: Vec<u8>,
    slot_offset: Vec<usize>,
    reward: Vec<f64>,
    /// The start contexts: rows and columns (inclusive) of each.
    contexts: Vec<((usize, usize), (usize, usize))>,
}

/// The one-cell moves `(drow, dcol)` a grid knows: stay, E, S, W, N.
const MOVES: [(i32, i32); 5] = [(0, 0), (0, 1), (1, 0), (0, -1), (-1, 0)];

impl GridWorld {
    /// The world of a grid scene (`None` for a physics scene).
    /// Memory: 5 transitions per cell, whatever the number of slots.
    pub fn from_scene(scene: &Scene) -> Option<GridWorld> {
        match &scene.spec().world {
            WorldSpec::Grid(g) => Some(Self::of(scene, g)),
            WorldSpec::Physics(_) => None,
        }
    }

    /// The world of `scene`, whose world is the grid `spec`.
    pub(crate) fn of(scene: &Scene, spec: &GridSpec) -> GridWorld {
        let space = scene.command_space();
        let cells = spec.rows * spec.cols;
        let mut walls: Vec<(usize, usize)> = spec
            .walls
            .iter()
            .flat_map(|&(a, b)| {
                let (a, b) = (a.0 * spec.cols + a.1, b.0 * spec.cols + b.1);
                [(a, b), (b, a)]
            })
            .collect();
        walls.sort_unstable();
        let mut next = Vec::with_capacity(MOVES.len() * cells);
        for (dr, dc) in MOVES {
            for cell in 0..cells {
                let (r, c) = (cell / spec.cols, cell % spec.cols);
                let (nr, nc) = (r as i64 + dr as i64, c as i64 + dc as i64);
                let inside = nr >= 0 && nc >= 0 && nr < spec.rows as i64 && nc < spec.cols as i64;
                let to = if inside {
                    nr as usize * spec.cols + nc as usize
                } else {
                    cell
                };
                let blocked = walls.binary_search(&(cell, to)).is_ok();
                next.push(if blocked { cell } else { to } as u32);
            }
        }
        let mut kind = Vec::new();
        let mut slot_offset = Vec::new();
        for alphabet in scene.spec().slots() {
            slot_offset.push(kind.len());
            for sym in alphabet {
                let mv = match sym.action {
                    Action::Move { drow, dcol } => (drow, dcol),
                    _ => (0, 0),
                };
                // validation admits only the one-cell moves of MOVES
                kind.push(MOVES.iter().position(|&m| m == mv).unwrap_or(0) as u8);
            }
        }
        GridWorld {
            space,
            grid: spec.effect_grid(),
            start: spec.start.0 * spec.cols + spec.start.1,
            next,
            kind,
            slot_offset,
            reward: scene.reward_table(),
            contexts: if spec.contexts.is_empty() {
                vec![((spec.start.0, spec.start.0), (spec.start.1, spec.start.1))]
            } else {
                spec.contexts.iter().map(|c| c.bounds()).collect()
            },
        }
    }

    #[inline]
    fn step(&self, cell: usize, slot: usize, symbol: u8) -> usize {
        let k = self.kind[self.slot_offset[slot] + symbol as usize] as usize;
        self.next[k * self.grid.num_cells() + cell] as usize
    }

    /// The cell grid.
    pub fn grid(&self) -> &EffectGrid {
        &self.grid
    }

    /// The outcome of ending in `cell`.
    fn outcome(&self, cell: usize) -> Outcome {
        let (r, c) = (cell / self.grid.cols, cell % self.grid.cols);
        Outcome {
            effect: cell,
            reward: self.reward[cell],
            point: self.grid.center(r, c),
        }
    }

    /// The terminal cell of `command` from `cell` (a command that fits).
    fn run_from(&self, mut cell: usize, command: &Command) -> usize {
        for (slot, &s) in command.symbols.iter().enumerate() {
            cell = self.step(cell, slot, s);
        }
        cell
    }

    /// The cells visited by a command, start included (for pictures).
    pub fn path(&self, command: &Command) -> Vec<usize> {
        let mut path = vec![self.start];
        for (slot, &s) in command.symbols.iter().enumerate() {
            path.push(self.step(path[slot], slot, s));
        }
        path
    }
}

impl World for GridWorld {
    fn command_space(&self) -> &CommandSpace {
        &self.space
    }

    fn num_effects(&self) -> usize {
        self.grid.num_cells()
    }

    #[inline]
    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        super::check_command(&self.space, command)?;
        Ok(self.outcome(self.run_from(self.start, command)))
    }
}

impl Episodic for GridWorld {
    fn num_contexts(&self) -> usize {
        self.contexts.len()
    }

    /// The context's cell, or for a rectangle a row then a column drawn
    /// uniformly (two integers of `rng`); no draw for a single cell.
    fn draw_start(&self, context: usize, rng: &mut SessionRng) -> Result<WorldState, WorldError> {
        let &((r0, r1), (c0, c1)) = self.contexts.get(context).ok_or_else(|| {
            WorldError::Other(format!(
                "context {context}: this grid has {} start contexts",
                self.contexts.len()
            ))
        })?;
        let (r, c) = if (r0, c0) == (r1, c1) {
            (r0, c0)
        } else {
            (rng.random_range(r0..=r1), rng.random_range(c0..=c1))
        };
        Ok(WorldState::Cell(r * self.grid.cols + c))
    }

    fn bin_state(&self, state: &WorldState) -> Result<usize, WorldError> {
        let &WorldState::Cell(cell) = state else {
            return Err(WorldError::Other(format!(
                "a grid starts from a cell, not from {state:?}"
            )));
        };
        if cell >= self.grid.num_cells() {
            return Err(WorldError::Other(format!(
                "cell {cell} is outside this {}-cell grid",
                self.grid.num_cells()
            )));
        }
        Ok(cell)
    }

    fn execute_from(
        &mut self,
        from: &WorldState,
        command: &Command,
    ) -> Result<(Outcome, WorldState), WorldError> {
        super::check_command(&self.space, command)?;
        let cell = self.bin_state(from)?;
        let end = self.run_from(cell, command);
        Ok((self.outcome(end), WorldState::Cell(end)))
    }
}
