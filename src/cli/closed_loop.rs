//! `e3d closed-loop`: closed-loop E3D against open-loop E3D, Q-learning
//! (over whole commands, and per move with optimistic values) and the
//! uniform policy on equal budgets of moves
//! ([`e3d::experiment::closed_loop`], its table
//! [`e3d::report::closed_loop::markdown`]).

use super::output::{prepare_out, write_file};
use super::{load_scene, plural, CliError, CliResult};
use crate::cli::console::{errln, outln};
use clap::Args;
use e3d::experiment::closed_loop::{run_comparison, ClosedLoopConfig};
use e3d::report::closed_loop::markdown;
use e3d::Params;
use std::path::PathBuf;

/// Arguments of `e3d closed-loop`.
#[derive(Args, Debug)]
pub struct ClosedLoopArgs {
    /// A scene whose command is `Repeat`: a grid scene, or a physics
    /// scene on a `Sequential` schedule (path or built-in name).
    #[arg(default_value = "four_rooms")]
    pub scene: String,
    /// Episodes per session.
    #[arg(long, default_value_t = 5000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub episodes: u64,
    /// Sessions per arm (seeds 0..N).
    #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub seeds: u64,
    /// Commands per episode of the closed-loop arms (K); the open-loop arms
    /// take one command of K times the scene's moves.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u64).range(1..=64))]
    pub commands: u64,
    /// Inverse temperature of the E3D arms.
    #[arg(long, default_value_t = Params::TASK2.beta)]
    pub beta: f64,
    /// Discount of Q_ref and of Q-learning, in [0, 1].
    #[arg(long, default_value_t = e3d::learner::ClosedLoopE3d::GAMMA)]
    pub gamma: f64,
    /// The value every action-value of the arm qlearning_moves starts at
    /// (1: optimistic; 0: the plain start).
    #[arg(long, default_value_t = Params::TASK2.initial)]
    pub initial: f64,
    /// The exploration rate of the arm qlearning_moves, in [0, 1].
    #[arg(long, default_value_t = e3d::experiment::closed_loop::MOVES_EPSILON)]
    pub moves_epsilon: f64,
    #[command(flatten)]
    pub threads: super::session::ThreadsArg,
    /// Also write closed_loop.md, closed_loop.csv (its figures and
    /// intervals) and sessions.csv in this folder.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Replace the files of an earlier comparison in --out.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: ClosedLoopArgs) -> CliResult {
    let scene = load_scene(&a.scene)?;
    let params = Params {
        beta: a.beta,
        initial: a.initial,
        ..Params::TASK2
    };
    let moves = Params {
        epsilon: a.moves_epsilon,
        ..params
    };
    moves
        .validate()
        .map_err(|e| CliError::input(format!("--moves-{e}")))?;
    params
        .validate()
        .map_err(|e| CliError::input(format!("--{e}")))?;
    e3d::learner::contextual::check_gamma(a.gamma)
        .map_err(|e| CliError::input(format!("--{e}")))?;
    e3d::experiment::closed_loop::check_scene(&scene, a.commands as usize).map_err(|e| {
        CliError::input(
            e.to_string()
                .replace("commands per episode (K)", "--commands"),
        )
    })?;
    let cfg = ClosedLoopConfig {
        episodes: a.episodes as usize,
        seeds: a.seeds,
        commands: a.commands as usize,
        params,
        gamma: a.gamma,
        moves_epsilon: a.moves_epsilon,
    };
    if let Some(out) = &a.out {
        prepare_out(
            out,
            &["closed_loop.md", "closed_loop.csv", "sessions.csv"],
            a.force,
        )?;
    }
    let threads = a.threads.count();
    let moves = scene.spec().num_slots() * cfg.commands;
    let (name, commands, seeds) = (&scene.spec().name, cfg.commands, cfg.seeds);
    let (episodes, c, s) = (cfg.episodes, plural(commands), plural(threads));
    errln!("closed-loop: {name} on {commands} command{c}, {seeds} sessions per arm of {episodes} episodes of {moves} moves, {threads} thread{s}");
    let sessions = super::session::ThreadsArg::pool_of(threads)?
        .install(|| run_comparison(&scene, &cfg))
        .map_err(CliError::input)?;
    let md = markdown(&sessions, &cfg, moves);
    if let Some(out) = &a.out {
        let mut csv = String::from("arm,seed,first_reward_episode,cumulative_reward,late_reward\n");
        for s in &sessions {
            let (arm, seed, reward, late) = (&s.arm, s.seed, s.cumulative_reward, s.late_reward);
            let first = (s.first_reward_episode).map_or(String::new(), |e| e.to_string());
            csv.push_str(&format!("{arm},{seed},{first},{reward},{late}\n"));
        }
        write_file(&out.join("closed_loop.md"), md.as_bytes())?;
        let figures = e3d::report::closed_loop::csv(&sessions);
        write_file(&out.join("closed_loop.csv"), figures.as_bytes())?;
        write_file(&out.join("sessions.csv"), csv.as_bytes())?;
    }
    outln!("{md}");
    Ok(())
}
