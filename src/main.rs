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
    /// Check, draw or execute a scene: `check`, `render`, `exec`, `reward-cell`, `stats`.
    Scene(cli::scene::SceneArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Cmd::Run(a) => cli::run::run(a),
        Cmd::Scene(a) => cli::scene::run(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => cli::report_error(&e),
    }
}
