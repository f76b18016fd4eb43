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

    pub(crate) fn validate(&self, scene: &SceneSpec) -> Result<(), Invalid> {
        self.effect_grid().validate().map_err(|e| {
            let field = if self.rows == 0 { "rows" } else { "cols" };
            Invalid::at(field, None, &e.to_string())
        })?;
        let inside = |(r, c): (usize, usize)| r < self.rows && c < self.cols;
        if !inside(self.start) {
            return Err(Invalid::at(
                "start",
                None,
                &format!(
                    "a start cell inside the {} x {} grid, found {:?}",
                    self.rows, self.cols, self.start
                ),
            ));
        }
        for &(a, b) in &self.walls {
            if !inside(a) || !inside(b) {
                return Err(Invalid::at(
                    "walls",
                    None,
                    &format!("walls between cells inside the grid, found {a:?}-{b:?}"),
                ));
            }
            if a.0.abs_diff(b.0) + a.1.abs_diff(b.1) != 1 {
                return Err(Invalid::at(
                    "walls",
                    None,
                    &format!("walls between neighbouring cells, found {a:?}-{b:?}"),
                ));
            }
        }
        for alphabet in scene.slots() {
            for s in alphabet {
                match s.action {
                    Action::Idle => {}
                    Action::Move { drow, dcol } if drow.abs() + dcol.abs() <= 1 => {}
                    Action::Move { .. } => {
                        return Err(Invalid::at(
                            "action",
                            Some("Move"),
                            &format!(
                                "symbol '{}': a one-cell move (|drow| + |dcol| <= 1)",
                                s.symbol
                            ),
                        ))
                    }
                    #[allow(unreachable_patterns)]
                    _ => {
                        return Err(Invalid::at(
                            "action",
                            Some(&format!("'{}'", s.symbol)),
                            &format!(
                                "symbol '{}': a Grid world takes Move or Idle actions only",
                                s.symbol
                            ),
                        ))
                    }
                }
            }
        }
        Ok(())
    }
}
