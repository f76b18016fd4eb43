//! Sessions of continuous commands: a built-in learner of values (the
//! Gaussian E3D or uniform values), or an `e3d.Learner`'s state, each
//! session live on a physics world of its own.

use super::{write_back, OneSession, SessionArgs};
use crate::errors::Fail;
use crate::held::{bad, Held};
use crate::learner::builtin_kind;
use crate::progress::{watched, Watch};
use crate::record::{record_to_py, Rows};
use crate::saved::PyLearnerState;
use crate::scene::PyScene;
use e3d::command::ValueSpace;
use e3d::learner::LearnerSetup;
use e3d::session::ValueSessionRecord;
use e3d::world::Strategy;
use e3d::LearnerKind;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// Runs sessions of a continuous scene, one per seed, in parallel without
/// the GIL, each on a physics world of its own (`e3d run` on a continuous
/// scene): the Gaussian E3D (`"e3d"`) or uniform values (`"uniform"`).
#[allow(clippy::too_many_arguments)]
pub(super) fn run_continuous(
    py: Python<'_>,
    scene: &PyScene,
    space: &ValueSpace,
    learner: Option<&Bound<'_, PyAny>>,
    a: &SessionArgs,
    seeds: &[u64],
    trials: usize,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(LearnerKind, Vec<Rows>, String)> {
    let kind = continuous_kind(scene, learner, a)?;
    let n_eff = scene.inner.num_effects();
    let make = || {
        LearnerSetup::new(kind)
            .params(a.params)
            .target(a.target.clone())
            .values(space, n_eff)
    };
    make().map_err(bad)?;
    if scene.inner.as_continuous().is_none() {
        return Err(PyValueError::new_err(format!(
            "scene `{}`: continuous commands need a physics world",
            scene.inner.spec().name
        )));
    }
    let configs = a.configs(trials, seeds);
    let total = (trials as u64).saturating_mul(seeds.len() as u64);
    let work = e3d::world::Workload {
        trials: total,
        sessions: configs.len(),
        threads: rayon::current_num_threads(),
    };
    let exec = e3d::Executor::for_values(&scene.inner, &work).map_err(Fail::from)?;
    let mut learners = configs
        .iter()
        .map(|_| make())
        .collect::<Result<Vec<_>, _>>()
        .map_err(bad)?;
    let mut records: Vec<ValueSessionRecord> = configs
        .iter()
        .map(|c| ValueSessionRecord::new(space.num_slots(), n_eff, c.trials))
        .collect();
    let watch = Watch::new();
    let status = watched(py, progress, total, &watch, |watch| {
        watch.control(|control| {
            e3d::run_sessions(&exec, &mut learners, &configs, &mut records, control)
        })
    })?;
    for ((s, r), l) in status.into_iter().zip(&mut records).zip(&learners) {
        s.map_err(Fail::from)?;
        r.set_policy(l);
    }
    let rows = records
        .into_iter()
        .map(|r| {
            let m = r.metrics(&a.target);
            Rows::of_values(py, r, m)
        })
        .collect();
    Ok((kind, rows, LIVE_VALUES.into()))
}

/// The built-in learner of a session of a continuous scene, with the
/// options checked: no table cache, no strategy but live.
pub(super) fn continuous_kind(
    scene: &PyScene,
    learner: Option<&Bound<'_, PyAny>>,
    a: &SessionArgs,
) -> PyResult<LearnerKind> {
    let name = &scene.inner.spec().name;
    let Some(kind) = builtin_kind(learner)? else {
        return Err(PyTypeError::new_err(format!(
            "learner: scene `{name}` takes continuous commands: expected one of {}",
            LearnerKind::CONTINUOUS
                .map(|k| format!("\"{}\"", k.as_str()))
                .join(", ")
        )));
    };
    if a.options.cache.is_some() {
        return Err(PyValueError::new_err(format!(
            "table_cache: scene `{name}` takes continuous commands, which have no outcome table (every trial is simulated)"
        )));
    }
    if matches!(a.options.force, Some(s) if s != Strategy::Live) {
        return Err(PyValueError::new_err(format!(
            "outcomes: scene `{name}` takes continuous commands, which run live only (no table, no memo)"
        )));
    }
    Ok(kind)
}

/// Runs one session of an `e3d.Learner`'s state on a continuous scene, on
/// a physics world of its own (off the GIL, stopped by Ctrl-C or by
/// `progress`), and writes the state it ends in back.
pub(super) fn run_held_values(
    py: Python<'_>,
    scene: &PyScene,
    saved: Option<&Bound<'_, PyLearnerState>>,
    mut held: Held,
    a: &SessionArgs,
    run: &OneSession<'_, '_>,
) -> PyResult<Py<PyAny>> {
    let name = held.kind().as_str();
    let l = held
        .values()
        .ok_or_else(|| PyTypeError::new_err("learner: not of values"))?;
    let Some(mut world) = scene.inner.as_continuous().map(|c| c.world(1)) else {
        return Err(PyValueError::new_err(format!(
            "scene `{}`: continuous commands need a physics world",
            scene.inner.spec().name
        )));
    };
    let cfg = &run.cfg;
    let slots = e3d::world::ContinuousWorld::value_space(&world).num_slots();
    let rec = watched(
        py,
        run.progress,
        cfg.trials as u64,
        &Watch::new(),
        |watch| {
            let mut rec = ValueSessionRecord::new(slots, scene.inner.num_effects(), cfg.trials);
            watch.control(|control| {
                e3d::session::run_session_into(&mut world, &mut *l, cfg, &mut rec, control)
            })?;
            rec.set_policy(&*l);
            Ok::<_, e3d::WorldError>(rec)
        },
    )?
    .map_err(Fail::from)?;
    let metrics = rec.metrics(&a.target);
    let rows = Rows::of_values(py, rec, metrics);
    write_back(saved, Some(held));
    let execution = LIVE_VALUES.to_string();
    record_to_py(py, scene, name, run.cfg.seed, rows, execution)
}

/// The execution text of sessions of continuous commands.
pub(super) const LIVE_VALUES: &str = "live: continuous commands (no table, no memo)";
