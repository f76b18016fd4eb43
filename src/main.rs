//! The `e3d` command line: a thin layer over the library.

mod cli;

use clap::parser::ValueSource;
use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};
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
    Run(cli::session::RunArgs),
    /// Reproduce the paper's Figures 2 and 3 on two_rooms (SVG, CSV, summary.md).
    Reproduce(cli::reproduce::ReproduceArgs),
    /// Measure what a scene costs: rollouts/s, steps/s, E3D trials/s (CSV; each
    /// figure the median and the best of 5 slices of its time).
    Bench(cli::bench::BenchArgs),
    /// Compare every drive (e3d, e3d_relax, count, smm, uniform, egreedy,
    /// goal_babbling, archive) on the canonical scenes: a table and a figure.
    Compare(cli::compare::CompareArgs),
    /// Closed loop against open loop on equal budgets of moves: closed-loop
    /// E3D (K commands), open-loop E3D (one command of K times the moves),
    /// Q-learning and uniform on a grid scene or a sequential physics
    /// scene (default four_rooms).
    ClosedLoop(cli::closed_loop::ClosedLoopArgs),
    /// Run a sweep file: every (cell, seed) session, in parallel, resumably.
    Sweep(cli::sweep::SweepArgs),
    /// Join the output folders of the shards of one sweep.
    Merge(cli::sweep::MergeArgs),
    /// Draw a sweep's summary: a line plot over one parameter, a heat map over two.
    Plot(cli::plot::PlotArgs),
    /// Check, draw or execute a scene: `check`, `render`, `exec`, `table`, `reward-cell`, `stats`.
    Scene(cli::scene::SceneArgs),
    /// One HTML page for a run folder: effects early and late, reward, policy per slot.
    Report(cli::report::ReportArgs),
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

/// Whether standard output was closed when e3d started (`>&-`). Rust's
/// runtime then opens /dev/null in its place, read-write, and would
/// discard the results silently; a shell's `> /dev/null` opens it
/// write-only. So a read-write /dev/null on descriptor 1 means closed.
fn stdout_was_closed() -> bool {
    #[cfg(unix)]
    // SAFETY: fcntl and fstat only read the descriptor's state; stat reads
    // a path literal into a zeroed struct
    unsafe {
        let flags = libc::fcntl(1, libc::F_GETFL);
        if flags == -1 {
            return true;
        }
        if flags & libc::O_ACCMODE != libc::O_RDWR {
            return false;
        }
        let mut out: libc::stat = std::mem::zeroed();
        let mut null: libc::stat = std::mem::zeroed();
        libc::fstat(1, &mut out) == 0
            && libc::stat(c"/dev/null".as_ptr(), &mut null) == 0
            && (out.st_mode & libc::S_IFMT) == libc::S_IFCHR
            && out.st_rdev == null.st_rdev
    }
    #[cfg(not(unix))]
    false
}

fn main() -> ExitCode {
    default_sigpipe();
    if stdout_was_closed() {
        cli::console::errln!("error: standard output is closed; e3d writes its results there (redirect it to a file or to /dev/null)");
        return ExitCode::from(cli::exit::OUTPUT);
    }
    // temporary files go on Ctrl-C and SIGTERM, and at the end whatever
    // the outcome (an error half-way leaves none)
    e3d::io::remove_temps_on_signals();
    let matches = Cli::command().get_matches();
    let mut cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let (Cmd::Run(a), Some(("run", m))) = (&mut cli.command, matches.subcommand()) {
        // clap's ids of the flags are the parameters' names (`goal_progress`
        // for `--goal-progress`)
        a.given_params = e3d::Params::NAMES
            .into_iter()
            .filter(|id| m.value_source(id) == Some(ValueSource::CommandLine))
            .collect();
    }
    let result = match cli.command {
        Cmd::Run(a) => cli::run::run(a),
        Cmd::Reproduce(a) => cli::reproduce::run(a),
        Cmd::Bench(a) => cli::bench::run(a),
        Cmd::Sweep(a) => cli::sweep::run(a),
        Cmd::Compare(a) => cli::compare::run(a),
        Cmd::ClosedLoop(a) => cli::closed_loop::run(a),
        Cmd::Merge(a) => cli::sweep::merge(a),
        Cmd::Plot(a) => cli::plot::run(a),
        Cmd::Scene(a) => cli::scene::run(a),
        Cmd::Report(a) => cli::report::run(a),
    };
    cli::output::release_locks();
    e3d::io::remove_temps();
    // what is still buffered: a failed flush is a failed write too
    let flushed = std::io::Write::flush(&mut std::io::stdout());
    match (result, flushed) {
        (Ok(()), Ok(())) => ExitCode::SUCCESS,
        (Ok(()), Err(e)) => cli::report_error(&cli::CliError::output(format!(
            "cannot write to standard output: {e}"
        ))),
        (Err(e), _) => {
            cli::output::remove_created_if_empty();
            cli::report_error(&e)
        }
    }
}
