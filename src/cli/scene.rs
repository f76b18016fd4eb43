//! `e3d scene`: check, draw and execute scene files.

use super::output::write_file;
use super::run::load_scene;
use super::{progress, CliError, CliResult};
use clap::{Args, Subcommand};
use e3d::report::scene_svg::{scene_svg, Overlay};
use e3d::scene::{physics::BodyKind, PhysicsSpec, Scene, WorldSpec};
use e3d::world::{farthest_reached_cell, GridSpec, PhysicsWorld};
use e3d::{Command, CommandSpace, GridWorld, OutcomeTable, World, WorldError};
use std::fmt::Write as _;
use std::io::{BufRead, Write as _};
use std::path::{Path, PathBuf};
use std::sync::mpsc::SyncSender;
use std::sync::Mutex;

/// Arguments of `e3d scene`.
#[derive(Args, Debug)]
pub struct SceneArgs {
    #[command(subcommand)]
    pub command: SceneCmd,
}

/// The sub-commands of `e3d scene`.
#[derive(Subcommand, Debug)]
pub enum SceneCmd {
    /// Validate a scene, print a summary of it, warn about suspicious
    /// geometry, and estimate what its commands reach from a seeded
    /// random sample of them.
    Check {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// How many random commands to execute for the reachability
        /// estimate (0: none). A space of at most this many commands is
        /// executed whole, and the counts are exact.
        #[arg(long, value_name = "N", default_value_t = 200)]
        samples: u64,
        /// The seed of the sample.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Print only the scene as RON with its shorthands (`chains`,
        /// `walls`) expanded into plain bodies and joints, every field
        /// written: text that loads back as the same scene.
        #[arg(long)]
        expanded: bool,
    },
    /// Draw a scene as SVG, with the path of one command if given; with
    /// `--animate`, that command's rollout as an animated SVG or HTML page.
    Render {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// A command (its symbols, one per slot) whose path to draw.
        #[arg(long, allow_hyphen_values = true)]
        command: Option<String>,
        /// Animate the command (needs `--command`): on a physics scene every
        /// moving body, the tracked point and the time; on a grid the
        /// agent's cell path, a keyframe per slot; looping. An `.html` FILE
        /// gets a page holding the SVG.
        #[arg(long, requires = "command")]
        animate: bool,
        /// The SVG (or, with `--animate`, HTML) file to write.
        #[arg(long, value_name = "FILE.svg")]
        out: PathBuf,
    },
    /// Execute commands and print `command,effect,reward,x,y` CSV, in
    /// input order, as they are done: stdin is read as it comes, and what
    /// has arrived runs in parallel on every core (physics scenes: many
    /// commands at once per Rapier world where that is exact).
    Exec {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// Commands (symbols, one per slot); `-` reads one per line from stdin.
        #[arg(required = true, allow_hyphen_values = true)]
        commands: Vec<String>,
        /// Look the commands up in the scene's outcome table in this folder
        /// (written by `e3d scene table --cache DIR`) instead of simulating
        /// them; without a usable table there, say why and simulate.
        #[arg(long, value_name = "DIR")]
        table_cache: Option<PathBuf>,
        /// Also write each command's whole motion to FILE.csv: per step, the
        /// time, every body's pose and velocity, every joint's angle and
        /// velocity (physics scenes; one command at a time).
        #[arg(long, value_name = "FILE.csv", conflicts_with = "table_cache")]
        trace: Option<PathBuf>,
    },
    /// Execute every command once and apply the rule of docs/canonical-scenes.md for a
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
    if let Some(r) = super::continuous::scene(&a.command) {
        return r;
    }
    match a.command {
        SceneCmd::Check {
            scene,
            expanded: true,
            ..
        } => {
            let text = load_scene(&scene)?.to_ron();
            let mut stdout = std::io::stdout().lock();
            stdout
                .write_all(text.as_bytes())
                .and_then(|()| stdout.flush())
                .map_err(|e| CliError::output(format!("standard output: {e}")))
        }
        SceneCmd::Check {
            scene,
            samples,
            seed,
            expanded: false,
        } => {
            let scene = load_scene(&scene)?;
            check(&scene)?;
            check_reach(&scene, samples, seed)
        }
        SceneCmd::Render {
            scene,
            command,
            animate: true,
            out,
        } => animate(&load_scene(&scene)?, command.as_deref().unwrap_or(""), &out),
        SceneCmd::Render {
            scene,
            command,
            animate: false,
            out,
        } => render(&load_scene(&scene)?, command.as_deref(), &out),
        SceneCmd::Exec {
            scene,
            commands,
            trace: Some(path),
            ..
        } => exec_trace(&load_scene(&scene)?, commands, &path),
        SceneCmd::Exec {
            scene,
            commands,
            table_cache,
            trace: None,
        } => exec(&load_scene(&scene)?, commands, table_cache.as_deref()),
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
                p.schedule.total_steps(p.dt, scene.num_slots()),
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
                let n = scene.command_space().num_commands_text();
                match OutcomeTable::simulated_commands(scene) {
                    Some(k) => println!(
                        "symmetry: {sym:?} (checked): {k} of {n} commands simulated, the others reflected"
                    ),
                    None => println!("symmetry: {sym:?} (checked)"),
                }
            }
        }
    }
    println!("slots ({}):", scene.num_slots());
    if let e3d::scene::CommandSpec::Continuous(slots) = &scene.command {
        for (i, slot) in slots.iter().enumerate() {
            println!(
                "  {i}: a value in [{}, {}]{}: {:?}",
                slot.range.0,
                slot.range.1,
                slot.name
                    .as_deref()
                    .map_or(String::new(), |n| format!(" ({n})")),
                slot.action
            );
        }
        println!(
            "distinct commands: infinitely many (continuous: live physics only, no table or memo)"
        );
    } else {
        for (i, alphabet) in scene.slots().enumerate() {
            let syms: String = alphabet.iter().map(|s| s.symbol).collect();
            println!("  {i}: {syms}");
        }
        println!(
            "distinct commands: {}",
            scene.command_space().num_commands_text()
        );
    }
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
    // every rewarded cell, listed or in a region: one answer
    let cells = rewarded_cells(scene);
    if cells.is_empty() {
        println!("reward cells: none (the scene declares no reward cell or region)");
    } else {
        let from = match (scene.reward.cells.is_empty(), scene.reward.regions.len()) {
            (true, 1) => " (from the region above)".to_string(),
            (true, _) => " (from the regions above)".to_string(),
            (false, 0) => String::new(),
            (false, _) => " (listed and from the regions above)".to_string(),
        };
        println!(
            "reward cells: {cells:?}{from}, value {}{}",
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

/// The reachability estimate of `scene check`: `samples` seeded random
/// commands executed, the cells they reach, the reward cells' share, and a
/// warning (stderr) when no sampled command reached a reward cell, with
/// what the full check costs.
fn check_reach(scene: &Scene, samples: u64, seed: u64) -> CliResult {
    if samples == 0 {
        return Ok(());
    }
    let total = match scene.is_continuous() {
        true => samples,
        false => scene
            .command_space()
            .num_commands()
            .map_or(samples, |n| n.min(samples)),
    };
    let label = format!("scene check {}", scene.name);
    say_cost(&label, scene, total, 1);
    let sampled = progress::track(&label, "commands", total, |p| {
        e3d::world::sample_reach_with_progress(scene, samples, seed, &|k| p.add(k))
    });
    let s = match sampled {
        Ok(s) => s,
        // the scene is valid; a command that blows up is a finding of the
        // check, not a failure of it
        Err(e) => {
            eprintln!("warning: scene {}: reach: {e}", scene.name);
            return Ok(());
        }
    };
    let grid = scene.effect_grid();
    let n = match scene.value_space() {
        Some(_) => "infinitely many, drawn uniformly in their ranges".to_string(),
        None => scene.command_space().num_commands_text(),
    };
    if s.exhaustive {
        println!(
            "reach: all {} commands executed ({:.2} s): {} of {} cells reached",
            s.samples,
            s.seconds,
            s.reached_cells(),
            grid.num_cells()
        );
    } else {
        println!(
            "reach (estimate): {} random commands of {n} (seed {seed}, {:.2} s): {} of {} cells reached",
            s.samples,
            s.seconds,
            s.reached_cells(),
            grid.num_cells()
        );
    }
    let cells = rewarded_cells(scene);
    if cells.is_empty() {
        return Ok(());
    }
    let effects: Vec<usize> = cells.iter().map(|&(r, c)| r * grid.cols + c).collect();
    let hits = s.hits(&effects);
    let share = hits as f64 / s.samples as f64;
    if s.exhaustive {
        println!(
            "reward cells reached by {hits} of {} commands ({:.3}%)",
            s.samples,
            100.0 * share
        );
        if hits == 0 {
            eprintln!(
                "warning: scene {}: no command reaches a reward cell {cells:?} (every command executed)",
                scene.name
            );
        }
        return Ok(());
    }
    println!(
        "reward cells: estimated probability {:.3}% ({hits} of {} sampled commands)",
        100.0 * share,
        s.samples
    );
    if hits == 0 {
        // the rule of three: with no hit in k draws, p < 3/k at 95%
        let bound = 100.0 * 3.0 / s.samples as f64;
        eprintln!(
            "warning: scene {}: no sampled command reached a reward cell {cells:?}: it may be unreachable, or rarer than about {bound:.2}% (95% bound); {}",
            scene.name,
            full_check_cost(scene)
        );
    }
    Ok(())
}

/// What `scene reward-cell` (every command executed) would cost: the
/// commands it simulates and the cost model's estimate (src/world/plan.rs).
fn full_check_cost(scene: &Scene) -> String {
    if scene.is_continuous() {
        return "a full check is not possible: continuous commands cannot be enumerated; sample more with `--samples N`".to_string();
    }
    let threads = rayon::current_num_threads();
    let plan = e3d::world::ExecutionPlan::choose(
        scene,
        &e3d::world::Workload {
            trials: 0,
            sessions: 1,
            threads,
        },
        None,
        0,
    );
    match (plan.simulated, plan.table_seconds) {
        (Some(k), Some(t)) => format!(
            "a full check (`e3d scene reward-cell {}`) simulates {k} commands: about {} on {threads} thread(s) by the cost model, calibrated here",
            scene.name,
            seconds_text(t * calibration(scene))
        ),
        _ => format!(
            "a full check is not possible: {} commands are too many for `e3d scene reward-cell` (at most {}); sample more with `--samples N`",
            scene.command_space().num_commands_text(),
            e3d::world::MAX_TABLE_COMMANDS
        ),
    }
}

fn seconds_text(t: f64) -> String {
    if t < 0.01 {
        format!("{:.2} ms", t * 1e3)
    } else if t < 1.0 {
        format!("{t:.2} s")
    } else if t < 120.0 {
        format!("{t:.0} s")
    } else if t < 7200.0 {
        format!("{:.0} min", t / 60.0)
    } else {
        format!("{:.1} h", t / 3600.0)
    }
}

/// The cells the scene rewards: those it lists and those of its regions,
/// in order, once each.
fn rewarded_cells(scene: &Scene) -> Vec<(usize, usize)> {
    let grid = scene.effect_grid();
    let mut cells: Vec<(usize, usize)> = scene.reward.cells.clone();
    for r in &scene.reward.regions {
        cells.extend(r.cells(&grid));
    }
    cells.sort_unstable();
    cells.dedup();
    cells
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

/// `e3d scene render --animate`: the command's rollout, animated (SVG, or
/// an HTML page when `out` ends in `.html`).
fn animate(scene: &Scene, text: &str, out: &std::path::Path) -> CliResult {
    use e3d::report::motion_svg::{grid_motion_svg, html_page, motion_svg, thin, MAX_FRAMES};
    let space = scene.command_space();
    let c = space.parse(text).map_err(CliError::input)?;
    let cmd = space.format(&c);
    say_cost(&format!("scene render {}", scene.name), scene, 1, 1);
    let (svg, what) = match scene.physics_world() {
        None => {
            let svg = grid_motion_svg(scene, &c).map_err(|e| CliError::input(e.to_string()))?;
            let keyframes = space.num_slots() + 1;
            (
                svg,
                format!(
                    "{keyframes} keyframes: the start and a cell per slot, {:.1} s",
                    keyframes as f64 * e3d::report::motion_svg::GRID_KEYFRAME_SECONDS
                ),
            )
        }
        Some(mut w) => {
            let motion = w.motion(&c).map_err(world_error)?;
            let svg =
                motion_svg(scene, &cmd, &motion).map_err(|e| CliError::input(e.to_string()))?;
            (
                svg,
                format!(
                    "{} of {} frames, {:.3} s",
                    thin(motion.frames.len(), MAX_FRAMES).len(),
                    motion.frames.len(),
                    motion.frames.last().map_or(0.0, |f| f.time)
                ),
            )
        }
    };
    let html = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
    let text = if html {
        html_page(&format!("{}: command {cmd}", scene.name), &svg)
    } else {
        svg
    };
    write_file(out, text.as_bytes())?;
    println!("wrote {} ({what})", out.display());
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

/// A command read by [`read_commands`], or why the input ends there.
type Read = Result<Command, CliError>;

/// Parses the `commands` of `e3d scene exec` in order (`-`: every
/// non-blank line of stdin, as it comes) and sends them to `tx`, up to the
/// first that does not parse (sent as an error naming its stdin line) or
/// until the receiver is gone.
fn read_commands(space: &CommandSpace, commands: &[String], tx: &SyncSender<Read>) {
    let send = |r: Read| {
        let stop = r.is_err();
        tx.send(r).is_ok() && !stop
    };
    for arg in commands {
        if arg != "-" {
            if !send(space.parse(arg).map_err(CliError::input)) {
                return;
            }
            continue;
        }
        for (k, line) in std::io::stdin().lock().lines().enumerate() {
            let r = match line {
                Err(e) => Err(CliError::input(format!("stdin line {}: {e}", k + 1))),
                Ok(l) if l.trim().is_empty() => continue,
                Ok(l) => space
                    .parse(l.trim())
                    .map_err(|e| CliError::input(format!("stdin line {}: {e}", k + 1))),
            };
            if !send(r) {
                return;
            }
        }
    }
}

/// `e3d scene exec --trace FILE`: each command's motion, one after the
/// other on one world, its CSV row printed as it is done and its frames
/// streamed into a temporary file renamed to FILE at the end (whole or not
/// at all).
fn exec_trace(scene: &Scene, commands: Vec<String>, path: &Path) -> CliResult {
    let Some(mut world) = scene.physics_world() else {
        return Err(CliError::input(format!(
            "scene `{}` is a grid: it has no motion to trace (`e3d scene render --command` draws a command's path)",
            scene.name
        )));
    };
    let space = scene.command_space();
    // whether stdin is read, and how many commands otherwise
    let commands_known = (commands.iter().any(|c| c == "-"), commands.len() as u64);
    let (tx, rx) = std::sync::mpsc::sync_channel::<Read>(64);
    let reader_space = space.clone();
    std::thread::spawn(move || read_commands(&reader_space, &commands, &tx));
    let out_err =
        |e: std::io::Error| CliError::output(format!("{}: cannot write: {e}", path.display()));
    // created exclusively: never through a link planted under its name
    let (tmp, f) = e3d::io::create_temp_beside(path).map_err(out_err)?;
    let mut file = std::io::BufWriter::new(f);
    let result = (|| -> CliResult {
        let mut stdout = std::io::stdout().lock();
        let mut first = true;
        let label = format!("scene exec {}", scene.name);
        let known = (!commands_known.0).then_some(commands_known.1);
        if let Some(n) = known {
            say_cost(&label, scene, n, 1);
        }
        progress::track_stream(&label, "commands", |p| -> CliResult {
            if let Some(n) = known {
                p.set_total(n);
            }
            for r in rx {
                let c = r?;
                let m = world.motion(&c).map_err(world_error)?;
                p.add(1);
                let text = space.format(&c);
                m.write_csv(&mut file, Some(&text), first)
                    .map_err(out_err)?;
                let o = m.outcome;
                let mut row = String::new();
                if first {
                    row.push_str("command,effect,reward,x,y\n");
                }
                let _ = writeln!(
                    row,
                    "{text},{},{},{},{}",
                    o.effect, o.reward, o.point[0], o.point[1]
                );
                stdout
                    .write_all(row.as_bytes())
                    .and_then(|()| stdout.flush())
                    .map_err(|e| CliError::output(format!("standard output: {e}")))?;
                first = false;
            }
            Ok(())
        })?;
        use std::io::Write as _;
        file.flush().map_err(out_err)?;
        std::fs::rename(&tmp, path).map_err(out_err)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// How `e3d scene exec` executes a chunk of commands; it keeps its worlds
/// from one chunk to the next (building a physics world costs).
enum ExecPool<'a> {
    /// One world, one command after another: a grid, or a table look-up
    /// (microseconds a command).
    Direct(Box<dyn World + 'a>),
    /// A physics scene on every core: each piece of a chunk takes an idle
    /// world of `copies` copies (or builds one) and executes as a batch.
    Parallel {
        scene: &'a Scene,
        spec: &'a PhysicsSpec,
        copies: usize,
        idle: Mutex<Vec<PhysicsWorld>>,
    },
}

impl<'a> ExecPool<'a> {
    fn new(scene: &'a Scene, table: Option<OutcomeTable>) -> ExecPool<'a> {
        match (table, &scene.world) {
            (Some(t), _) => ExecPool::Direct(Box::new(t)),
            (None, WorldSpec::Grid(_)) => ExecPool::Direct(scene.build()),
            (None, WorldSpec::Physics(spec)) => ExecPool::Parallel {
                scene,
                spec,
                // as the outcome table: bit-identical to one copy per world
                copies: if spec.copies_are_exact() {
                    e3d::world::TABLE_COPIES
                } else {
                    1
                },
                idle: Mutex::new(Vec::new()),
            },
        }
    }

    /// Appends the result of each of `commands` to `out`, in order: those
    /// of [`World::execute`], bit for bit.
    /// With `memo`, the physics worlds' commands go through it
    /// ([`Memoized`](e3d::Memoized)): those kept are looked up, the others
    /// simulated once and kept.
    fn run(
        &mut self,
        commands: &[Command],
        memo: Option<&e3d::OutcomeMemo>,
        out: &mut Vec<Result<e3d::Outcome, WorldError>>,
    ) {
        use rayon::prelude::*;
        match self {
            // a grid's move or a table's look-up costs less than the memo's
            ExecPool::Direct(world) => world.execute_batch(commands, out),
            ExecPool::Parallel {
                scene,
                spec,
                copies,
                idle,
            } => {
                // shared by the workers
                let idle: &Mutex<_> = idle;
                // every thread gets a piece, of at most one batch
                let piece = commands
                    .len()
                    .div_ceil(rayon::current_num_threads())
                    .clamp(1, *copies);
                let take = || idle.lock().unwrap_or_else(|e| e.into_inner()).pop();
                let pieces: Vec<Vec<_>> = commands
                    .par_chunks(piece)
                    .map(|part| {
                        let mut world = take()
                            .unwrap_or_else(|| PhysicsWorld::with_copies(scene, spec, *copies));
                        let mut results = Vec::with_capacity(part.len());
                        if let Some(m) = memo {
                            let mut through = e3d::Memoized::new(world, m);
                            through.execute_batch(part, &mut results);
                            world = through.into_inner();
                        } else {
                            world.execute_batch(part, &mut results);
                        }
                        idle.lock().unwrap_or_else(|e| e.into_inner()).push(world);
                        results
                    })
                    .collect();
                out.extend(pieces.into_iter().flatten());
            }
        }
    }
}

/// The most commands `e3d scene exec` executes at once: two batches of
/// [`TABLE_COPIES`](e3d::world::TABLE_COPIES) per thread.
fn chunk_limit() -> usize {
    2 * rayon::current_num_threads() * e3d::world::TABLE_COPIES
}

/// What the folder `dir` holds for `scene`: a whole table (looked up), or
/// a memo of the commands executed so far (partial file, or empty when the
/// file is missing or cannot be used, having said why on stderr). The
/// memo's new outcomes are written back at the end (`OutcomeMemo::save`).
fn exec_cache(scene: &Scene, dir: &Path) -> (Option<OutcomeTable>, Option<e3d::OutcomeMemo>) {
    use e3d::world::CachedOutcomes;
    let path = OutcomeTable::cache_path(scene, dir);
    let space = scene.command_space();
    let memo = || e3d::OutcomeMemo::new(&space, scene.num_effects(), e3d::world::DEFAULT_MEMO_CAP);
    match OutcomeTable::read_file(&path, scene) {
        Ok(CachedOutcomes::Full(t)) => (Some(t), None),
        Ok(CachedOutcomes::Partial(entries)) => {
            let m = memo().ok();
            if let Some(m) = &m {
                m.extend(entries);
            }
            (None, m)
        }
        Err(e) => {
            let shown = path.display().to_string();
            let why = if e.kind() == std::io::ErrorKind::NotFound {
                format!("no outcome table {shown} yet")
            } else if e.to_string().contains(&shown) {
                format!("cannot use the outcome table {e}")
            } else {
                format!("cannot use the outcome table {shown}: {e}")
            };
            eprintln!("note: {why}; simulating the commands, keeping their outcomes there");
            (None, memo().ok())
        }
    }
}

/// `e3d scene exec`: a reader thread parses the commands as they come; the
/// main thread waits for one, takes what else is queued (up to
/// [`chunk_limit`]), executes that chunk on every core and prints its rows
/// in input order, flushed, before the next chunk. The first command that
/// does not parse or that blows up ends the output, after the rows before
/// it, with its error.
fn exec(scene: &Scene, commands: Vec<String>, table_cache: Option<&Path>) -> CliResult {
    let space = scene.command_space();
    let (table, memo) = match table_cache {
        Some(d) => exec_cache(scene, d),
        None => (None, None),
    };
    let label = format!("scene exec {}", scene.name);
    // what the commands cost, said before when their number is known, or
    // once those read so far reach it (stdin); a table looks them up
    let threads = rayon::current_num_threads();
    let known = (!commands.iter().any(|c| c == "-")).then_some(commands.len() as u64);
    let copies = match &scene.world {
        WorldSpec::Physics(p) if p.copies_are_exact() => e3d::world::TABLE_COPIES,
        _ => 1,
    };
    let mut cost_said = table.is_some()
        || known.is_some_and(|n| say_cost_copies(&label, scene, n, threads, copies));
    let per_command = if cost_said {
        0.0
    } else {
        e3d::world::batch_rollout_seconds(scene, copies) * calibration(scene)
    };
    let mut executed = 0u64;
    let mut executor = ExecPool::new(scene, table);
    let limit = chunk_limit();
    let (tx, rx) = std::sync::mpsc::sync_channel::<Read>(2 * limit);
    let reader_space = space.clone();
    // not joined: it may wait on stdin when the output ends with an error
    std::thread::spawn(move || read_commands(&reader_space, &commands, &tx));
    let mut stdout = std::io::stdout().lock();
    let mut write = |text: &str| {
        stdout
            .write_all(text.as_bytes())
            .and_then(|()| stdout.flush())
            .map_err(|e| CliError::output(format!("standard output: {e}")))
    };
    let header = "command,effect,reward,x,y\n";
    let mut header_written = false;
    let (mut chunk, mut results, mut text) = (Vec::new(), Vec::new(), String::new());
    let mut end: Option<CliError> = None;
    progress::track_stream(&label, "commands", |p| -> CliResult {
        if let Some(n) = known {
            p.set_total(n);
        }
        while end.is_none() {
            chunk.clear();
            let Ok(mut next) = rx.recv() else {
                break;
            };
            loop {
                match next {
                    Ok(c) => chunk.push(c),
                    Err(e) => {
                        end = Some(e);
                        break;
                    }
                }
                if chunk.len() == limit {
                    break;
                }
                match rx.try_recv() {
                    Ok(r) => next = r,
                    Err(_) => break,
                }
            }
            results.clear();
            executor.run(&chunk, memo.as_ref(), &mut results);
            p.add(chunk.len() as u64);
            executed += chunk.len() as u64;
            if !cost_said && executed as f64 * per_command / threads as f64 >= progress::LONG {
                cost_said = true;
                p.say(format!(
                    "{label}: {executed} commands so far{}, about {} each on {threads} thread(s) by the cost model, calibrated here; more as stdin gives them",
                    steps_text(scene),
                    seconds_text(per_command)
                ));
            }
            text.clear();
            for (c, r) in chunk.iter().zip(results.drain(..)) {
                match r {
                    Ok(o) => {
                        let _ = writeln!(
                            text,
                            "{},{},{},{},{}",
                            space.format(c),
                            o.effect,
                            o.reward,
                            o.point[0],
                            o.point[1]
                        );
                    }
                    Err(e) => {
                        end = Some(world_error(e));
                        break;
                    }
                }
            }
            if !text.is_empty() {
                if !header_written {
                    text.insert_str(0, header);
                    header_written = true;
                }
                write(&text)?;
            }
        }
        Ok(())
    })?;
    if let (Some(m), Some(dir)) = (memo.as_ref().filter(|m| !m.is_empty()), table_cache) {
        let path = OutcomeTable::cache_path(scene, dir);
        if let Err(e) = m.save(&path, scene) {
            eprintln!(
                "note: could not keep the outcomes in {}: {e}",
                path.display()
            );
        }
    }
    match end {
        Some(e) => Err(e),
        None if header_written => Ok(()),
        None => write(header),
    }
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
    let table = build_table(scene)?;
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
    let declared = rewarded_cells(scene);
    let rule = (cell.row, cell.col);
    if declared.is_empty() {
        println!(
            "the scene declares no reward cell; by the rule it would be {rule:?}: `reward: (cells: [{rule:?}])`"
        );
    } else if declared == [rule] {
        println!("the scene's reward cells {declared:?} match the rule's cell");
    } else {
        println!("the scene's reward cells {declared:?} do NOT match the rule's cell {rule:?}");
    }
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
    let threads = rayon::current_num_threads();
    let secs = n as f64 * e3d::world::rollout_seconds(scene) * calibration(scene) / threads as f64;
    let all: Vec<e3d::world::RunStats> = simulate_all(scene, n, secs, |progress| {
        (0..n)
            .into_par_iter()
            .map_init(
                || PhysicsWorld::from_scene(scene, spec),
                |w, i| {
                    let stats = w.inspect(&space.command_at(i));
                    progress(1);
                    stats
                },
            )
            .collect::<Result<_, _>>()
    })
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
    let start = std::time::Instant::now();
    let (table, existed) = match cache {
        Some(dir) => cached_table(scene, dir)?,
        None => (build_table(scene)?, false),
    };
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

/// Says on stderr how many commands of `scene` are about to be simulated
/// (`simulated`: fewer than all with a symmetry) and what that costs by
/// the cost model (`seconds`), then runs `work` with its progress shown
/// there (see [`progress::track`]).
fn simulate_all<T>(
    scene: &Scene,
    simulated: u64,
    seconds: f64,
    work: impl FnOnce(&(dyn Fn(u64) + Sync)) -> T,
) -> T {
    let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
    let what = if simulated < n {
        format!("{simulated} of {n} commands (the others are mirror images)")
    } else {
        format!("{simulated} commands")
    };
    eprintln!(
        "scene {}: simulating {what} on {} thread(s){}: about {} by the cost model (calibrated on timed rollouts here)",
        scene.name,
        rayon::current_num_threads(),
        steps_text(scene),
        seconds_text(seconds)
    );
    progress::track(
        &format!("scene {}", scene.name),
        "commands",
        simulated,
        |p| work(&|k| p.add(k)),
    )
}

/// [`OutcomeTable::build_scene`], its cost and progress on stderr.
fn build_table(scene: &Scene) -> Result<OutcomeTable, CliError> {
    let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
    let simulated = OutcomeTable::simulated_commands(scene).unwrap_or(n);
    simulate_all(scene, simulated, table_seconds(scene), |progress| {
        OutcomeTable::build_scene_with_progress(scene, progress)
    })
    .map_err(world_error)
}

/// The cost model's seconds for building the whole table of `scene` on
/// the current threads (0 when no table is possible).
fn table_seconds(scene: &Scene) -> f64 {
    e3d::world::ExecutionPlan::choose(
        scene,
        &e3d::world::Workload {
            trials: 0,
            sessions: 1,
            threads: rayon::current_num_threads(),
        },
        None,
        0,
    )
    .table_seconds
    .unwrap_or(0.0)
        * calibration(scene)
}

/// ` (120 steps each)` for a physics scene (nothing for a grid).
fn steps_text(scene: &Scene) -> String {
    match &scene.world {
        WorldSpec::Physics(p) => format!(
            " ({} steps each)",
            p.schedule.total_steps(p.dt, scene.num_slots())
        ),
        WorldSpec::Grid(_) => String::new(),
    }
}

/// The cost model's estimate for `commands` rollouts of `scene` on
/// `threads` threads, said on stderr (`LABEL: N commands, S steps each,
/// on T thread(s): about X by the cost model`) when it reaches
/// [`progress::LONG`]; whether it was said.
fn say_cost(label: &str, scene: &Scene, commands: u64, threads: usize) -> bool {
    say_cost_copies(label, scene, commands, threads, 1)
}

/// [`say_cost`] for commands run `copies` to a world (as `scene exec`
/// does on scenes whose copies are exact).
fn say_cost_copies(
    label: &str,
    scene: &Scene,
    commands: u64,
    threads: usize,
    copies: usize,
) -> bool {
    let model =
        commands as f64 * e3d::world::batch_rollout_seconds(scene, copies) / threads.max(1) as f64;
    // one rollout is timed by doing it: no calibration for a command or two
    // that the model puts far below a second
    if commands <= 2 && model < 0.05 * progress::LONG {
        return false;
    }
    let secs = model * calibration(scene);
    if secs < progress::LONG {
        return false;
    }
    eprintln!(
        "{label}: {commands} command(s){} on {threads} thread(s): about {} (the cost model, calibrated on {} timed rollouts here)",
        steps_text(scene),
        seconds_text(secs),
        calibration_rollouts(scene)
    );
    true
}

/// The cost model's factor for this machine as loaded now
/// ([`e3d::world::calibration`]: a few rollouts of `scene` timed), measured
/// once per scene and process.
fn calibration(scene: &Scene) -> f64 {
    static CACHE: Mutex<Vec<(String, f64)>> = Mutex::new(Vec::new());
    let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, f)) = cache.iter().find(|(n, _)| *n == scene.name) {
        return *f;
    }
    let f = e3d::world::calibration(scene);
    cache.push((scene.name.clone(), f));
    f
}

/// How many rollouts [`calibration`] timed ("a few" for a grid, which is
/// not timed).
fn calibration_rollouts(scene: &Scene) -> String {
    match scene.world {
        WorldSpec::Grid(_) => "no".into(),
        WorldSpec::Physics(_) => format!("at least {}", e3d::world::CALIBRATION_ROLLOUTS),
    }
}

/// The table of `scene` as [`OutcomeTable::cached`] gives it, with the
/// progress of its building shown ([`build_table`]), and whether it was
/// read from `dir`.
fn cached_table(scene: &Scene, dir: &Path) -> Result<(OutcomeTable, bool), CliError> {
    use e3d::world::CachedOutcomes;
    let path = OutcomeTable::cache_path(scene, dir);
    let table = match OutcomeTable::read_file(&path, scene) {
        Ok(CachedOutcomes::Full(t)) => return Ok((t, true)),
        // what the partial file holds is not simulated again
        Ok(CachedOutcomes::Partial(known)) => {
            eprintln!(
                "scene {}: {} outcomes read from {}; simulating the others",
                scene.name,
                known.len(),
                path.display()
            );
            let n = scene.command_space().num_commands().unwrap_or(u64::MAX);
            let simulated = OutcomeTable::simulated_commands(scene)
                .unwrap_or(n)
                .saturating_sub(known.len() as u64);
            let whole = OutcomeTable::simulated_commands(scene).unwrap_or(n).max(1);
            let secs = table_seconds(scene) * simulated as f64 / whole as f64;
            simulate_all(scene, simulated, secs, |progress| {
                OutcomeTable::complete_with_progress(scene, &known, progress)
            })
            .map_err(world_error)?
        }
        Err(_) => build_table(scene)?,
    };
    // a cache that cannot be written is not an error: it costs time only
    let _ = table.write_file(&path, scene);
    Ok((table, false))
}
