//! The progress of a long computation on standard error: an estimate of
//! its time once a sample is measured, then a bar with ETA on a terminal,
//! or a line every few seconds otherwise (a batch log shows that work goes
//! on). A command that ends within the first seconds prints nothing.

use crate::cli::console::errln;
use crate::cli::locked;
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// How long the first sample runs before the estimate of the whole.
const SAMPLE: Duration = Duration::from_secs(1);

/// How often a line is printed when standard error is not a terminal.
pub const EVERY: Duration = Duration::from_secs(5);

/// Seconds from which a scene tool's estimated cost is said before it
/// starts (`scene check --samples`, `scene exec`, `scene render
/// --animate`); a shorter one stays quiet. The tools that simulate every
/// command (`scene table|stats|reward-cell`) always say it.
pub const LONG: f64 = 1.0;

/// The count of a tracked computation, moved on by the work from any
/// thread and read by the reporter.
#[derive(Default)]
pub struct Progress {
    /// Units done by this run.
    done: Arc<AtomicU64>,
    /// Units done before this run (a resumed sweep): shown in the position,
    /// left out of the rate.
    base: AtomicU64,
    /// A position known to be reached (sessions finished), whatever `done`
    /// says.
    floor: AtomicU64,
    /// The units in all; 0 while unknown (a stream of commands).
    total: AtomicU64,
    /// Shown after the count, for example `3/40 sessions`.
    note: Mutex<String>,
    /// Lines to print once, above the bar on a terminal ([`Progress::say`]).
    said: Mutex<Vec<String>>,
    /// A phase shown instead of the count while it runs.
    phase: Arc<Phase>,
}

/// A part of a tracked computation with a count of its own (a sweep's
/// outcome table, built before any trial runs), shown instead of the
/// computation's count while it runs: its own bar with ETA on a terminal,
/// its own lines otherwise (`sweep: table of arm7: 300/1094 commands
/// (27%), 5 s elapsed, about 13 s left`). Moved on from any thread.
#[derive(Default)]
pub struct Phase(Mutex<Option<Arc<Part>>>);

/// The label, unit and count of a [`Phase`] running.
type Part = (String, String, Progress);

impl Phase {
    /// Starts the phase `label` of `total` units unless it is the one
    /// running (one look, so that threads that all report a phase's first
    /// units start it once).
    pub fn enter(&self, label: &str, unit: &str, total: u64) {
        let mut current = locked(&self.0);
        if current.as_ref().is_none_or(|p| p.0 != label) {
            *current = Some(Arc::new((label.into(), unit.into(), Progress::new(total))));
        }
    }

    /// `k` more units of the phase done.
    pub fn add(&self, k: u64) {
        if let Some(p) = &*locked(&self.0) {
            p.2.add(k);
        }
    }

    /// Ends the phase running: the computation's count shows again.
    pub fn end(&self) {
        *locked(&self.0) = None;
    }

    fn current(&self) -> Option<Arc<Part>> {
        locked(&self.0).clone()
    }
}

impl Progress {
    fn new(total: u64) -> Progress {
        Progress {
            total: AtomicU64::new(total),
            ..Progress::default()
        }
    }

    /// The phase of this computation, to hand to code that reports a part
    /// of it on its own (`Sweep::with_table_progress`).
    pub fn phase(&self) -> Arc<Phase> {
        self.phase.clone()
    }

    /// Prints `line` on standard error at the reporter's next look (within
    /// 0.1 s, and at the end at the latest), above the bar on a terminal.
    pub fn say(&self, line: impl Into<String>) {
        locked(&self.said).push(line.into());
    }

    fn take_said(&self) -> Vec<String> {
        std::mem::take(&mut *locked(&self.said))
    }

    /// `k` more units done.
    pub fn add(&self, k: u64) {
        self.done.fetch_add(k, Ordering::Relaxed);
    }

    /// The counter of the units done by this run, to hand to code that
    /// counts on its own (`Sweep::with_trial_counter`).
    pub fn counter(&self) -> Arc<AtomicU64> {
        self.done.clone()
    }

    /// The units in all, once known.
    pub fn set_total(&self, total: u64) {
        self.total.store(total, Ordering::Relaxed);
    }

    /// The units done before this run started.
    pub fn set_base(&self, base: u64) {
        self.base.store(base, Ordering::Relaxed);
    }

    /// At least `pos` units are done (before and by this run).
    pub fn at_least(&self, pos: u64) {
        self.floor.fetch_max(pos, Ordering::Relaxed);
    }

    /// What to show after the count.
    pub fn note(&self, note: impl Into<String>) {
        *locked(&self.note) = note.into();
    }

