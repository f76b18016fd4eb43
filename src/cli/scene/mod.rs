//! `e3d scene`: check, draw and execute scene files.

mod check;
mod exec;
mod mjcf;
mod render;
mod reward_cell;
pub(super) mod simulate;
mod stats;
mod table;
mod values;

use super::{load_scene, CliError, CliResult};
use check::{check, check_accuracy, check_reach};
use clap::{Args, Subcommand};
use exec::{exec, exec_trace};
use render::{animate, render};
use reward_cell::reward_cell;
use stats::stats;
use std::path::PathBuf;
use table::table;

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
        /// executed whole, and the counts are exact. At most 100000000,
        /// as `run --trials`.
        #[arg(long, value_name = "N", default_value_t = 200, value_parser = clap::value_parser!(u64).range(0..=100_000_000))]
        samples: u64,
        /// The seed of the sample.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Also measure accuracy against cost on a physics scene: N seeded
        /// random commands (default 200) run at 1, 2, 3, 4 and 8 solver
        /// iterations per step (and the scene's own), each compared with a
        /// converged run (dt / 4, 8 iterations): how many land in its
        /// cell, and what a command costs on one thread.
        #[arg(long, value_name = "N", num_args = 0..=1, default_missing_value = "200", value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
        accuracy: Option<u64>,
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
        /// On a scene with start contexts: draw only the context NAME's
        /// start (and the command's path from it); with `--animate`, the
        /// rollout from that start. Without it, every context gets a panel,
        /// stacked, titled with its name (an animation starts where the
        /// scene lists its bodies); a drawn context (a range) shows its
        /// seed-0 draw, as `scene exec` runs it.
        #[arg(long, value_name = "NAME")]
        context: Option<String>,
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
        /// Run each command R times under the scene's `noise` and print,
        /// per command, its modal effect and the share of the R runs that
        /// end in it (`command,effect,share,runs`, `values,...` for a
        /// continuous scene); a noise-free scene's share is 1. Scenes
        /// without start contexts.
        #[arg(long, value_name = "R", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1_000_000), conflicts_with_all = ["trace", "table_cache"])]
        repeat: u32,
        /// The seed of a noisy scene's draws: command `i` of the input, run
        /// `r`, draws from `draw_key(draw_key(seed, r), i)` (docs/scenes.md,
        /// "Noise").
        #[arg(long, value_name = "S", default_value_t = 0)]
        seed: u64,
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
    /// Write a physics scene as a MuJoCo model (MJCF) in the x-y plane:
    /// bodies, masses and inertias as Rapier has them, joints, motors,
    /// gravity, the time step, and an actuator for every action, with the
    /// table that replays a command (docs/mjcf.md).
    Export {
        /// A scene file, or the name of a built-in scene.
        scene: String,
        /// Write MJCF (the one format exported).
        #[arg(long, required = true)]
        mjcf: bool,
        /// The file to write (default: standard output).
        #[arg(long, value_name = "FILE.xml")]
        out: Option<PathBuf>,
    },
    /// Read the planar subset of an MJCF model (bodies in the x-y plane,
    /// hinges about z, slides in the plane, sphere, box and capsule geoms,
    /// motor and position actuators) and write it as a RON scene to edit
    /// (docs/mjcf.md); anything outside the subset is refused with its line.
    Import {
        /// The MJCF file.
        model: PathBuf,
        /// The scene file to write (default: standard output).
        #[arg(long, value_name = "FILE.ron")]
        out: Option<PathBuf>,
    },
    /// Execute every command of a physics scene and report what happens:
    /// contacts between moving bodies, joints at their limits, top speeds.
    Stats {
        /// A scene file, or the name of a built-in scene.
        scene: String,
    },
}

impl SceneCmd {
    /// The scene the sub-command works on, as given.
    fn scene(&self) -> &str {
        use SceneCmd as C;
        match self {
            C::Check { scene, .. }
            | C::Render { scene, .. }
            | C::Exec { scene, .. }
            | C::RewardCell { scene, .. }
            | C::Table { scene, .. }
            | C::Stats { scene, .. }
            | C::Export { scene, .. } => scene,
            C::Import { model, .. } => model.to_str().unwrap_or_default(),
        }
    }
}

