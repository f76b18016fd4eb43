//! [`Control`]: what a long run (sessions, a table's building, a sample
//! of commands) reports to and obeys: progress, its size, a stop.

use super::WorldError;

/// What a long run reports and obeys: `total(n)` is told the size of the
/// work once it is known (the commands a table simulates), `progress(k)`
/// of `k` more units done (trials summed over the sessions, or commands
/// of a table, from the worker threads), and once `stop()` returns `true`
/// (asked before every execution) the work still running ends with
/// [`WorldError::Stopped`]. A Ctrl-C, a cancelled call, a progress bar.
///
/// ```
/// use e3d::Control;
/// let quiet = Control::default();
/// assert!(quiet.check().is_ok());
/// let stop = || true;
/// assert!(Control { stop: &stop, ..Control::default() }.check().is_err());
/// ```
#[derive(Clone, Copy)]
pub struct Control<'a> {
    /// Told of the units done since its last call.
    pub progress: &'a (dyn Fn(u64) + Sync),
    /// Told the size of the work, in the units of `progress`, once known.
    pub total: &'a (dyn Fn(u64) + Sync),
    /// Asked before every execution: `true` stops the sessions.
    pub stop: &'a (dyn Fn() -> bool + Sync),
}

impl Default for Control<'_> {
    /// No progress, no stop.
    fn default() -> Self {
        Control {
            progress: &|_| {},
            total: &|_| {},
            stop: &|| false,
        }
    }
}

impl std::fmt::Debug for Control<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Control").finish_non_exhaustive()
    }
}

impl<'a> Control<'a> {
    /// The same control, reporting progress to `progress`.
    pub fn with_progress(self, progress: &'a (dyn Fn(u64) + Sync)) -> Self {
        Control { progress, ..self }
    }

    /// `Err(`[`WorldError::Stopped`]`)` once the run is to stop.
    pub fn check(&self) -> Result<(), WorldError> {
        if (self.stop)() {
            Err(WorldError::Stopped)
        } else {
            Ok(())
        }
    }
}

/// What the engine reports to and obeys while sessions run: [`Control`]
/// for closures shared by worker threads; implement it for state of your
/// own on one thread (a `RefCell`, a throttled callback).
pub trait Observer {
    /// Told of `trials` more trials done, summed over the sessions.
    fn progress(&self, trials: u64);
    /// Asked before every execution: `true` stops the sessions still
    /// running, with [`WorldError::Stopped`].
    fn stopped(&self) -> bool;
}

impl Observer for Control<'_> {
    fn progress(&self, trials: u64) {
        (self.progress)(trials)
    }
    fn stopped(&self) -> bool {
        (self.stop)()
    }
}
