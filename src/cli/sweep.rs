//! `e3d sweep` and `e3d merge`: grids of sessions, resumable, in shards.

use super::{plural, progress, CliError, CliResult};
use crate::cli::console::{errln, outln};
use clap::Args;
use e3d::sweep::{self, DirOptions, DirReport, Shard, Sweep, SweepError};
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `e3d sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    /// The sweep file (RON, see docs/sweeps.md).
    pub file: PathBuf,
    /// The output folder: results.csv, summary.csv, sweep.ron, version.txt,
    /// journal.txt.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    #[command(flatten)]
    pub threads: super::session::ThreadsArg,
    /// Complete the sweep that --out holds (only the missing sessions run).
    #[arg(long)]
    pub resume: bool,
    /// Run only the K-th of N disjoint parts (1 <= K <= N); join the parts
    /// with `e3d merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Keep the scenes' outcome tables (every command executed once) in DIR
    /// and reuse them across runs, resumes and shards.
    #[arg(long, value_name = "DIR")]
    pub table_cache: Option<PathBuf>,
    #[command(flatten)]
    pub memo: super::session::MemoArgs,
}

/// Arguments of `e3d merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The output folders of every shard of one sweep.
    #[arg(required = true, value_name = "DIR")]
    pub dirs: Vec<PathBuf>,
    /// The folder to write the joined results into (must not exist or be
    /// empty).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

pub(crate) fn sweep_error(e: SweepError) -> CliError {
    match e {
        SweepError::Input(_) => CliError::input(e),
        SweepError::Io { .. } | SweepError::Output(_) => CliError::output(e),
        _ => CliError::simulation(e),
    }
}

pub fn run(a: SweepArgs) -> CliResult {
    if let Some(dir) = &a.table_cache {
        super::output::check_cache_folder(dir, "--table-cache")?;
    }
    let sweep = configured(&a)?;
    let threads = a.threads.count();
    let shard = a.shard.unwrap_or(Shard::ALL);
    let plan = plan_line(&a, &sweep, shard, threads);
    // one run at a time in a folder: two would both do all the work
    super::output::lock_out(&a.out)?;
    let start = Instant::now();
    let per_session = sweep.spec.trials as u64;
    // progress counts trials, so that sessions in lockstep, which all end
    // together, still move it; its total is known once the folder is read
    let report = progress::track("sweep", "trials", 0, |p| {
        // a table built before the trials shows its own count and ETA
        let phase = p.phase();
        let on_table = move |scene: &str, k, total| match total {
            0 => phase.end(),
            _ => {
                phase.enter(&format!("sweep: table of {scene}"), "commands", total);
                phase.add(k);
            }
        };
        let sweep = sweep
            .with_trial_counter(p.counter())
            .with_table_progress(on_table);
        let mut planned = false;
        sweep.run_to_dir(
            &a.out,
            &DirOptions {
                threads,
                resume: a.resume,
                shard,
            },
            |done, total| {
                // the first call comes once every check of the folder has
                // passed: a refusal is not preceded by the plan
                if !planned {
                    planned = true;
                    if done > 0 {
                        errln!("{plan}; {done} of the {total} done by an earlier run");
                    } else {
                        errln!("{plan}");
                    }
                    p.set_base(done as u64 * per_session);
                    p.set_total(total as u64 * per_session);
                }
                p.at_least(done as u64 * per_session);
                p.note(format!("{done}/{total} sessions"));
            },
        )
    })
    .map_err(sweep_error)?;
    tell_done(&report, start.elapsed().as_secs_f64());
    tell_written(&a, shard);
    Ok(())
}

/// The sweep of `a.file`, with the table cache, memo cap, outcome
/// strategy and notices the arguments ask for.
fn configured(a: &SweepArgs) -> Result<Sweep, CliError> {
    let mut sweep = Sweep::load(&a.file).map_err(sweep_error)?;
    if let Some(dir) = &a.table_cache {
        sweep = sweep.with_table_cache(dir);
    }
    sweep = sweep
        .with_memo_cap(a.memo.memo_cap)
        .with_strategy(a.memo.outcomes.0)
        .map_err(|e| CliError::input(format!("--outcomes: {e}")))?
        .with_notices(|line| errln!("outcomes: {line}"));
    Ok(sweep)
}

/// The line that tells the plan: cells, sessions, trials, episodes,
/// shard and threads.
fn plan_line(a: &SweepArgs, sweep: &Sweep, shard: Shard, threads: usize) -> String {
    let (total, spec) = (sweep.num_sessions(), &sweep.spec);
    let mut episodes = String::new();
    if spec.runs_episodes() {
        let s = plural(spec.commands);
        let closed = if spec.closed_loop {
            ", closed loop"
        } else {
            ""
        };
        episodes = format!(" (episodes of {} command{s}{closed})", spec.commands);
    }
    let mut part = String::new();
    if shard.n > 1 {
        part = format!(", shard {shard} ({} sessions)", shard.count(total));
    }
    let (file, cells, s) = (a.file.display(), sweep.cells().len(), plural(threads));
    let (sessions, trials) = (spec.sessions, spec.trials);
    format!("sweep {file}: {cells} cells x {sessions} sessions = {total} sessions of {trials} trials{episodes}{part}, {threads} thread{s}")
}

/// Tells how many sessions ran, how many an earlier run did, and how
/// fast.
fn tell_done(report: &DirReport, secs: f64) {
    let (all, resumed, ran) = (report.sessions, report.resumed, report.ran);
    let mut rate = String::new();
    if ran > 0 && secs > 0.0 {
        rate = format!(", {:.1} sessions/s", ran as f64 / secs);
    }
    errln!("done: {all} sessions ({resumed} from an earlier run, {ran} now) in {secs:.2} s{rate}");
}

/// Tells the files written: the results, and for a whole sweep the
/// summary.
fn tell_written(a: &SweepArgs, shard: Shard) {
    let mut wrote = a.out.join(sweep::RESULTS).display().to_string();
    if shard.n == 1 {
        wrote += &format!(" and {}", a.out.join(sweep::SUMMARY).display());
    }
    outln!("wrote {wrote}");
}

pub fn merge(a: MergeArgs) -> CliResult {
    // one command at a time writes into a folder, as `sweep` does
    super::output::lock_out(&a.out)?;
    let report = sweep::merge(&a.dirs, &a.out).map_err(sweep_error)?;
    let (results, summary) = (a.out.join(sweep::RESULTS), a.out.join(sweep::SUMMARY));
    let (results, summary) = (results.display(), summary.display());
    let (shards, sessions) = (a.dirs.len(), report.sessions);
    outln!("merged {shards} shards, {sessions} sessions: wrote {results} and {summary}");
    Ok(())
}
