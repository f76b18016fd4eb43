//! `e3d scene`: check, draw and execute scene files.

use super::run::{load_scene, write_file};
use super::{CliError, CliResult};
use clap::{Args, Subcommand};
use e3d::report::scene_svg::{scene_svg, Overlay};
use e3d::scene::{physics::BodyKind, PhysicsSpec, Scene, WorldSpec};
use e3d::world::{farthest_reached_cell, GridSpec, PhysicsWorld};
use e3d::{Command, GridWorld, OutcomeTable, World, WorldError};
use std::io::BufRead;
use std::path::PathBuf;

/// Arguments of `e3d scene`.
#[derive(Args, Debug)]
pub struct SceneArgs {
    #[command(subcommand)]
    pub command: SceneCmd,
}

/// The sub-commands of `e3d scene`.
#[derive(Subcommand, Debug)]
pub enum SceneCmd {
    /// Validate a scene and print a summary of it.
    Check {
        /// A scene file, or the name of a built-in scene.
        scene: String,
    },
    /// Draw a scene as SVG, with the path of one command if given.
    Render {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// A command (its symbols, one per slot) whose path to draw.
        #[arg(long, allow_hyphen_values = true)]
        command: Option<String>,
        /// The SVG file to write.
        #[arg(long, value_name = "FILE.svg")]
        out: PathBuf,
    },
    /// Execute commands and print `command,effect,reward,x,y` CSV.
    Exec {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// Commands (symbols, one per slot); `-` reads one per line from stdin.
        #[arg(required = true, allow_hyphen_values = true)]
        commands: Vec<String>,
    },
    /// Execute every command once and apply SCENES.md's rule for a
    /// hard-to-reach reward cell: among the reached cells, the farthest
    /// from the tracked point's start; ties to the fewest commands, then
    /// the lowest index.
    RewardCell {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// Measure distances from this point `X,Y` instead of the tracked
        /// point's start.
        #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true)]
        from: Option<[f64; 2]>,
    },
    /// Compute a scene's whole outcome table ahead of time, in parallel on
    /// every core (physics scenes: many commands at once per Rapier world
    /// where that is exact), and report its size, time and rollouts/s.
    Table {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// The folder of the table cache (read if the table is there,
        /// written otherwise); without it the table is computed and not kept.
        #[arg(long, value_name = "DIR")]
        cache: Option<PathBuf>,
    },
    /// Execute every command of a physics scene and report what happens:
    /// contacts between moving bodies, joints at their limits, top speeds.
    Stats {
        /// A scene file, or the name of a built-in scene.
        scene: String,
    },
}

fn parse_point(s: &str) -> Result<[f64; 2], String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|e| format!("`{t}`: {e}")))
        .collect::<Result<_, _>>()?;
    match v.as_slice() {
        [x, y] if x.is_finite() && y.is_finite() => Ok([*x, *y]),
        _ => Err(format!("expected two finite numbers `X,Y`, found `{s}`")),
    }
}

/// Runs `e3d scene ...`.
pub fn run(a: SceneArgs) -> CliResult {
    match a.command {
        SceneCmd::Check { scene } => check(&load_scene(&scene)?),
        SceneCmd::Render {
            scene,
            command,
            out,
        } => render(&load_scene(&scene)?, command.as_deref(), &out),
        SceneCmd::Exec { scene, commands } => exec(&load_scene(&scene)?, &commands),
        SceneCmd::RewardCell { scene, from } => reward_cell(&load_scene(&scene)?, from),
        SceneCmd::Stats { scene } => stats(&load_scene(&scene)?),
        SceneCmd::Table { scene, cache } => table(&load_scene(&scene)?, cache.as_deref()),
    }
}

fn world_error(e: WorldError) -> CliError {
    match e {
        WorldError::BadCommand { .. } => CliError::input(e),
        _ => CliError::simulation(e),
    }
}

