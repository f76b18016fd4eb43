//! Sub-commands of the `e3d` binary.

pub mod bench;
pub mod closed_loop;
pub mod compare;
pub mod console;
pub mod episodes;
pub mod output;
pub mod plot;
pub mod progress;
pub mod report;
pub mod reproduce;
pub mod run;
pub mod scene;
pub mod session;
pub mod sweep;

use std::process::ExitCode;

/// Exit codes, stable and documented in `docs/robustness.md`.
pub mod exit {
    /// Bad input: a scene, a sweep file, a parameter, a command.
    pub const BAD_INPUT: u8 = 2;
    /// An output could not be written (or would overwrite without leave).
    pub const OUTPUT: u8 = 3;
    /// A simulation failed (for example it blew up).
    pub const SIMULATION: u8 = 4;
}

/// An error of the command line, with its exit code.
#[derive(Debug, thiserror::Error)]
#[error("{message}")]
pub struct CliError {
    pub code: u8,
    pub message: String,
}

impl CliError {
    fn new(code: u8, m: impl std::fmt::Display) -> Self {
        let message = m.to_string();
        CliError { code, message }
    }
    pub fn input(m: impl std::fmt::Display) -> Self {
        Self::new(exit::BAD_INPUT, m)
    }
    pub fn output(m: impl std::fmt::Display) -> Self {
        Self::new(exit::OUTPUT, m)
    }
    pub fn simulation(m: impl std::fmt::Display) -> Self {
        Self::new(exit::SIMULATION, m)
    }
}

/// A world's failure is a failed simulation.
impl From<e3d::WorldError> for CliError {
    fn from(e: e3d::WorldError) -> Self {
        CliError::simulation(e)
    }
}

pub type CliResult = Result<(), CliError>;

/// `PATH: cannot write: E`, an output error.
pub fn cannot_write(path: &std::path::Path, e: impl std::fmt::Display) -> CliError {
    CliError::output(format!("{}: cannot write: {e}", path.display()))
}

/// `m` locked, even if a thread panicked holding it (what it guards stays usable).
pub fn locked<T>(m: &std::sync::Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// `"s"` after a count other than one.
pub fn plural(n: usize) -> &'static str {
    &"s"[usize::from(n == 1)..]
}

/// Loads a scene by path or built-in name, as a CLI error.
pub fn load_scene(name: &str) -> Result<e3d::Scene, CliError> {
    e3d::Scene::resolve(name).map_err(CliError::input)
}

/// The most characters of an error message printed; the rest is cut,
/// with its length said (a message echoing a huge input stays readable).
const MAX_MESSAGE_CHARS: usize = 4096;

/// Prints `e` to standard error and gives its exit code.
pub fn report_error(e: &CliError) -> ExitCode {
    use std::io::Write;
    // a standard error that cannot be written does not change the code
    // a name or a command with ESC or BEL in it must not drive the terminal
    let _ = writeln!(
        std::io::stderr(),
        "error: {}",
        e3d::text::escape_controls(&e3d::text::cut(&e.message, MAX_MESSAGE_CHARS))
    );
    ExitCode::from(e.code)
}
