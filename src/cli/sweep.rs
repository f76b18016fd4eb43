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
    #[command(flatten)]
    pub memo: super::run::MemoArgs,
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
    sweep = sweep
        .with_memo_cap(a.memo.memo_cap)
        .with_strategy(a.memo.outcomes.0)
        .with_notices(|line| eprintln!("outcomes: {line}"));
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
    let counter = std::sync::Arc::new(std::sync::atomic::AtomicU64::new(0));
    let sweep = sweep.with_trial_counter(counter.clone());
    let trials = sweep.spec.trials as u64;
    let reporter = std::sync::Mutex::new(Reporter::new(trials));
    let finished = std::sync::atomic::AtomicBool::new(false);
    let report = std::thread::scope(|scope| {
        // between sessions, the trials of sessions in lockstep move it on
        scope.spawn(|| {
            while !finished.load(std::sync::atomic::Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(200));
                let t = counter.load(std::sync::atomic::Ordering::Relaxed);
                reporter.lock().unwrap_or_else(|e| e.into_inner()).trials(t);
            }
        });
        let r = sweep.run_to_dir(
            &a.out,
            &DirOptions {
                threads,
                resume: a.resume,
                shard,
            },
            |done, total| {
                reporter
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .update(done, total)
            },
        );
        finished.store(true, std::sync::atomic::Ordering::Relaxed);
        r
    })
    .map_err(sweep_error);
    reporter
        .into_inner()
        .unwrap_or_else(|e| e.into_inner())
        .finish();
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
/// otherwise (logs, Slurm). It counts trials, so that sessions in lockstep,
/// which all end together, still show progress.
struct Reporter {
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    last_line: Option<Instant>,
    /// Trials per session.
    per_session: u64,
    /// Sessions of the shard, and those done before this run.
    total: usize,
    resumed: Option<usize>,
    done: usize,
    /// Trials run by this run so far.
    ran: u64,
}

impl Reporter {
    fn new(per_session: u64) -> Reporter {
        Reporter {
            bar: None,
            start: Instant::now(),
            last_line: None,
            per_session,
            total: 0,
            resumed: None,
            done: 0,
            ran: 0,
        }
    }

    /// Sessions done (called after each session).
    fn update(&mut self, done: usize, total: usize) {
        self.resumed.get_or_insert(done);
        self.done = done;
        self.total = total;
        self.show(done == total);
    }

    /// Trials run by this run so far (called from a ticker).
    fn trials(&mut self, ran: u64) {
        if ran != self.ran {
            self.ran = ran;
            self.show(false);
        }
    }

    fn show(&mut self, last: bool) {
        let Some(resumed) = self.resumed else { return };
        let total = self.total as u64 * self.per_session;
        let before = resumed as u64 * self.per_session;
        let done = (before + self.ran)
            .max(self.done as u64 * self.per_session)
            .min(total);
        let sessions = format!("{}/{} sessions", self.done, self.total);
        if std::io::stderr().is_terminal() {
            let bar = self.bar.get_or_insert_with(|| {
                let b = indicatif::ProgressBar::new(total);
                b.set_style(
                    indicatif::ProgressStyle::with_template(
                        "{bar:40.cyan/blue} {percent}% of the trials, {msg}  {elapsed_precise} elapsed, ETA {eta_precise}",
                    )
                    .expect("a valid template"),
                );
                b.set_position(done);
                b.reset_eta();
                b
            });
            bar.set_message(sessions);
            bar.set_position(done);
            return;
        }
        let due = self
            .last_line
            .is_none_or(|t| t.elapsed() >= Duration::from_secs(5));
        if due || last {
            let secs = self.start.elapsed().as_secs_f64();
            let ran = done - before;
            let eta = if ran > 0 && done < total {
                format!(", ETA {:.0} s", secs / ran as f64 * (total - done) as f64)
            } else {
                String::new()
            };
            eprintln!(
                "sweep: {sessions} ({:.0}% of the trials), {secs:.1} s elapsed{eta}",
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
