//! Progress callbacks and Ctrl-C for the long calls.
//!
//! A long call (`run_session`, `run_sessions`, `run_sweep`, a large
//! `execute_batch`) runs its work on a thread of its own, without the GIL,
//! while the calling thread waits on it and wakes every [`TICK`]: it takes
//! the GIL back only then, to check for signals (`py.check_signals()`:
//! Ctrl-C raises `KeyboardInterrupt`) and, at most every [`INTERVAL`], to
//! call the user's `progress(done, total)`. An exception from either asks
//! the work to stop ([`Watch::cancelled`]) and is raised once it has.
//!
//! A Python learner runs on the calling thread with the GIL (it is called
//! every trial): there, [`Ticks`] does the same from the session's own
//! progress callback.

use pyo3::prelude::*;
use std::cell::{Cell, RefCell};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// How often the waiting thread wakes to check for signals.
pub const TICK: Duration = Duration::from_millis(50);
/// The shortest time between two calls of a progress callback (the last
/// call, when the work is done, is always made).
pub const INTERVAL: Duration = Duration::from_millis(100);

/// What the work and the waiting thread share: how much is done, and
/// whether to stop.
#[derive(Default)]
pub struct Watch {
    /// Units done (trials, or commands), added by the work as it goes.
    pub done: Arc<AtomicU64>,
    /// Units done before the work started (a resumed sweep's sessions).
    pub base: AtomicU64,
    cancel: AtomicBool,
}

impl Watch {
    /// Adds `n` units done.
    pub fn add(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
    }

    fn total_done(&self) -> u64 {
        self.base.load(Ordering::Relaxed) + self.done.load(Ordering::Relaxed)
    }

    /// Runs `work` under the library's [`e3d::Control`] of this watch: its
    /// progress adds to the units done, its stop is [`cancelled`](Self::cancelled).
    pub fn control<R>(&self, work: impl FnOnce(&e3d::Control<'_>) -> R) -> R {
        let (add, stop) = (|n| self.add(n), || self.cancelled());
        work(&e3d::Control {
            progress: &add,
            stop: &stop,
            ..e3d::Control::default()
        })
    }

    /// Whether the caller asked the work to stop (Ctrl-C, or an exception
    /// from the progress callback).
    pub fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// Refuses a `progress` that cannot be called, before any work.
pub(crate) fn check_callable(progress: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
    match progress {
        Some(p) if !p.is_callable() => Err(pyo3::exceptions::PyTypeError::new_err(format!(
            "progress: expected a callable, progress(done, total), found {}",
            p.get_type().name()?
        ))),
        _ => Ok(()),
    }
}

/// Runs `work` on a thread of its own, the GIL released, waking every
/// [`TICK`] to check for signals and call `progress(done, total)` (see the
/// module). Returns `work`'s result, or the first exception raised by a
/// signal handler or by `progress` (after the work has stopped).
pub fn watched<R, F>(
    py: Python<'_>,
    progress: Option<&Bound<'_, PyAny>>,
    total: u64,
    watch: &Watch,
    work: F,
) -> PyResult<R>
where
    R: Send,
    F: FnOnce(&Watch) -> R + Send,
{
    check_callable(progress)?;
    let callback: Option<Py<PyAny>> = progress.map(|p| p.clone().unbind());
    let (result, error) = py.detach(|| {
        std::thread::scope(|scope| {
            let (tx, rx) = std::sync::mpsc::channel::<()>();
            let handle = scope.spawn(move || {
                let r = work(watch);
                let _ = tx.send(());
                r
            });
            let mut error: Option<PyErr> = None;
            let mut pace = Pace::default();
            loop {
                let finished = !matches!(
                    rx.recv_timeout(TICK),
                    Err(std::sync::mpsc::RecvTimeoutError::Timeout)
                );
                if error.is_none() {
                    let done = watch.total_done();
                    let call = pace.due(done, finished);
                    let r = Python::attach(|py| -> PyResult<()> {
                        py.check_signals()?;
                        if let (Some(cb), true) = (&callback, call) {
                            cb.call1(py, (done, total))?;
                        }
                        Ok(())
                    });
                    if let Err(e) = r {
                        watch.cancel();
                        error = Some(e);
                    }
                }
                if finished {
                    break;
                }
            }
            let result = match handle.join() {
                Ok(r) => r,
                Err(panic) => std::panic::resume_unwind(panic),
            };
            (result, error)
        })
    });
    // the callback object is dropped with the GIL held
    drop(callback);
    match error {
        Some(e) => Err(e),
        None => Ok(result),
    }
}

/// When a progress callback is due: at most every [`INTERVAL`], always
/// at the end, never twice for the same count.
#[derive(Default)]
struct Pace {
    last_call: Option<Instant>,
    reported: Option<u64>,
}

impl Pace {
    /// Whether to call now, `done` units done (`last`: the work is over);
    /// a call due counts as made.
    fn due(&mut self, done: u64, last: bool) -> bool {
        let due = (last || self.last_call.is_none_or(|t| t.elapsed() >= INTERVAL))
            && self.reported != Some(done);
        if due {
            self.last_call = Some(Instant::now());
            self.reported = Some(done);
        }
        due
    }
}

/// The progress and stop of sessions run on the calling thread with the
/// GIL (Python learners): signals checked every [`TICK`],
/// `progress(done, total)` paced as [`watched`] paces it, and a stop once
/// either raised (the error goes to `error`).
pub(crate) struct Ticks<'a, 'py> {
    py: Python<'py>,
    callback: Option<Bound<'py, PyAny>>,
    total: u64,
    done: Cell<u64>,
    last_check: Cell<Instant>,
    pace: RefCell<Pace>,
    error: &'a RefCell<Option<PyErr>>,
}

impl<'a, 'py> Ticks<'a, 'py> {
    pub(crate) fn new(
        py: Python<'py>,
        callback: Option<&Bound<'py, PyAny>>,
        total: u64,
        error: &'a RefCell<Option<PyErr>>,
    ) -> PyResult<Self> {
        check_callable(callback)?;
        Ok(Ticks {
            py,
            callback: callback.cloned(),
            total,
            done: Cell::new(0),
            last_check: Cell::new(Instant::now()),
            pace: RefCell::default(),
            error,
        })
    }

    fn tick(&self, done: u64) -> PyResult<()> {
        let last = done == self.total;
        if !last && self.last_check.get().elapsed() < TICK {
            return Ok(());
        }
        self.last_check.set(Instant::now());
        self.py.check_signals()?;
        match &self.callback {
            Some(cb) if self.pace.borrow_mut().due(done, last) => {
                cb.call1((done, self.total)).map(drop)
            }
            _ => Ok(()),
        }
    }
}

impl e3d::session::Observer for Ticks<'_, '_> {
    fn progress(&self, trials: u64) {
        let done = self.done.get() + trials;
        self.done.set(done);
        if self.error.borrow().is_none() {
            if let Err(e) = self.tick(done) {
                *self.error.borrow_mut() = Some(e);
            }
        }
    }
    fn stopped(&self) -> bool {
        self.error.borrow().is_some()
    }
}
