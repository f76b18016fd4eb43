//! Sessions of symbols run on this thread, with the GIL: Python learners
//! (one, or several in lockstep), and built-in learners whose trials go to
//! `on_trials`.

use super::{execution_text, first_failure, symbol_metrics, OneSession, SessionArgs};
use crate::errors::Fail;
use crate::learner::{python_learner_name, PyLearner};
use crate::progress::{watched, Ticks, Watch};
use crate::record::{record_to_py, Rows};
use crate::scene::PyScene;
use e3d::world::{ExecOptions, Executor, Workload};
use e3d::{Learner, SessionConfig, SessionRecord};
use pyo3::prelude::*;
use std::cell::RefCell;

/// The executor of `scene` for work that then runs with the GIL (a Python
/// learner): its table, if it builds one, is built without the GIL, and
/// Ctrl-C stops it (`KeyboardInterrupt`) within a chunk of commands.
fn executor<'s>(
    py: Python<'_>,
    scene: &'s e3d::Scene,
    work: &Workload,
    options: &ExecOptions,
) -> PyResult<Executor<'s>> {
    let watch = Watch::new();
    let exec = watched(py, None, 0, &watch, |w| {
        let stop = || w.cancelled();
        let control = e3d::Control {
            stop: &stop,
            ..e3d::Control::default()
        };
        Executor::with_control(scene, work, options, &control)
    })?;
    Ok(exec.map_err(Fail::from)?)
}

/// Runs one session of a Python learner on this thread, with the GIL.
pub(super) fn run_python(
    py: Python<'_>,
    scene: &PyScene,
    obj: &Bound<'_, PyAny>,
    a: &SessionArgs,
    run: &OneSession<'_, '_>,
) -> PyResult<Py<PyAny>> {
    let obj = obj.clone();
    let name = python_learner_name(&obj)?;
    let error = RefCell::new(None);
    let mut pl = [PyLearner::new(py, obj, &scene.space, &error)?];
    let configs = std::slice::from_ref(&run.cfg);
    let (mut recs, exec) = run_here(
        py,
        scene,
        a,
        &run.work,
        configs,
        &mut pl,
        &error,
        run.progress,
    )?;
    let rec = recs.remove(0);
    let metrics = symbol_metrics(&exec, &rec, &a.target);
    let rows = Rows::of_symbols(py, rec, metrics, None, None)?;
    record_to_py(py, scene, &name, run.cfg.seed, rows, execution_text(exec))
}

/// Runs sessions of Python learners, one per configuration, in one
/// lockstep group on this thread, with the GIL. Returns the learners'
/// name (their names joined by commas when they differ), their rows and
/// the execution text.
pub(super) fn run_python_batch(
    py: Python<'_>,
    scene: &PyScene,
    objs: Vec<Bound<'_, PyAny>>,
    a: &SessionArgs,
    work: &Workload,
    configs: &[SessionConfig],
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(String, Vec<Rows>, String)> {
    let names: Vec<String> = objs
        .iter()
        .map(python_learner_name)
        .collect::<PyResult<_>>()?;
    let error = RefCell::new(None);
    let mut learners: Vec<PyLearner<'_, '_>> = objs
        .into_iter()
        .map(|o| PyLearner::new(py, o, &scene.space, &error))
        .collect::<PyResult<_>>()?;
    let (records, exec) = run_here(py, scene, a, work, configs, &mut learners, &error, progress)?;
    let rows = records
        .into_iter()
        .map(|r| {
            let m = symbol_metrics(&exec, &r, &a.target);
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
/// the executor chooses; stopped at the first error put in `error` (by a
/// learner, `progress` or `on_trials`), which is then raised, else by the
/// first failing session.
#[allow(clippy::too_many_arguments)]
pub(super) fn run_here<'s, L: Learner>(
    py: Python<'_>,
    scene: &'s PyScene,
    a: &SessionArgs,
    work: &Workload,
    configs: &[SessionConfig],
    learners: &mut [L],
    error: &RefCell<Option<PyErr>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Vec<SessionRecord>, Executor<'s>)> {
    let total = work.trials;
    let exec = executor(py, &scene.inner, work, &a.options)?;
    let mut world = exec.world(configs.len());
    let mut records: Vec<SessionRecord> = configs
        .iter()
        .map(|c| SessionRecord::new(&*world, c.trials))
        .collect();
    let ticks = Ticks::new(py, progress, total, error)?;
    let status = e3d::session::run_group(&mut *world, learners, configs, &mut records, &ticks);
    drop(world);
    if let Some(e) = error.take() {
        return Err(e);
    }
    first_failure(status)?;
    Ok((records, exec))
}
