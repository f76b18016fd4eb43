//! `e3d scene reward-cell`: every command executed, and the rule for a
//! hard-to-reach reward cell.

use super::check::rewarded_cells;
use super::simulate::build_table;
use crate::cli::console::outln;
use crate::cli::{CliError, CliResult};
use e3d::effect::EffectGrid;
use e3d::scene::{Scene, WorldSpec};
use e3d::world::farthest_reached_cell;
use e3d::OutcomeTable;

pub(super) fn reward_cell(scene: &Scene, from: Option<[f64; 2]>) -> CliResult {
    let from = from.unwrap_or_else(|| start_point(scene));
    super::simulate::all_commands(scene, "to execute them all")?;
    let start = std::time::Instant::now();
    let table = build_table(scene)?;
    let secs = start.elapsed().as_secs_f64();
    let grid = scene.effect_grid();
    let cell = farthest_reached_cell(&table, &grid, from)
        .ok_or_else(|| CliError::input("no command to execute"))?;
    let (name, k) = (&scene.spec().name, table.len());
    let (rate, threads) = (k as f64 / secs, rayon::current_num_threads());
    outln!("scene {name}: executed {k} commands in {secs:.2} s ({rate:.0} commands/s on {threads} thread(s))");
    let (reached, cells) = (cell.reached_cells, grid.num_cells());
    outln!("reached cells: {reached} of {cells}");
    outln!("most common cells: {}", most_common_cells(&table, &grid));
    let center = grid.center(cell.row, cell.col);
    outln!(
        "rule: farthest reached cell from ({:.4}, {:.4}): ({}, {}) = effect {}, centre ({}, {}), {:.4} m away, reached by {} command(s)",
        // 4 decimals, as the distance: pendulum3's start, cos(-pi/2) * 0.9,
        // prints as 0.0000, not 0.000000000000000006123233995736766
        from[0], from[1], cell.row, cell.col, cell.effect, center[0], center[1], cell.distance, cell.commands
    );
    let space = scene.command_space();
    let reaching: Vec<String> = table
        .outcomes()
        .enumerate()
        .filter(|(_, o)| o.effect == cell.effect)
        .take(10)
        .map(|(i, _)| space.format(&space.command_at(i as u64)))
        .collect();
    outln!("commands reaching it: {}", reaching.join(" "));
    print_rule_match(scene, (cell.row, cell.col));
    Ok(())
}

/// Where the distance of the rule is measured from by default: a grid's
/// start cell's centre, the tracked point where the scene places it, or
/// the features' start on the effect's layout.
fn start_point(scene: &Scene) -> [f64; 2] {
    match &scene.spec().world {
        WorldSpec::Physics(p) => match p.effect.world_point() {
            // the tracked point where the scene places it
            Some((body, point, _)) if let Some(b) = p.body(body) => {
                let t = e3d::scene::physics::to_world_point(b.position, b.angle, point);
                [t.0, t.1]
            }
            // the features' start, on the effect's layout
            _ => scene.physics_world().map_or([0.0, 0.0], |w| w.start().0),
        },
        WorldSpec::Grid(g) => scene.effect_grid().center(g.start.0, g.start.1),
    }
}

/// The five cells most commands of `table` reach, with their counts and
/// shares.
fn most_common_cells(table: &OutcomeTable, grid: &EffectGrid) -> String {
    let counts = table.effect_counts();
    let mut sorted: Vec<(usize, u64)> = (counts.iter().copied().enumerate())
        .filter(|&(_, c)| c > 0)
        .collect();
    // the most common first, ties to the lower cell
    sorted.sort_by_key(|&(e, c)| (std::cmp::Reverse(c), e));
    let top: Vec<String> = (sorted.iter().take(5))
        .map(|&(e, c)| {
            let share = 100.0 * c as f64 / table.len() as f64;
            format!("({}, {}) {c} ({share:.1}%)", e / grid.cols, e % grid.cols)
        })
        .collect();
    top.join(", ")
}

/// Whether the scene's reward cells are the rule's cell `rule`.
fn print_rule_match(scene: &Scene, rule: (usize, usize)) {
    let declared = rewarded_cells(scene);
    if declared.is_empty() {
        outln!(
            "the scene declares no reward cell; by the rule it would be {rule:?}: `reward: (cells: [{rule:?}])`"
        );
    } else if declared == [rule] {
        outln!("the scene's reward cells {declared:?} match the rule's cell");
    } else {
        outln!("the scene's reward cells {declared:?} do NOT match the rule's cell {rule:?}");
    }
}