fn check(scene: &Scene) -> CliResult {
    let space = scene.command_space();
    let grid = scene.effect_grid();
    println!("scene {}: valid", scene.name);
    if !scene.description.is_empty() {
        println!("  {}", scene.description);
    }
    match &scene.world {
        WorldSpec::Grid(g) => {
            println!(
                "world: Grid, {} x {} cells, start {:?}, {} wall(s)",
                g.rows,
                g.cols,
                g.start,
                g.walls.len()
            );
        }
        WorldSpec::Physics(p) => {
            for w in p.warnings() {
                eprintln!("warning: scene {}: {w}", scene.name);
            }
            let (phase, settle, together) = p.schedule.steps(p.dt);
            println!(
                "world: Physics, gravity ({}, {}) m/s², dt {:.6} s, {} step(s) per command ({})",
                p.gravity.0,
                p.gravity.1,
                p.dt,
                p.schedule.total_steps(p.dt, space.num_slots()),
                if together {
                    format!("all slots push {phase} steps, then settle {settle}")
                } else {
                    format!("{phase} steps per slot, then settle {settle}")
                }
            );
            println!("bodies ({}):", p.bodies.len());
            for b in &p.bodies {
                let mass = if b.kind == BodyKind::Dynamic {
                    format!(", {:.4} kg", b.mass_kg())
                } else {
                    String::new()
                };
                println!(
                    "  {:<12} {:?}, {:?}{mass}, at ({}, {}), angle {}",
                    b.name, b.kind, b.shape, b.position.0, b.position.1, b.angle
                );
            }
            println!("joints ({}):", p.joints.len());
            for j in &p.joints {
                println!(
                    "  {:<12} {} -> {}, limits {}, damping {} N·m·s/rad{}",
                    j.name,
                    j.parent,
                    j.child,
                    j.limits
                        .map_or("none".to_string(), |(a, b)| format!("[{a}, {b}] rad")),
                    j.damping,
                    j.motor.map_or(String::new(), |m| format!(
                        ", motor {} N·m/rad, {} N·m·s/rad",
                        m.stiffness, m.damping
                    ))
                );
            }
            println!(
                "tracked point: ({}, {}) on `{}`",
                p.effect.point.0, p.effect.point.1, p.effect.body
            );
            if let Some(sym) = p.symmetry {
                let n = space.num_commands_text();
                match OutcomeTable::simulated_commands(scene) {
                    Some(k) => println!(
                        "symmetry: {sym:?} (checked): {k} of {n} commands simulated, the others reflected"
                    ),
                    None => println!("symmetry: {sym:?} (checked)"),
                }
            }
        }
    }
    println!("slots ({}):", space.num_slots());
    for (i, alphabet) in scene.slots().enumerate() {
        let syms: String = alphabet.iter().map(|s| s.symbol).collect();
        println!("  {i}: {syms}");
    }
    println!("distinct commands: {}", space.num_commands_text());
    println!(
        "effects: {} ({} x {} cells over [{}, {}] x [{}, {}])",
        grid.num_cells(),
        grid.rows,
        grid.cols,
        grid.min[0],
        grid.max[0],
        grid.min[1],
        grid.max[1]
    );
    for r in &scene.reward.regions {
        println!(
            "reward region `{}`: [{}, {}] x [{}, {}], cells {:?}",
            r.name,
            r.min.0,
            r.max.0,
            r.min.1,
            r.max.1,
            r.cells(&grid)
        );
    }
    if scene.reward.cells.is_empty() {
        println!("reward cells: none");
    } else {
        println!(
            "reward cells: {:?}, value {}{}",
            scene.reward.cells,
            scene.reward.value,
            if scene.reward.note.is_empty() {
                String::new()
            } else {
                format!(" ({})", scene.reward.note)
            }
        );
    }
    Ok(())
}

fn render(scene: &Scene, command: Option<&str>, out: &std::path::Path) -> CliResult {
    let overlay = match command {
        None => None,
        Some(text) => {
            let space = scene.command_space();
            let c = space.parse(text).map_err(CliError::input)?;
            Some(overlay_of(scene, &c, &space.format(&c))?)
        }
    };
    let svg = scene_svg(scene, overlay.as_ref());
    write_file(out, svg.as_bytes())?;
    println!("wrote {}", out.display());
    Ok(())
}

fn overlay_of(scene: &Scene, c: &Command, text: &str) -> Result<Overlay, CliError> {
    match &scene.world {
        WorldSpec::Grid(g) => {
            let mut w = GridWorld::from_scene(scene, g);
            let o = w.execute(c).map_err(world_error)?;
            Ok(Overlay {
                command: text.to_string(),
                points: grid_path(&w, g, c),
                poses: None,
                effect: o.effect,
                reward: o.reward,
            })
        }
        WorldSpec::Physics(p) => {
            let mut w = PhysicsWorld::from_scene(scene, p);
            let t = w.trace(c).map_err(world_error)?;
            Ok(Overlay {
                command: text.to_string(),
                points: t.points,
                poses: Some(t.poses),
                effect: t.outcome.effect,
                reward: t.outcome.reward,
            })
        }
    }
}