    /// (position, units done by this run, total).
    fn read(&self) -> (u64, u64, u64) {
        let ran = self.done.load(Ordering::Relaxed);
        let base = self.base.load(Ordering::Relaxed);
        let total = self.total.load(Ordering::Relaxed);
        let mut pos = (base + ran).max(self.floor.load(Ordering::Relaxed));
        if total > 0 {
            pos = pos.min(total);
        }
        (pos, pos.saturating_sub(base), total)
    }
}

/// Runs `work`, which moves its [`Progress`] on (from any thread), while a
/// reporter thread shows it as `LABEL: ... UNIT ...` on standard error.
/// `total` may be 0 until [`Progress::set_total`] tells it (nothing is
/// shown meanwhile).
pub fn track<T>(label: &str, unit: &str, total: u64, work: impl FnOnce(&Progress) -> T) -> T {
    track_as(label, unit, total, true, false, work)
}

/// [`track`] for work that reports its units through an [`e3d::Control`].
pub fn track_control<T>(
    label: &str,
    unit: &str,
    total: u64,
    work: impl FnOnce(&e3d::Control<'_>) -> T,
) -> T {
    track(label, unit, total, |p| {
        let add = |k| p.add(k);
        work(&e3d::Control::default().with_progress(&add))
    })
}

/// [`track`] for a command that prints its results as they come (`scene
/// exec`): no total, and no spinner when standard output is the terminal
/// too (the rows show the progress there, and a spinner would cut into
/// them); off a terminal, the same lines.
pub fn track_stream<T>(label: &str, unit: &str, work: impl FnOnce(&Progress) -> T) -> T {
    track_as(label, unit, 0, !std::io::stdout().is_terminal(), true, work)
}

fn track_as<T>(
    label: &str,
    unit: &str,
    total: u64,
    bar: bool,
    stream: bool,
    work: impl FnOnce(&Progress) -> T,
) -> T {
    let progress = Progress::new(total);
    let finished = AtomicBool::new(false);
    let terminal = std::io::stderr().is_terminal();
    std::thread::scope(|s| {
        let reporter = s.spawn(|| {
            let mut r = Reporter::new(label, unit, terminal);
            r.bar_allowed = bar;
            r.stream = stream;
            // the phase being shown and its reporter
            let mut sub: Option<(Arc<Part>, Reporter)> = None;
            loop {
                std::thread::park_timeout(Duration::from_millis(100));
                let printer = sub.as_ref().map_or(&r, |(_, s)| s);
                for line in progress.take_said() {
                    printer.print(line);
                }
                if finished.load(Ordering::Acquire) {
                    break;
                }
                let now = Instant::now();
                match progress.phase.current() {
                    Some(phase) if r.bar_allowed || !terminal => {
                        if sub.as_ref().is_none_or(|(p, _)| !Arc::ptr_eq(p, &phase)) {
                            r.finish();
                            let mut s = Reporter::new(&phase.0, &phase.1, terminal);
                            // lines at the pace of the computation's
                            s.last_line = r.last_line;
                            sub = Some((phase, s));
                        }
                        if let Some((p, s)) = sub.as_mut() {
                            s.show(&p.2, now);
                            r.last_line = s.last_line;
                        }
                    }
                    _ => {
                        sub = None;
                        r.show(&progress, now);
                    }
                }
            }
            drop((sub, r));
            for line in progress.take_said() {
                errln!("{line}");
            }
        });
        // set even if `work` panics, or the scope would wait for the reporter
        let _stop = Stop {
            finished: &finished,
            reporter: reporter.thread().clone(),
        };
        work(&progress)
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

/// What the reporter thread keeps between two looks at the count.
struct Reporter {
    label: String,
    unit: String,
    terminal: bool,
    /// On a terminal: draw a bar (or a spinner), or nothing at all.
    bar_allowed: bool,
    /// No total ever (a spinner, and lines only when the count moves);
    /// otherwise nothing is shown until the total is known.
    stream: bool,
    bar: Option<indicatif::ProgressBar>,
    start: Instant,
    estimated: bool,
    last_line: Instant,
    /// The position the last line showed.
    last_pos: u64,
    /// The last look at which this run had counted nothing: the rate is
    /// measured from there.
    counting_since: Instant,
}

/// Units done in a time, from the first count.
#[derive(Debug, Clone, Copy)]
struct Rate {
    units: u64,
    time: Duration,
}

impl Rate {
    /// The seconds `left` units take at this rate (`None` before any).
    fn secs_for(&self, left: u64) -> Option<f64> {
        (self.units > 0).then(|| self.time.as_secs_f64() * left as f64 / self.units as f64)
    }
}

impl Reporter {
    fn new(label: &str, unit: &str, terminal: bool) -> Self {
        let start = Instant::now();
        Reporter {
            label: label.to_string(),
            unit: unit.to_string(),
            terminal,
            bar_allowed: true,
            stream: false,
            bar: None,
            start,
            estimated: false,
            last_line: start,
            last_pos: 0,
            counting_since: start,
        }
    }

    fn show(&mut self, p: &Progress, now: Instant) {
        self.show_counts(p.read(), &locked(&p.note).clone(), now);
    }

    fn show_counts(&mut self, (pos, ran, total): (u64, u64, u64), note: &str, now: Instant) {
        if total == 0 && !self.stream {
            return;
        }
        if self.terminal {
            if !self.bar_allowed {
                return;
            }
            self.draw_bar(pos, total, note);
        }
        // the rate is measured from the first count, not from the start:
        // building an outcome table first does not count as slow trials
        if ran == 0 {
            self.counting_since = now;
        }
        let rate = Rate {
            units: ran,
            time: now - self.counting_since,
        };
        if !self.estimated && total > 0 && rate.units > 0 && rate.time >= SAMPLE {
            self.estimated = true;
            let line = estimate_line(&self.label, &self.unit, pos, total, now - self.start, rate);
            self.print(line);
        }
        // without a total (a stream), a line only when the count moved:
        // waiting for input is not work going on
        let due = now - self.last_line >= EVERY;
        if !self.terminal && due && (total > 0 || pos != self.last_pos) {
            self.print(status_line(
                &self.label,
                &self.unit,
                (pos, total),
                note,
                now - self.start,
                rate,
            ));
            self.last_line = now;
            self.last_pos = pos;
        }
    }

    fn draw_bar(&mut self, pos: u64, total: u64, note: &str) {
        let unit = &self.unit;
        let bar = self.bar.get_or_insert_with(|| {
            let (bar, template) = if total > 0 {
                (
                    indicatif::ProgressBar::new(total),
                    format!("{{msg}} [{{bar:30}}] {{pos}}/{{len}} {unit}, {{eta}} left"),
                )
            } else {
                (
                    indicatif::ProgressBar::new_spinner(),
                    format!("{{msg}} {{spinner}} {{pos}} {unit}, {{elapsed}}"),
                )
            };
            bar.set_style(
                indicatif::ProgressStyle::with_template(&template)
                    .expect("valid template")
                    .progress_chars("=> "),
            );
            // what an earlier run did is not part of this run's rate
            bar.set_position(pos);
            bar.reset_eta();
            bar
        });
        if total > 0 && bar.length() != Some(total) {
            bar.set_length(total);
        }
        bar.set_message(if note.is_empty() {
            self.label.clone()
        } else {
            format!("{} ({note})", self.label)
        });
        bar.set_position(pos);
    }

    fn print(&self, line: String) {
        match &self.bar {
            Some(bar) => bar.println(line),
            None => errln!("{line}"),
        }
    }

    /// Removes the bar (also while a phase shows its own: it comes back,
    /// its ETA anew, at the next [`show`](Self::show)).
    fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Drop for Reporter {
    fn drop(&mut self) {
        self.finish();
    }
}

/// `LABEL: about 12 s in all (214 commands in 1.0 s)`: the time so far
/// and what is left at the measured rate.
fn estimate_line(
    label: &str,
    unit: &str,
    pos: u64,
    total: u64,
    elapsed: Duration,
    rate: Rate,
) -> String {
    let rest = rate.secs_for(total.saturating_sub(pos)).unwrap_or(0.0);
    format!(
        "{label}: about {:.0} s in all ({} {unit} in {:.1} s)",
        elapsed.as_secs_f64() + rest,
        rate.units,
        rate.time.as_secs_f64()
    )
}

/// The line printed every [`EVERY`] off a terminal:
/// `LABEL: 1200/5000 trials (24%), 3/10 sessions, 5 s elapsed, about 16 s left`
/// (without a total: `LABEL: 1200 commands, 5 s elapsed`).
fn status_line(
    label: &str,
    unit: &str,
    (pos, total): (u64, u64),
    note: &str,
    elapsed: Duration,
    rate: Rate,
) -> String {
    let secs = elapsed.as_secs_f64();
    let note = if note.is_empty() {
        String::new()
    } else {
        format!(", {note}")
    };
    if total == 0 {
        return format!("{label}: {pos} {unit}{note}, {secs:.0} s elapsed");
    }
    let left = match rate.secs_for(total.saturating_sub(pos)) {
        Some(l) => format!(", about {l:.0} s left"),
        None => String::new(),
    };
    format!(
        "{label}: {pos}/{total} {unit} ({:.0}%){note}, {secs:.0} s elapsed{left}",
        100.0 * pos as f64 / total as f64
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_off_a_terminal_say_count_share_time_and_what_is_left() {
        let t = Duration::from_secs(5);
        let rate = |units, secs| Rate {
            units,
            time: Duration::from_secs(secs),
        };
        assert_eq!(
            status_line("run arm7", "trials", (1000, 5000), "", t, rate(1000, 5)),
            "run arm7: 1000/5000 trials (20%), 5 s elapsed, about 20 s left"
        );
        // a resumed sweep, after its table: the rate is this run's, from
        // its first trials
        assert_eq!(
            status_line(
                "sweep",
                "trials",
                (3000, 5000),
                "3/5 sessions",
                t,
                rate(1000, 2)
            ),
            "sweep: 3000/5000 trials (60%), 3/5 sessions, 5 s elapsed, about 4 s left"
        );
        assert_eq!(
            status_line("run x", "trials", (0, 5000), "", t, rate(0, 0)),
            "run x: 0/5000 trials (0%), 5 s elapsed"
        );
        assert_eq!(
            status_line("scene exec arm7", "commands", (640, 0), "", t, rate(640, 5)),
            "scene exec arm7: 640 commands, 5 s elapsed"
        );
        assert_eq!(
            estimate_line(
                "scene arm7",
                "commands",
                214,
                1094,
                Duration::from_secs(1),
                rate(214, 1)
            ),
            "scene arm7: about 5 s in all (214 commands in 1.0 s)"
        );
        // 6 s of table first, then 100 trials a second
        assert_eq!(
            estimate_line(
                "sweep",
                "trials",
                100,
                1000,
                Duration::from_secs(7),
                rate(100, 1)
            ),
            "sweep: about 16 s in all (100 trials in 1.0 s)"
        );
    }

    #[test]
    fn a_phase_is_entered_once_counts_its_own_units_and_ends() {
        let p = Progress::new(100);
        let phase = p.phase();
        assert!(phase.current().is_none());
        phase.enter("sweep: table of arm7", "commands", 1094);
        phase.add(24);
        // a second thread's first units do not start it again
        phase.enter("sweep: table of arm7", "commands", 1094);
        phase.add(24);
        let first = phase.current().unwrap();
        assert_eq!(
            (first.0.as_str(), first.1.as_str(), first.2.read()),
            ("sweep: table of arm7", "commands", (48, 48, 1094))
        );
        // the next scene's table: a new phase, counted from 0
        phase.enter("sweep: table of maze3", "commands", 10);
        phase.add(50);
        let next = phase.current().unwrap();
        assert!(!Arc::ptr_eq(&first, &next));
        assert_eq!(next.2.read(), (10, 10, 10));
        phase.end();
        assert!(phase.current().is_none());
        // the computation's own count is untouched
        assert_eq!(p.read(), (0, 0, 100));
    }

    #[test]
    fn the_position_counts_the_earlier_run_and_the_floor() {
        let p = Progress::new(0);
        p.set_total(100);
        p.set_base(40);
        p.add(5);
        assert_eq!(p.read(), (45, 5, 100));
        p.at_least(60);
        assert_eq!(p.read(), (60, 20, 100));
        p.add(500);
        assert_eq!(p.read(), (100, 60, 100));
    }

    #[test]
    fn a_reporter_off_a_terminal_prints_nothing_in_the_first_seconds() {
        // no line before EVERY (a short command leaves stderr empty)
        let p = Progress::new(10);
        let mut r = Reporter::new("x", "commands", false);
        p.add(3);
        let t0 = r.start;
        r.show(&p, t0 + Duration::from_millis(500));
        assert!(!r.estimated);
        assert_eq!(r.last_line, t0);
        r.show(&p, t0 + EVERY);
        assert!(r.estimated);
        assert_eq!(r.last_line, t0 + EVERY);
        // a stream whose count does not move (waiting for input): no line
        let p = Progress::new(0);
        let mut r = Reporter::new("x", "commands", false);
        r.stream = true;
        let t0 = r.start;
        r.show(&p, t0 + EVERY);
        assert_eq!(r.last_line, t0);
        p.add(1);
        r.show(&p, t0 + 2 * EVERY);
        assert_eq!(r.last_line, t0 + 2 * EVERY);
    }
}
