//! The grid part of the scene format: `world: Grid(...)`, the paper's
//! degenerate kinematic scene (its world is [`GridWorld`](crate::world::GridWorld)).

use super::{Action, Invalid, SceneSpec};
use crate::effect::EffectGrid;
use serde::{Deserialize, Serialize};

/// The `Grid` world of a scene file: `rows x cols` cells, walls between
/// some neighbouring cells, a start cell. Row 0 is at the top, column 0 at
/// the left; in metres each cell is 1 x 1 with the grid's lower-left corner
/// at the origin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridSpec {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// The start cell `(row, col)`.
    pub start: (usize, usize),
    /// Walls between two neighbouring cells, `((row, col), (row, col))`.
    /// The outer border is always a wall.
    #[serde(default)]
    pub walls: Vec<((usize, usize), (usize, usize))>,
    /// Start contexts: when given, each trial (or episode) starts from one
    /// of them, drawn with the session's generator, instead of `start`;
    /// what the learner observes is the context's index (see
    /// [`num_contexts`](Self::num_contexts)). Empty (the default): one
    /// context, `start`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contexts: Vec<StartCells>,
}

/// One start context of a grid: a named cell, or a named rectangle of
/// cells from which the start is drawn uniformly (a seeded range).
///
/// ```ron
/// contexts: [(name: "left", cell: (1, 0)), (name: "room_b", cell: (0, 3), to: (2, 5))]
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartCells {
    /// The context's name (results and pictures).
    pub name: String,
    /// The start cell `(row, col)`; with `to`, a corner of the rectangle.
    pub cell: (usize, usize),
    /// The opposite corner of a rectangle of start cells (inclusive): each
    /// start draws a row, then a column, uniformly in it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<(usize, usize)>,
}

impl StartCells {
    /// The rows and the columns of the context's cells (inclusive ranges).
    pub fn bounds(&self) -> ((usize, usize), (usize, usize)) {
        let to = self.to.unwrap_or(self.cell);
        (
            (self.cell.0.min(to.0), self.cell.0.max(to.0)),
            (self.cell.1.min(to.1), self.cell.1.max(to.1)),
        )
    }
}

impl GridSpec {
    /// The effect grid: one effect per cell.
    pub fn effect_grid(&self) -> EffectGrid {
        EffectGrid {
            rows: self.rows,
            cols: self.cols,
            min: [0.0, 0.0],
            max: [self.cols as f64, self.rows as f64],
        }
    }

    /// The number of start contexts: the declared ones, or 1 (`start`).
    pub fn num_contexts(&self) -> usize {
        self.contexts.len().max(1)
    }

    /// Checks the grid world of `scene`: its size, start, contexts, walls
    /// and the symbols' actions.
    pub(crate) fn validate(&self, scene: &SceneSpec) -> Result<(), Invalid> {
        self.effect_grid().validate().map_err(|e| {
            let field = if self.rows == 0 { "rows" } else { "cols" };
            Invalid::new(field, e.to_string())
        })?;
        let inside = |(r, c): (usize, usize)| r < self.rows && c < self.cols;
        if !inside(self.start) {
            return Err(Invalid::new(
                "start",
                format!(
                    "a start cell inside the {} x {} grid, found {:?}",
                    self.rows, self.cols, self.start
                ),
            ));
        }
        self.check_contexts_and_walls()?;
        check_actions(scene)?;
        Ok(())
    }

    /// The start contexts (cells inside the grid, distinct non-empty
    /// names) and the walls (between neighbouring cells inside the grid).
    fn check_contexts_and_walls(&self) -> Result<(), Invalid> {
        let inside = |(r, c): (usize, usize)| r < self.rows && c < self.cols;
        super::check_context_count(self.contexts.len())?;
        let mut names = std::collections::HashSet::with_capacity(self.contexts.len());
        for (i, c) in self.contexts.iter().enumerate() {
            let here = |expected: String| Invalid::new("name", expected).within("contexts", i);
            for cell in [Some(c.cell), c.to].into_iter().flatten() {
                if !inside(cell) {
                    return Err(Invalid::new(
                        if Some(cell) == c.to { "to" } else { "cell" },
                        format!(
                            "context `{}` of `contexts`: cells inside the {} x {} grid, found {cell:?}",
                            crate::text::echo(&c.name),
                            self.rows,
                            self.cols
                        ),
                    )
                    .within("contexts", i));
                }
            }
            if c.name.trim().is_empty() || !names.insert(c.name.as_str()) {
                return Err(here(format!(
                    "a distinct, non-empty name for every context, found `{}`",
                    crate::text::echo(&c.name)
                )));
            }
            crate::text::check_name(&c.name).map_err(|e| here(format!("context {i}: {e}")))?;
        }
        for &(a, b) in &self.walls {
            let between = if !inside(a) || !inside(b) {
                "cells inside the grid"
            } else if a.0.abs_diff(b.0) + a.1.abs_diff(b.1) != 1 {
                "neighbouring cells"
            } else {
                continue;
            };
            let found = format!("walls between {between}, found {a:?}-{b:?}");
            return Err(Invalid::new("walls", found));
        }
        Ok(())
    }
}

/// The symbols' actions: one-cell moves or idle, the only actions of a
/// grid world.
fn check_actions(scene: &SceneSpec) -> Result<(), Invalid> {
    for s in scene.slots().flatten() {
        let (anchor, what) = match s.action {
            Action::Idle => continue,
            Action::Move { drow, dcol } if drow.abs() + dcol.abs() <= 1 => continue,
            Action::Move { .. } => ("Move".into(), "a one-cell move (|drow| + |dcol| <= 1)"),
            _ => (
                format!("'{}'", s.symbol),
                "a Grid world takes Move or Idle actions only",
            ),
        };
        let what = format!("symbol '{}': {what}", s.symbol);
        return Err(Invalid::at("action", Some(&anchor), &what));
    }
    Ok(())
}
