//! Sessions of continuous commands: built-in learners of values (the
//! Gaussian E3D, uniform values, ...), new or an `e3d.Learner`'s state,
//! each session live on a physics world of its own.

use super::{Lent, Run, SessionArgs};
use crate::errors::Fail;
use crate::held::{bad, Held};
use crate::progress::{watched, Watch};
use crate::record::Rows;
use crate::scene::PyScene;
use e3d::learner::LearnerSetup;
use e3d::session::ValueSessionRecord;
use e3d::world::Strategy;
use e3d::{ContinuousLearner, LearnerKind};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// Checks that new learners of `kind` (None: Python objects) can run on
/// the continuous `scene` with the options of `a`: built-in learners of
/// values only, no table cache, no strategy but live.
pub(super) fn check_values(
    scene: &PyScene,
    kind: Option<LearnerKind>,
    a: &SessionArgs,
) -> PyResult<()> {
    let name = &scene.inner.spec().name;
    let Some(kind) = kind else {
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
    let space = scene.values.as_ref().expect("a continuous scene");
    LearnerSetup::new(kind)
        .params(a.params)
        .target(a.target.clone())
        .values(space, scene.inner.num_effects())
        .map_err(bad)?;
    Ok(())
}

/// Runs sessions of built-in learners of values (`held`, one per
/// configuration) in parallel without the GIL, each on a physics world of
/// its own (`e3d run` on a continuous scene). Returns their rows and the
/// execution text.
pub(super) fn run_values(
    py: Python<'_>,
    run: &Run<'_, '_>,
    held: &mut [Held],
) -> PyResult<(Vec<Rows>, String)> {
    let inner = &run.scene.inner;
    let exec = e3d::Executor::for_values(inner, run.work).map_err(Fail::from)?;
    let mut learners: Vec<Lent<'_, dyn ContinuousLearner + Send>> = held
        .iter_mut()
        .map(|h| Lent(h.values().expect("a learner of values")))
        .collect();
    let slots = run.scene.values.as_ref().map_or(0, |v| v.num_slots());
    let mut records: Vec<ValueSessionRecord> = run
        .configs
        .iter()
        .map(|c| ValueSessionRecord::new(slots, inner.num_effects(), c.trials))
        .collect();
    let status = watched(py, run.progress, run.work.trials, &Watch::default(), |w| {
        w.control(|c| e3d::run_sessions(&exec, &mut learners, run.configs, &mut records, c))
    })?;
    for ((s, r), l) in status.into_iter().zip(&mut records).zip(&learners) {
        s.map_err(Fail::from)?;
        r.set_policy(&*l.0);
    }
    let rows = records
        .into_iter()
        .map(|r| {
            let effort = e3d::learner::Effort::of_scene(&run.scene.inner);
            let m = e3d::Metrics {
                qd_score: r.qd_score(&effort),
                ..r.metrics(&run.a.target)
            };
            Rows::of_values(py, r, m)
        })
        .collect();
    Ok((rows, "live: continuous commands (no table, no memo)".into()))
}
