//! `e3d sweep` and `e3d merge`: grids of sessions, resumable, in shards.

use super::{CliError, CliResult};
use clap::Args;
use e3d::sweep::{self, DirOptions, Shard, Sweep, SweepError};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Arguments of `e3d sweep`.
#[derive(Args, Debug)]
pub struct SweepArgs {
    /// The sweep file (RON, see docs/sweeps.md).
    pub file: PathBuf,
    /// The output folder: results.csv, summary.csv, sweep.ron, version.txt,
    /// journal.txt.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Threads (default: every core).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u16).range(1..=4096))]
    pub threads: Option<u16>,
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
        SweepError::World(_) => CliError::simulation(e),
        SweepError::Io { .. } | SweepError::Output(_) => CliError::output(e),
        SweepError::Other(_) => CliError::simulation(e),
    }
}

pub fn run(a: SweepArgs) -> CliResult {
    let mut sweep = Sweep::load(&a.file).map_err(sweep_error)?;
    if let Some(dir) = &a.table_cache {
        sweep = sweep.with_table_cache(dir);
    }
    let threads = a.threads.map(usize::from).unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let shard = a.shard.unwrap_or(Shard::ALL);
    let total = sweep.num_sessions();
    eprintln!(
        "sweep {}: {} cells x {} sessions = {} sessions of {} trials{}, {} thread{}",
        a.file.display(),
        sweep.cells().len(),
        sweep.spec.sessions,
        total,
        sweep.spec.trials,
        if shard.n > 1 {
            format!(", shard {shard} ({} sessions)", shard.count(total))
        } else {
            String::new()
        },
        threads,
        if threads == 1 { "" } else { "s" }
    );
    // one run at a time in a folder: two would both do all the work
    let _lock = lock_out(&a.out)?;
    let start = Instant::now();
    let mut reporter = Reporter::new();
    let report = sweep
        .run_to_dir(
            &a.out,
            &DirOptions {
                threads,
                resume: a.resume,
                shard,
            },
            |done, total| reporter.update(done, total),
        )
        .map_err(sweep_error);
    reporter.finish();
    let report = report?;
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "done: {} sessions ({} from an earlier run, {} now) in {:.2} s{}",
        report.sessions,
        report.resumed,
        report.ran,
        secs,
        if report.ran > 0 && secs > 0.0 {
            format!(", {:.1} sessions/s", report.ran as f64 / secs)
        } else {
            String::new()
        }
    );
    let mut wrote = vec![a.out.join(sweep::RESULTS)];
    if shard.n == 1 {
        wrote.push(a.out.join(sweep::SUMMARY));
    }
    println!(
        "wrote {}",
        wrote
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(" and ")
    );
    Ok(())
}

/// Takes the lock of the output folder (creating it), or refuses with who
/// holds it. A lock file left by a killed run is taken over, with a
/// warning. A folder that cannot be created is left to the sweep's own
/// checks and messages.
fn lock_out(dir: &std::path::Path) -> Result<Option<e3d::io::DirLock>, CliError> {
    if dir.exists() && !dir.is_dir() {
        return Ok(None);
    }
    if std::fs::create_dir_all(dir).is_err() {
        return Ok(None);
    }
    match e3d::io::DirLock::acquire(dir) {
        Ok(lock) => {
            if let Some(old) = &lock.previous {
                eprintln!(
                    "warning: {}: took over the lock of a run that ended without releasing it ({old})",
                    dir.display()
                );
            }
            Ok(Some(lock))
        }
        Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => Err(CliError::output(format!(
            "{}: in use by {e}, which is running a sweep into it; wait for it to end or choose another --out",
            dir.display()
        ))),
        Err(e) => Err(CliError::output(format!(
            "{}: cannot take the lock {}: {e}",
            dir.display(),
            dir.join(e3d::io::LOCK_FILE).display()
        ))),
    }
}

pub fn merge(a: MergeArgs) -> CliResult {
    let report = sweep::merge(&a.dirs, &a.out).map_err(sweep_error)?;
    println!(
        "merged {} shards, {} sessions: wrote {} and {}",
        a.dirs.len(),
        report.sessions,
        a.out.join(sweep::RESULTS).display(),
        a.out.join(sweep::SUMMARY).display()
    );
    Ok(())
}

/// Progress: a bar with ETA on a terminal, plain lines every few seconds
/// otherwise (logs, Slurm).
struct Reporter {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    last_line: Option<Instant>,
    first_done: Option<usize>,
}

impl Reporter {
    fn new() -> Reporter {
        Reporter {
            bar: None,
            start: Instant::now(),
            last_line: None,
            first_done: None,
        }
    }

    fn update(&mut self, done: usize, total: usize) {
        let first = *self.first_done.get_or_insert(done);
        if std::io::stderr().is_terminal() {
            let bar = self.bar.get_or_insert_with(|| {
                let b = indicatif::ProgressBar::new(total as u64);
                b.set_style(
                    indicatif::ProgressStyle::with_template(
                        "{bar:40.cyan/blue} {pos}/{len} sessions  {elapsed_precise} elapsed, ETA {eta_precise}",
                    )
                    .expect("a valid template"),
                );
                b.set_position(done as u64);
                b.reset_eta();
                b
            });
            bar.set_position(done as u64);
            return;
        }
        let due = self
            .last_line
            .is_none_or(|t| t.elapsed() >= Duration::from_secs(5));
        if due || done == total {
            let secs = self.start.elapsed().as_secs_f64();
            let ran = done - first;
            let eta = if ran > 0 && done < total {
                format!(", ETA {:.0} s", secs / ran as f64 * (total - done) as f64)
            } else {
                String::new()
            };
            eprintln!(
                "sweep: {done}/{total} sessions ({:.0}%), {secs:.1} s elapsed{eta}",
                100.0 * done as f64 / total.max(1) as f64
            );
            self.last_line = Some(Instant::now());
        }
    }

    fn finish(&mut self) {
        if let Some(b) = self.bar.take() {
            b.finish_and_clear();
        }
    }
}
