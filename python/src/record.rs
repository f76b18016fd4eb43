//! What sessions recorded: `SessionRecord` and `SessionBatch`.

use crate::scene::PyScene;
use e3d::{Metrics, SessionConfig, SessionRecord, Target};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// What a session recorded: `commands` (uint8 `[T, slots]`), `effects`
/// (int64 `[T]`), `rewards` (float64 `[T]`, 0 when the reward is not
/// used), `metrics` (a dict), and how outcomes were obtained (`execution`).
#[pyclass(module = "e3d", name = "SessionRecord", frozen, get_all)]
pub(crate) struct PyRecord {
    scene: String,
    learner: String,
    seed: u64,
    trials: usize,
    commands: Py<numpy::PyArray2<u8>>,
    effects: Py<PyArray1<i64>>,
    rewards: Py<PyArray1<f64>>,
    metrics: Py<PyDict>,
    execution: String,
}

#[pymethods]
impl PyRecord {
    fn __repr__(&self) -> String {
        format!(
            "SessionRecord(scene={:?}, learner={:?}, seed={}, trials={})",
            self.scene, self.learner, self.seed, self.trials
        )
    }
}

/// A session's metrics as a dict (`summary.json`'s names).
pub(crate) fn metrics_dict<'py>(py: Python<'py>, m: &Metrics) -> PyResult<Bound<'py, PyDict>> {
    let metrics = PyDict::new(py);
    metrics.set_item("normalized_entropy", m.normalized_entropy)?;
    metrics.set_item(
        "normalized_entropy_last_1000",
        m.normalized_entropy_last_1000,
    )?;
    metrics.set_item("kl_to_target", m.kl_to_target)?;
    metrics.set_item("distinct_effects", m.distinct_effects)?;
    metrics.set_item("cumulative_reward", m.cumulative_reward)?;
    metrics.set_item("first_reward_trial", m.first_reward_trial)?;
    metrics.set_item("trials", m.trials)?;
    Ok(metrics)
}

pub(crate) fn record_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    cfg: &SessionConfig,
    rec: SessionRecord,
    execution: String,
) -> PyResult<PyRecord> {
    let metrics = metrics_dict(py, &rec.metrics(&Target::Uniform))?;
    let t = rec.trials();
    let commands = Array2::from_shape_vec((t, rec.num_slots), rec.commands).expect("T x slots");
    let effects: Vec<i64> = rec.effects.iter().map(|&e| e as i64).collect();
    Ok(PyRecord {
        scene: scene.inner.name.clone(),
        learner: learner.to_string(),
        seed: cfg.seed,
        trials: t,
        commands: commands.into_pyarray(py).unbind(),
        effects: effects.into_pyarray(py).unbind(),
        rewards: rec.rewards.into_pyarray(py).unbind(),
        metrics: metrics.unbind(),
        execution,
    })
}

/// Sessions of one scene run together, in lockstep (`run_sessions`):
/// per-session arrays stacked along a first axis of one entry a session.
/// `seeds` (uint64 `[S]`), `commands` (uint8 `[S, T, slots]`), `effects`
/// (int64 `[S, T]`), `rewards` (float64 `[S, T]`), `metrics` (a dict of
/// arrays `[S]`: float64, `distinct_effects` and `trials` int64,
/// `first_reward_trial` float64 with NaN for none, as in `run_sweep`).
/// `batch[i]` is session `i`'s `SessionRecord`.
#[pyclass(module = "e3d", name = "SessionBatch", frozen)]
pub(crate) struct PyBatchRecord {
    #[pyo3(get)]
    scene: String,
    #[pyo3(get)]
    learner: String,
    #[pyo3(get)]
    seeds: Py<PyArray1<u64>>,
    #[pyo3(get)]
    trials: usize,
    #[pyo3(get)]
    commands: Py<numpy::PyArray3<u8>>,
    #[pyo3(get)]
    effects: Py<numpy::PyArray2<i64>>,
    #[pyo3(get)]
    rewards: Py<numpy::PyArray2<f64>>,
    #[pyo3(get)]
    metrics: Py<PyDict>,
    #[pyo3(get)]
    execution: String,
    /// Each session's metrics, as `SessionRecord.metrics`.
    per_session: Vec<Py<PyDict>>,
}

