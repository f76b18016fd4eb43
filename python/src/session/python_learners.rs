//! Sessions of symbols run on this thread, with the GIL: Python learners
//! (one, or several in lockstep), and built-in learners whose trials go to
//! `on_trials`.

use super::{execution_text, executor, first_failure, new_records, symbol_metrics, Run};
use crate::learner::{python_learner_name, PyLearner};
use crate::progress::Ticks;
use crate::record::Rows;
use e3d::world::Executor;
use e3d::{Learner, SessionRecord};
use pyo3::prelude::*;
use std::cell::RefCell;

/// Runs sessions of Python learners, one per configuration, in one
/// lockstep group on this thread, with the GIL. Returns the learners'
/// name (their names joined by commas when they differ), their rows and
/// the execution text.
pub(super) fn run_python(
    py: Python<'_>,
    run: &Run<'_, '_>,
    objs: Vec<Bound<'_, PyAny>>,
) -> PyResult<(String, Vec<Rows>, String)> {
    let names: Vec<String> = objs
        .iter()
        .map(python_learner_name)
        .collect::<PyResult<_>>()?;
    let error = RefCell::new(None);
    let space = &run.scene.space;
    let mut learners: Vec<PyLearner<'_, '_>> = objs
        .into_iter()
        .map(|o| PyLearner::new(py, o, space, &error))
        .collect::<PyResult<_>>()?;
    let exec = executor(py, &run.scene.inner, run)?;
    let records = run_here(py, &exec, run, &mut learners, &error)?;
    let rows = records
        .into_iter()
        .map(|r| {
            let m = symbol_metrics(&exec, &run.scene.inner, &r, &run.a.target);
            Rows::of_symbols(py, r, m, None, None)
        })
        .collect::<PyResult<_>>()?;
    let name = if names.iter().all(|m| *m == names[0]) {
        names[0].clone()
    } else {
        names.join(",")
    };
    Ok((name, rows, execution_text(exec)))
}

/// Runs sessions in one lockstep group on this thread, with the GIL (Python
/// learners, or a learner whose trials go to `on_trials`), on the world
/// `exec` makes; stopped at the first error put in `error` (by a learner,
/// `progress` or `on_trials`), which is then raised, else by the first
/// failing session.
pub(super) fn run_here<L: Learner>(
    py: Python<'_>,
    exec: &Executor<'_>,
    run: &Run<'_, '_>,
    learners: &mut [L],
    error: &RefCell<Option<PyErr>>,
) -> PyResult<Vec<SessionRecord>> {
    let mut world = exec.world(run.configs.len());
    let mut records = new_records(exec, run.configs);
    let ticks = Ticks::new(py, run.progress, run.work.trials, error)?;
    let status = e3d::session::run_group(&mut *world, learners, run.configs, &mut records, &ticks);
    drop(world);
    if let Some(e) = error.take() {
        return Err(e);
    }
    first_failure(status)?;
    Ok(records)
}
