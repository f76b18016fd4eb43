//! The `e3d._e3d` extension module: Python bindings of the e3d library,
//! which does all the work (scenes, worlds through an [`e3d::world::OutcomeMemo`],
//! sessions on the world an [`e3d::Executor`] chooses, sweeps). These modules
//! only convert: numpy arrays in and out, errors into Python exceptions with
//! the CLI's text.

mod commands;
mod contextual;
mod episode;
mod episode_world;
mod errors;
mod held;
mod learn_args;
mod learner;
mod motion;
mod outcome;
mod picture;
mod progress;
mod record;
mod rng;
mod saved;
mod scene;
mod scene_dict;
mod session;
mod state;
mod sweep;
mod world;

use pyo3::prelude::*;

/// e3d's native module (import `e3d`, which re-exports it).
#[pymodule]
fn _e3d(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // numpy's C API is imported on first use: once a Ctrl-C is pending,
    // that import raises KeyboardInterrupt and rust-numpy panics, so it is
    // imported here, before any long call
    numpy::PyArray1::<f64>::zeros(m.py(), 0, false);
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("E3D_VERSION", e3d::sweep::VERSION)?;
    m.add_class::<scene::PyScene>()?;
    m.add_class::<world::PyWorld>()?;
    m.add_class::<rng::PyRng>()?;
    m.add_class::<state::PyE3dLearner>()?;
    m.add_class::<saved::PyLearnerState>()?;
    m.add_class::<episode_world::PyEpisodeWorld>()?;
    errors::scene_error_defaults(m.py())?;
    m.add("SceneError", m.py().get_type::<errors::SceneError>())?;
    m.add(
        "SimulationError",
        m.py().get_type::<errors::SimulationError>(),
    )?;
    m.add_function(wrap_pyfunction!(session::_run_sessions, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::run_sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::merge_sweeps, m)?)?;
    m.add_function(wrap_pyfunction!(episode::_run_episodes, m)?)?;
    Ok(())
}