#[pymethods]
impl PyBatchRecord {
    fn __len__(&self) -> usize {
        self.per_session.len()
    }

    /// Session `i`'s record, as `run_session(seed=seeds[i])` returns it
    /// (its arrays are views of this batch's).
    fn __getitem__(&self, py: Python<'_>, i: isize) -> PyResult<PyRecord> {
        let n = self.per_session.len() as isize;
        let k = if i < 0 { i + n } else { i };
        if k < 0 || k >= n {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "session {i} out of range: {n} sessions"
            )));
        }
        let k = k as usize;
        let seed = self.seeds.bind(py).readonly().as_slice()?[k];
        Ok(PyRecord {
            scene: self.scene.clone(),
            learner: self.learner.clone(),
            seed,
            trials: self.trials,
            commands: self.commands.bind(py).get_item(k)?.cast_into()?.unbind(),
            effects: self.effects.bind(py).get_item(k)?.cast_into()?.unbind(),
            rewards: self.rewards.bind(py).get_item(k)?.cast_into()?.unbind(),
            metrics: self.per_session[k].bind(py).copy()?.unbind(),
            execution: self.execution.clone(),
        })
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let seeds = self.seeds.bind(py).readonly();
        let seeds = seeds.as_slice().unwrap_or(&[]);
        format!(
            "SessionBatch(scene={:?}, learner={:?}, {} sessions, seeds {:?}, trials={})",
            self.scene,
            self.learner,
            seeds.len(),
            seeds,
            self.trials
        )
    }
}

pub(crate) fn batch_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    seeds: &[u64],
    trials: usize,
    records: Vec<SessionRecord>,
    execution: String,
) -> PyResult<PyBatchRecord> {
    let s = records.len();
    let slots = scene.space.num_slots();
    let mut commands = Vec::with_capacity(s * trials * slots);
    let mut effects = Vec::with_capacity(s * trials);
    let mut rewards = Vec::with_capacity(s * trials);
    let mut per_session = Vec::with_capacity(s);
    let cols: [&str; 7] = [
        "normalized_entropy",
        "normalized_entropy_last_1000",
        "kl_to_target",
        "distinct_effects",
        "cumulative_reward",
        "first_reward_trial",
        "trials",
    ];
    let mut floats: Vec<Vec<f64>> = vec![Vec::with_capacity(s); cols.len()];
    for rec in &records {
        let m = rec.metrics(&Target::Uniform);
        per_session.push(metrics_dict(py, &m)?.unbind());
        let row = [
            m.normalized_entropy,
            m.normalized_entropy_last_1000,
            m.kl_to_target,
            m.distinct_effects as f64,
            m.cumulative_reward,
            m.first_reward_trial.map_or(f64::NAN, |t| t as f64),
            m.trials as f64,
        ];
        for (c, v) in floats.iter_mut().zip(row) {
            c.push(v);
        }
        commands.extend_from_slice(&rec.commands);
        effects.extend(rec.effects.iter().map(|&e| e as i64));
        rewards.extend_from_slice(&rec.rewards);
    }
    let metrics = PyDict::new(py);
    for (name, v) in cols.iter().zip(floats) {
        if *name == "distinct_effects" || *name == "trials" {
            let ints: Vec<i64> = v.iter().map(|&x| x as i64).collect();
            metrics.set_item(name, ints.into_pyarray(py))?;
        } else {
            metrics.set_item(name, v.into_pyarray(py))?;
        }
    }
    let commands = numpy::ndarray::Array3::from_shape_vec((s, trials, slots), commands)
        .expect("S x T x slots");
    let effects = Array2::from_shape_vec((s, trials), effects).expect("S x T");
    let rewards = Array2::from_shape_vec((s, trials), rewards).expect("S x T");
    Ok(PyBatchRecord {
        scene: scene.inner.name.clone(),
        learner: learner.to_string(),
        seeds: seeds.to_vec().into_pyarray(py).unbind(),
        trials,
        commands: commands.into_pyarray(py).unbind(),
        effects: effects.into_pyarray(py).unbind(),
        rewards: rewards.into_pyarray(py).unbind(),
        metrics: metrics.unbind(),
        execution,
        per_session,
    })
}