fn grid_path(w: &GridWorld, g: &GridSpec, c: &Command) -> Vec<[f64; 2]> {
    w.path(c)
        .into_iter()
        .map(|cell| w.grid().center(cell / g.cols, cell % g.cols))
        .collect()
}

fn exec(scene: &Scene, commands: &[String]) -> CliResult {
    let mut world = scene.build();
    let space = world.command_space().clone();
    let mut texts: Vec<String> = Vec::new();
    for c in commands {
        if c == "-" {
            for line in std::io::stdin().lock().lines() {
                let line = line.map_err(|e| CliError::input(format!("stdin: {e}")))?;
                if !line.trim().is_empty() {
                    texts.push(line.trim().to_string());
                }
            }
        } else {
            texts.push(c.clone());
        }
    }
    let mut out = String::from("command,effect,reward,x,y\n");
    for t in &texts {
        let c = space.parse(t).map_err(CliError::input)?;
        let o = world.execute(&c).map_err(world_error)?;
        out.push_str(&format!(
            "{},{},{},{},{}\n",
            space.format(&c),
            o.effect,
            o.reward,
            o.point[0],
            o.point[1]
        ));
    }
    print!("{out}");
    Ok(())
}

fn reward_cell(scene: &Scene, from: Option<[f64; 2]>) -> CliResult {
    let from = match (from, &scene.world) {
        (Some(p), _) => p,
        (None, WorldSpec::Physics(p)) => {
            let b = p.body(&p.effect.body).expect("validated: tracked body");
            let t = e3d::scene::physics::to_world_point(b.position, b.angle, p.effect.point);
            [t.0, t.1]
        }
        (None, WorldSpec::Grid(g)) => scene.effect_grid().center(g.start.0, g.start.1),
    };
    let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
    if n > e3d::world::MAX_TABLE_COMMANDS {
        return Err(CliError::input(format!(
            "{} commands: too many to execute them all (at most {})",
            scene.command_space().num_commands_text(),
            e3d::world::MAX_TABLE_COMMANDS
        )));
    }
    let start = std::time::Instant::now();
    let table = OutcomeTable::build_scene(scene).map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    let grid = scene.effect_grid();
    let cell = farthest_reached_cell(&table, &grid, from)
        .ok_or_else(|| CliError::input("no command to execute"))?;
    let counts = table.effect_counts();
    let mut sorted: Vec<(u64, usize)> = counts
        .iter()
        .enumerate()
        .filter(|(_, &c)| c > 0)
        .map(|(e, &c)| (c, e))
        .collect();
    sorted.sort_by(|a, b| b.0.cmp(&a.0).then(a.1.cmp(&b.1)));
    println!(
        "scene {}: executed {} commands in {:.2} s ({:.0} commands/s on {} thread(s))",
        scene.name,
        table.len(),
        secs,
        table.len() as f64 / secs,
        rayon::current_num_threads()
    );
    println!(
        "reached cells: {} of {}",
        cell.reached_cells,
        grid.num_cells()
    );
    let top: Vec<String> = sorted
        .iter()
        .take(5)
        .map(|(c, e)| {
            format!(
                "({}, {}) {} ({:.1}%)",
                e / grid.cols,
                e % grid.cols,
                c,
                100.0 * *c as f64 / table.len() as f64
            )
        })
        .collect();
    println!("most common cells: {}", top.join(", "));
    let center = grid.center(cell.row, cell.col);
    println!(
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
    println!("commands reaching it: {}", reaching.join(" "));
    let ok = scene.reward.cells == [(cell.row, cell.col)];
    println!(
        "the scene's reward cells {:?} {} the rule's cell",
        scene.reward.cells,
        if ok { "match" } else { "do NOT match" }
    );
    Ok(())
}

fn stats(scene: &Scene) -> CliResult {
    use rayon::prelude::*;
    let WorldSpec::Physics(spec) = &scene.world else {
        return Err(CliError::input(
            "`e3d scene stats` is for physics scenes; this is a grid scene",
        ));
    };
    let space = scene.command_space();
    let n = space.num_commands().unwrap_or(u64::MAX);
    if n > e3d::world::MAX_TABLE_COMMANDS {
        return Err(CliError::input(format!(
            "{} commands: too many to execute them all (at most {})",
            space.num_commands_text(),
            e3d::world::MAX_TABLE_COMMANDS
        )));
    }
    let start = std::time::Instant::now();
    let all: Vec<e3d::world::RunStats> = (0..n)
        .into_par_iter()
        .map_init(
            || PhysicsWorld::from_scene(scene, spec),
            |w, i| w.inspect(&space.command_at(i)),
        )
        .collect::<Result<_, _>>()
        .map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    let count = |f: &dyn Fn(&e3d::world::RunStats) -> bool| all.iter().filter(|s| f(s)).count();
    let pct = |k: usize| 100.0 * k as f64 / all.len() as f64;
    let contacts = count(&|s| s.contact_steps > 0);
    let limits = count(&|s| s.limit_steps > 0);
    let max_speed = all.iter().map(|s| s.max_speed).fold(0.0, f64::max);
    let max_spin = all.iter().map(|s| s.max_spin).fold(0.0, f64::max);
    let mut cells = vec![0u64; scene.num_effects()];
    for s in &all {
        cells[s.outcome.effect] += 1;
    }
    println!(
        "scene {}: {} commands in {:.2} s ({:.0} rollouts/s on {} thread(s))",
        scene.name,
        all.len(),
        secs,
        all.len() as f64 / secs,
        rayon::current_num_threads()
    );
    println!(
        "reached cells: {} of {}",
        cells.iter().filter(|&&c| c > 0).count(),
        cells.len()
    );
    println!(
        "commands bringing two moving bodies into contact: {contacts} ({:.1}%)",
        pct(contacts)
    );
    println!(
        "commands pressing a joint against a limit (within 0.01 rad): {limits} ({:.1}%)",
        pct(limits)
    );
    println!(
        "top linear speed {max_speed:.3} m/s (max_speed {} m/s); top angular speed {max_spin:.2} rad/s (Rapier's cap: {:.2} rad/s)",
        spec.max_speed,
        std::f64::consts::FRAC_PI_4 / spec.dt
    );
    Ok(())
}

fn table(scene: &Scene, cache: Option<&std::path::Path>) -> CliResult {
    let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
    if n > e3d::world::MAX_TABLE_COMMANDS {
        return Err(CliError::input(format!(
            "{} commands: too many for an outcome table (at most {})",
            scene.command_space().num_commands_text(),
            e3d::world::MAX_TABLE_COMMANDS
        )));
    }
    let existed = cache.is_some_and(|d| OutcomeTable::cache_path(scene, d).exists());
    let start = std::time::Instant::now();
    let table = OutcomeTable::for_scene(scene, cache).map_err(world_error)?;
    let secs = start.elapsed().as_secs_f64();
    let mut how = match &scene.world {
        WorldSpec::Physics(p) if p.copies_are_exact() => {
            format!("{} copies per Rapier world", e3d::world::TABLE_COPIES)
        }
        WorldSpec::Physics(_) => "one command per Rapier world".to_string(),
        WorldSpec::Grid(_) => "grid".to_string(),
    };
    if let WorldSpec::Physics(PhysicsSpec {
        symmetry: Some(sym),
        ..
    }) = &scene.world
    {
        let simulated = OutcomeTable::simulated_commands(scene).unwrap_or(n);
        how = format!("{how}; {sym:?} symmetry: {simulated} simulated, the others reflected");
    }
    println!(
        "scene {}: {} commands in {:.3} s ({:.0} commands/s, {} thread(s), {how})",
        scene.name,
        table.len(),
        secs,
        table.len() as f64 / secs,
        rayon::current_num_threads()
    );
    match cache {
        Some(dir) => {
            let path = OutcomeTable::cache_path(scene, dir);
            if existed {
                println!("read from {}", path.display());
            } else if path.exists() {
                println!("written to {}", path.display());
            } else {
                println!(
                    "could not write {} (the table was computed)",
                    path.display()
                );
            }
        }
        None => println!("not written (give --cache DIR to keep it)"),
    }
    Ok(())
}
