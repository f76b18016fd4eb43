//! The `e3d` command line: a thin layer over the library.

mod cli;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// e3d: learn compositional motor commands by End-Effect Exploration.
#[derive(Parser)]
#[command(name = "e3d", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run one learning session on a scene and print a summary.
    Run(cli::run::RunArgs),
    /// Reproduce the paper's Figures 2 and 3 on two_rooms (SVG, CSV, summary.md).
    Reproduce(cli::reproduce::ReproduceArgs),
    /// Measure what a scene costs: rollouts/s, steps/s, E3D trials/s (CSV; each
    /// figure the median and the best of 5 slices of its time).
    Bench(cli::bench::BenchArgs),
    /// Run a sweep file: every (cell, seed) session, in parallel, resumably.
    Sweep(cli::sweep::SweepArgs),
    /// Join the output folders of the shards of one sweep.
    Merge(cli::sweep::MergeArgs),
    /// Draw a sweep's summary: a line plot over one parameter, a heat map over two.
    Plot(cli::plot::PlotArgs),
    /// Check, draw or execute a scene: `check`, `render`, `exec`, `table`, `reward-cell`, `stats`.
    Scene(cli::scene::SceneArgs),
}

/// Lets a closed pipe end the program quietly, as it does other Unix tools
/// (`e3d scene exec arm7 - | head`): Rust ignores SIGPIPE, so a write to a
/// closed stdout would otherwise panic with a backtrace.
fn default_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first thing in `main`, before any thread starts;
    // restoring a signal's default disposition has no other effect
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn main() -> ExitCode {
    default_sigpipe();
    let cli = Cli::parse();
    let result = match cli.command {
        Cmd::Run(a) => cli::run::run(a),
        Cmd::Reproduce(a) => cli::reproduce::run(a),
        Cmd::Bench(a) => cli::bench::run(a),
        Cmd::Sweep(a) => cli::sweep::run(a),
        Cmd::Merge(a) => cli::sweep::merge(a),
        Cmd::Plot(a) => cli::plot::run(a),
        Cmd::Scene(a) => cli::scene::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => cli::report_error(&e),
    }
}
