//! `e3d compare`: every drive on the canonical scenes, one table and one
//! figure (the sweep `scenes/sweeps/drives.ron`, run in memory).

use super::output::{prepare_out, write_file};
use super::progress;
use super::sweep::sweep_error;
use super::CliResult;
use crate::cli::console::{errln, outln};
use clap::Args;
use e3d::experiment::drives::{drives_sweep, with_reachable_cells};
use e3d::report::drives::DriveComparison;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `e3d compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The folder for drives.md, drives.csv, drives.svg and results.csv.
    #[arg(long, default_value = "out/drives", value_name = "DIR")]
    pub out: PathBuf,
    /// Sessions per learner, scene and task.
    #[arg(long, default_value_t = 200, value_parser = clap::value_parser!(u64).range(1..=100_000))]
    pub sessions: u64,
    /// Trials per session.
    #[arg(long, default_value_t = 5000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    pub trials: u64,
    /// Only these scenes (built-in names, comma-separated; default:
    /// two_rooms, puck_rooms, arm7, maze3).
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    pub scenes: Vec<String>,
    /// Only these learners (comma-separated; default: e3d, e3d_relax,
    /// count, smm, uniform, egreedy, goal_babbling, archive);
    /// qlearning_moves runs each trial as an episode of the scene's moves,
    /// one by one (scenes whose command is `Repeat`).
    #[arg(long, value_delimiter = ',', value_name = "NAMES")]
    pub learners: Vec<String>,
    #[command(flatten)]
    pub threads: super::session::ThreadsArg,
    /// Replace the files of an earlier comparison in --out.
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: CompareArgs) -> CliResult {
    let names: Vec<&str> = a.scenes.iter().map(String::as_str).collect();
    check_scene_names(&names)?;
    let learners: Vec<&str> = a.learners.iter().map(String::as_str).collect();
    check_learner_names(&learners)?;
    let files = ["drives.md", "drives.csv", "drives.svg", "results.csv"];
    prepare_out(&a.out, &files, a.force)?;
    let sweep = drives_sweep(a.sessions as usize, a.trials as usize, &names, &learners)
        .map_err(|e| {
            // the sweep is built from the flags: speak of them, not of a
            // `<SweepSpec>` the user never wrote
            let mut e = sweep_error(e);
            e.message = e
                .message
                .replace("<SweepSpec>: field `scenes`", "--scenes")
                .replace("<SweepSpec>: field `sessions`", "--sessions")
                .replace("<SweepSpec>: field `trials`", "--trials")
                .replace("<SweepSpec>", "compare");
            e
        })?
        .with_notices(|line| errln!("outcomes: {line}"));
    let threads = a.threads.count();
    // the reachable cells of each scene, from its outcome table: the
    // reference of the coverage measures
    let sweep = super::session::ThreadsArg::pool_of(threads)?
        .install(|| with_reachable_cells(sweep, None))
        .map_err(sweep_error)?;
    let total = sweep.num_sessions() as u64 * a.trials;
    let (learners, scenes) = (sweep.spec.learners.len(), sweep.scenes().len());
    let (cells, sessions, trials) = (sweep.cells().len(), a.sessions, a.trials);
    let s = super::plural(threads);
    errln!("compare: {learners} learners on {scenes} scenes, tasks 1 and 2: {cells} cells x {sessions} sessions of {trials} trials, {threads} thread{s}");
    let start = Instant::now();
    let (sweep, results) = progress::track("compare", "trials", total, |p| {
        let sweep = sweep.with_trial_counter(p.counter());
        let results = sweep.run(threads);
        (sweep, results)
    });
    let results = results.map_err(sweep_error)?;
    let cmp = DriveComparison::new(&sweep, &results);
    let mut rows = sweep.results_header();
    rows.push('\n');
    for r in &results {
        rows.push_str(&sweep.result_row(r));
        rows.push('\n');
    }
    let md = cmp.markdown();
    for (name, bytes) in [
        ("drives.md", md.as_bytes()),
        ("drives.csv", cmp.csv().as_bytes()),
        ("drives.svg", cmp.svg().as_bytes()),
        ("results.csv", rows.as_bytes()),
    ] {
        write_file(&a.out.join(name), bytes)?;
    }
    outln!("{md}");
    let (out, secs) = (a.out.display(), start.elapsed().as_secs_f64());
    outln!("wrote drives.md, drives.csv, drives.svg and results.csv in {out} ({secs:.1} s)");
    Ok(())
}

/// `--learners`: built-in learners' names, each once.
fn check_learner_names(names: &[&str]) -> CliResult {
    let mut seen = std::collections::HashSet::new();
    for n in names {
        if let Err(e) = n.parse::<e3d::LearnerKind>() {
            return Err(super::CliError::input(format!("--learners: {e}")));
        }
        if !seen.insert(*n) {
            return Err(super::CliError::input(format!(
                "--learners {}: `{n}` is listed twice; expected each learner once",
                names.join(",")
            )));
        }
    }
    Ok(())
}

/// `--scenes` as the user wrote them: each named once, none empty
/// (checked before any folder is made).
fn check_scene_names(names: &[&str]) -> CliResult {
    let mut seen = std::collections::HashSet::new();
    for n in names {
        if n.trim().is_empty() {
            return Err(super::CliError::input(format!(
                "--scenes {}: an empty scene name; expected comma-separated scene names or files",
                names.join(",")
            )));
        }
        if !seen.insert(*n) {
            return Err(super::CliError::input(format!(
                "--scenes {}: `{n}` is listed twice; expected each scene once",
                names.join(",")
            )));
        }
    }
    Ok(())
}
