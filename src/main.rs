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
    /// Measure what a scene costs: rollouts/s, steps/s, E3D trials/s.
    Bench(cli::bench::BenchArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Cmd::Run(a) => cli::run::run(a),
        Cmd::Reproduce(a) => cli::reproduce::run(a),
        Cmd::Bench(a) => cli::bench::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => cli::report_error(&e),
    }
}
