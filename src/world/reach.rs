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
