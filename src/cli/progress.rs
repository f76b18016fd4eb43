//! The progress of a long computation, on standard error: an estimate of
//! its time once a sample has been measured, then a bar with ETA on a
//! terminal, or a line every few seconds otherwise (batch logs show that
//! work goes on). Nothing goes to standard output.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// How long the first sample runs before the estimate of the whole.
const SAMPLE: Duration = Duration::from_secs(1);

/// How often a line is printed when standard error is not a terminal.
const EVERY: Duration = Duration::from_secs(5);

/// Runs `work`, which calls its argument (from any thread) with the number
/// of commands it has just finished, out of `total`, while a reporter
/// thread shows the progress as `LABEL: ...` on standard error.
pub fn track<T>(label: &str, total: u64, work: impl FnOnce(&(dyn Fn(u64) + Sync)) -> T) -> T {
    let done = AtomicU64::new(0);
    let finished = AtomicBool::new(false);
    let count = |k: u64| {
        done.fetch_add(k, Ordering::Relaxed);
    };
    std::thread::scope(|s| {
        let reporter = s.spawn(|| report(label, total, &done, &finished));
        // set even if `work` panics, or the scope would wait for the reporter
        let _stop = Stop {
            finished: &finished,
            reporter: reporter.thread().clone(),
        };
        work(&count)
    })
}

/// Tells the reporter thread to finish, when dropped.
struct Stop<'a> {
    finished: &'a AtomicBool,
    reporter: std::thread::Thread,
}

impl Drop for Stop<'_> {
    fn drop(&mut self) {
        self.finished.store(true, Ordering::Release);
        self.reporter.unpark();
    }
}

fn report(label: &str, total: u64, done: &AtomicU64, finished: &AtomicBool) {
    let start = Instant::now();
    let bar = std::io::stderr().is_terminal().then(|| {
        let bar = indicatif::ProgressBar::new(total);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg} [{bar:30}] {pos}/{len} commands, {eta} left",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_message(label.to_string());
        bar
    });
    let mut estimated = false;
    let mut last_line = start;
    loop {
        std::thread::park_timeout(Duration::from_millis(100));
        if finished.load(Ordering::Acquire) {
            break;
        }
        let d = done.load(Ordering::Relaxed).min(total);
        let secs = start.elapsed().as_secs_f64();
        if let Some(bar) = &bar {
            bar.set_position(d);
        }
        if !estimated && d > 0 && start.elapsed() >= SAMPLE {
            estimated = true;
            let line = format!(
                "{label}: about {:.0} s in all ({d} commands in the first {secs:.1} s)",
                secs * total as f64 / d as f64
            );
            match &bar {
                Some(bar) => bar.println(line),
                None => eprintln!("{line}"),
            }
        }
        if bar.is_none() && last_line.elapsed() >= EVERY {
            let left = if d > 0 {
                format!(", about {:.0} s left", secs * (total - d) as f64 / d as f64)
            } else {
                String::new()
            };
            eprintln!(
                "{label}: {d}/{total} commands ({:.0}%), {secs:.0} s elapsed{left}",
                100.0 * d as f64 / total.max(1) as f64
            );
            last_line = Instant::now();
        }
    }
    if let Some(bar) = bar {
        bar.finish_and_clear();
    }
}
