//! What sessions recorded, handed to `SessionRecord` and `SessionBatch`
//! (python/e3d/_results.py), and the effect grid they draw (its SVG is
//! `_results._grid_svg`).

use crate::scene::PyScene;
use e3d::session::ValueSessionRecord;
use e3d::{Learner, Metrics, SessionRecord};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyList, PyTuple};

/// The effect grid of a session's scene: rows, columns, and whether each
/// cell is rewarded (a dict in Python).
#[derive(Clone, IntoPyObject)]
pub(crate) struct Grid {
    pub(crate) rows: usize,
    pub(crate) cols: usize,
    pub(crate) rewarded: Vec<bool>,
}

impl Grid {
    pub(crate) fn of(scene: &e3d::Scene) -> Grid {
        let g = scene.effect_grid();
        Grid {
            rows: g.rows,
            cols: g.cols,
            rewarded: scene.reward_table().iter().map(|&r| r != 0.0).collect(),
        }
    }
}

/// One session's results, whatever its commands, ready for Python.
pub(crate) struct Rows {
    /// `[T, slots]`, uint8 or float64.
    commands: Py<PyAny>,
    effects: Vec<usize>,
    rewards: Vec<f64>,
    metrics: Metrics,
    effect_counts: Vec<f64>,
    policy: Option<Py<PyAny>>,
    exact: Option<Vec<f64>>,
    /// E3D's final `Q` (per slot) and running effect histogram `p`.
    pub(crate) q: Option<Vec<Vec<f64>>>,
    pub(crate) effect_model: Option<Vec<f64>>,
}

impl Rows {
    /// A session of symbols; `learner` for its final policy (None: a
    /// Python learner), `exact` the exact effect distribution of it.
    pub(crate) fn of_symbols(
        py: Python<'_>,
        rec: SessionRecord,
        metrics: Metrics,
        learner: Option<&dyn Learner>,
        exact: Option<Vec<f64>>,
    ) -> PyResult<Rows> {
        let t = rec.trials();
        let effect_counts = rec.effect_counts(0..t);
        let policy = match learner {
            Some(l) => slot_policies(py, l, rec.num_slots)?,
            None => None,
        };
        let commands = Array2::from_shape_vec((t, rec.num_slots), rec.commands).expect("T x slots");
        Ok(Rows {
            commands: commands.into_pyarray(py).into_any().unbind(),
            effects: rec.effects,
            rewards: rec.rewards,
            metrics,
            effect_counts,
            policy,
            exact,
            q: None,
            effect_model: None,
        })
    }

    /// A session of continuous commands.
    pub(crate) fn of_values(py: Python<'_>, rec: ValueSessionRecord, metrics: Metrics) -> Rows {
        let t = rec.trials();
        let effect_counts = rec.effect_counts(0..t);
        let flat: Vec<f64> = rec.final_policy.iter().flat_map(|&(m, s)| [m, s]).collect();
        let policy = Array2::from_shape_vec((rec.num_slots, 2), flat).expect("slots x 2");
        let commands = Array2::from_shape_vec((t, rec.num_slots), rec.commands).expect("T x slots");
        Rows {
            commands: commands.into_pyarray(py).into_any().unbind(),
            effects: rec.effects,
            rewards: rec.rewards,
            metrics,
            effect_counts,
            policy: Some(policy.into_pyarray(py).into_any().unbind()),
            exact: None,
            q: None,
            effect_model: None,
        }
    }
}

/// Each slot's symbol probabilities under `learner`'s policy, as a list of
/// float64 arrays (None if it does not draw slots independently).
pub(crate) fn slot_policies(
    py: Python<'_>,
    learner: &dyn Learner,
    slots: usize,
) -> PyResult<Option<Py<PyAny>>> {
    let mut out = Vec::with_capacity(slots);
    for s in 0..slots {
        match learner.slot_policy(s) {
            Some(p) => out.push(p.into_pyarray(py)),
            None => return Ok(None),
        }
    }
    Ok(Some(PyList::new(py, out)?.into_any().unbind()))
}

/// A class of python/e3d/_results.py.
pub(crate) fn result_class<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("e3d._results")?.getattr(name)
}

/// A session's metrics as a dict of `summary.json`'s names
/// (`_results._metrics`).
pub(crate) fn metrics_dict<'py>(py: Python<'py>, m: &Metrics) -> PyResult<Bound<'py, PyAny>> {
    let values = (
        m.normalized_entropy,
        m.normalized_entropy_last_1000,
        m.kl_to_target,
        m.distinct_effects,
        m.cumulative_reward,
        m.first_reward_trial,
        m.trials,
        m.reachable_effects,
        m.normalized_entropy_reachable,
        m.coverage_cells,
        m.coverage,
        m.trials_to_50_percent,
    );
    let more = (
        m.trials_to_90_percent,
        m.qd_score,
        m.discovery_trials.clone(),
    );
    let values = values.into_pyobject(py)?.add(more.into_pyobject(py)?)?;
    result_class(py, "_metrics")?.call1(values.cast_into::<PyTuple>()?)
}

/// A session's rows as a `SessionRecord`.
pub(crate) fn record_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    seed: u64,
    rows: Rows,
    execution: String,
) -> PyResult<Py<PyAny>> {
    let effects: Vec<i64> = rows.effects.iter().map(|&e| e as i64).collect();
    let q = match rows.q {
        Some(q) => {
            let arrays: Vec<_> = q.into_iter().map(|s| s.into_pyarray(py)).collect();
            Some(PyList::new(py, arrays)?.into_any().unbind())
        }
        None => None,
    };
    let fields = (
        scene.inner.spec().name.clone(),
        learner,
        seed,
        effects.len(),
        rows.commands,
        effects.into_pyarray(py),
        rows.rewards.into_pyarray(py),
        metrics_dict(py, &rows.metrics)?,
    );
    let more = (
        rows.effect_counts.into_pyarray(py),
        rows.policy,
        rows.exact.map(|d| d.into_pyarray(py)),
        q,
        rows.effect_model.map(|p| p.into_pyarray(py)),
        execution,
        Grid::of(&scene.inner),
    );
    let state = fields.into_pyobject(py)?.add(more.into_pyobject(py)?)?;
    let class = result_class(py, "SessionRecord")?;
    Ok(class.call1(state.cast_into::<PyTuple>()?)?.unbind())
}