/// `e3d scene ...` on a continuous scene: the sub-commands that differ
/// (`exec`, `render --command`) and those that cannot apply (`table`,
/// `reward-cell`, `stats`, which enumerate the commands); `None` for the
/// others, and for scenes of symbols (the plain path then runs them).
fn continuous(cmd: &SceneCmd, scene: &e3d::Scene) -> Option<CliResult> {
    use SceneCmd as C;
    let continuous = scene.as_continuous()?;
    let refuse = |what: &str| Some(scene.spec().require_symbols(what).map_err(CliError::input));
    match cmd {
        C::Exec {
            commands,
            table_cache: None,
            trace,
            repeat,
            seed,
            ..
        } => Some(values::exec(
            continuous,
            commands,
            trace.as_deref(),
            (*repeat, *seed),
        )),
        C::Exec { .. } => refuse("`e3d scene exec --table-cache` (an outcome table)"),
        C::Render {
            command: Some(text),
            animate,
            out,
            ..
        } => Some(values::render(continuous, text, *animate, out)),
        C::RewardCell { .. } => refuse("`e3d scene reward-cell` (which executes every command)"),
        C::Table { .. } => refuse("`e3d scene table` (an outcome table)"),
        C::Stats { .. } => refuse("`e3d scene stats` (which executes every command)"),
        C::Render { .. } | C::Check { .. } | C::Export { .. } | C::Import { .. } => None,
    }
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

/// Refuses, before any work, an output file named for a format the
/// subcommand does not write (`render --out x.png`), and a cache folder
/// that is a file.
fn check_outputs(cmd: &SceneCmd) -> CliResult {
    use super::output::{check_cache_folder, check_format};
    match cmd {
        SceneCmd::Render {
            animate: true, out, ..
        } => check_format(out, "--out", &["svg", "html", "htm"], ""),
        SceneCmd::Render { out, .. } => {
            let hint = " (for a raster image: Python's `Scene.render`, or convert the SVG, e.g. `rsvg-convert x.svg -o x.png`)";
            check_format(out, "--out", &["svg"], hint)
        }
        SceneCmd::Exec {
            trace, table_cache, ..
        } => {
            if let Some(t) = trace {
                check_format(t, "--trace", &["csv"], "")?;
            }
            (table_cache.as_deref()).map_or(Ok(()), |d| check_cache_folder(d, "--table-cache"))
        }
        SceneCmd::Table { cache: Some(d), .. } => check_cache_folder(d, "--cache"),
        SceneCmd::Export { out: Some(o), .. } => check_format(o, "--out", &["xml"], ""),
        SceneCmd::Import { out: Some(o), .. } => check_format(o, "--out", &["ron"], ""),
        _ => Ok(()),
    }
}

/// Runs `e3d scene ...`.
pub fn run(a: SceneArgs) -> CliResult {
    check_outputs(&a.command)?;
    if let SceneCmd::Import { model, out } = &a.command {
        return mjcf::import(model, out.as_deref());
    }
    let scene = load_scene(a.command.scene())?;
    if let Some(r) = continuous(&a.command, &scene) {
        return r;
    }
    match a.command {
        SceneCmd::Check { expanded: true, .. } => {
            crate::cli::console::write_stdout(scene.spec().to_ron().as_bytes())
        }
        SceneCmd::Check {
            samples,
            seed,
            accuracy,
            ..
        } => {
            check(&scene)?;
            check_reach(&scene, samples, seed)?;
            accuracy.map_or(Ok(()), |n| check_accuracy(&scene, n, seed))
        }
        SceneCmd::Render {
            command,
            context,
            animate: true,
            out,
            ..
        } => animate(
            &scene,
            command.as_deref().unwrap_or(""),
            context.as_deref(),
            &out,
        ),
        SceneCmd::Render {
            command,
            context,
            out,
            ..
        } => render(&scene, command.as_deref(), context.as_deref(), &out),
        SceneCmd::Exec {
            commands,
            trace: Some(path),
            seed,
            ..
        } => exec_trace(&scene, commands, &path, seed),
        SceneCmd::Exec {
            commands,
            table_cache,
            repeat,
            seed,
            ..
        } => exec(&scene, commands, table_cache.as_deref(), (repeat, seed)),
        SceneCmd::RewardCell { from, .. } => reward_cell(&scene, from),
        SceneCmd::Stats { .. } => stats(&scene),
        SceneCmd::Export { out, .. } => mjcf::export(&scene, out.as_deref()),
        SceneCmd::Import { .. } => unreachable!("imports load no scene"),
        SceneCmd::Table { cache, .. } => table(&scene, cache.as_deref()),
    }
}
