//! Errors: the package's exceptions, and the library's errors made Python
//! exceptions with the CLI's text.

use e3d::{SweepError, WorldError};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    e3d,
    SceneError,
    PyValueError,
    "A scene or sweep file (or text) that cannot be used; the message names the file, line and column, as the CLI does."
);
create_exception!(
    e3d,
    SimulationError,
    PyRuntimeError,
    "A command whose simulation failed (for example a physics blow-up); the message names the scene and the command."
);

/// A failure inside code that runs without the GIL, made a Python
/// exception once the GIL is back.
pub(crate) enum Fail {
    Value(String),
    Scene(String),
    Simulation(String),
    Runtime(String),
    Os(String),
}

impl From<Fail> for PyErr {
    fn from(f: Fail) -> PyErr {
        match f {
            Fail::Value(m) => PyValueError::new_err(m),
            Fail::Scene(m) => SceneError::new_err(m),
            Fail::Simulation(m) => SimulationError::new_err(m),
            Fail::Runtime(m) => PyRuntimeError::new_err(m),
            Fail::Os(m) => pyo3::exceptions::PyOSError::new_err(m),
        }
    }
}

impl From<WorldError> for Fail {
    fn from(e: WorldError) -> Fail {
        match e {
            WorldError::BadCommand { .. } => Fail::Value(e.to_string()),
            _ => Fail::Simulation(e.to_string()),
        }
    }
}

impl From<SweepError> for Fail {
    fn from(e: SweepError) -> Fail {
        match e {
            SweepError::Input(_) => Fail::Scene(e.to_string()),
            SweepError::World(w) => w.into(),
            SweepError::Io { .. } | SweepError::Output(_) => Fail::Os(e.to_string()),
            _ => Fail::Runtime(e.to_string()),
        }
    }
}

pub(crate) fn scene_err(e: e3d::SceneError) -> PyErr {
    SceneError::new_err(e.to_string())
}

/// The error text of work stopped on request (Ctrl-C, a failed callback).
pub(crate) const STOPPED: &str = "stopped";
