//! What sessions recorded: `SessionRecord` and `SessionBatch`.

use crate::pickling::{pickled, Reduced};
use crate::scene::PyScene;
use e3d::session::ValueSessionRecord;
use e3d::{Learner, Metrics, SessionRecord};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PySlice, PyTuple};

/// What a session recorded: `commands` (`[T, slots]`: uint8 symbol indices,
/// or float64 values on a continuous scene), `effects` (int64 `[T]`),
/// `rewards` (float64 `[T]`, 0 when the reward is not used), `metrics` (a
/// dict, `summary.json`'s names), `effect_counts` (float64
/// `[num_effects]`), `final_policy` (per slot the final policy: a float64
/// array of each symbol's probability, or `(mean, sd)` on a continuous
/// scene; None for a Python learner), `policy_effect_distribution` (the
/// exact effect distribution of the final policy, where the outcomes come
/// from a table, else None), E3D's final `q` (per slot a float64 array of
/// `Q`) and `effect_model` (its running effect histogram `p`, float64
/// `[num_effects]`), both from `run_session` with `learner="e3d"` only
/// (else None), and how outcomes were obtained (`execution`).
#[pyclass(module = "e3d", name = "SessionRecord", frozen)]
pub(crate) struct PyRecord {
    #[pyo3(get)]
    scene: String,
    #[pyo3(get)]
    learner: String,
    #[pyo3(get)]
    seed: u64,
    #[pyo3(get)]
    trials: usize,
    #[pyo3(get)]
    commands: Py<PyAny>,
    #[pyo3(get)]
    effects: Py<PyArray1<i64>>,
    #[pyo3(get)]
    rewards: Py<PyArray1<f64>>,
    metrics: Py<PyDict>,
    #[pyo3(get)]
    effect_counts: Py<PyArray1<f64>>,
    #[pyo3(get)]
    final_policy: Option<Py<PyAny>>,
    #[pyo3(get)]
    policy_effect_distribution: Option<Py<PyArray1<f64>>>,
    #[pyo3(get)]
    q: Option<Py<PyAny>>,
    #[pyo3(get)]
    effect_model: Option<Py<PyArray1<f64>>>,
    #[pyo3(get)]
    execution: String,
    /// The effect grid's rows, columns and rewarded cells (for the picture).
    grid: Grid,
}

/// The effect grid of a session's scene: rows, columns, and whether each
/// cell is rewarded.
#[derive(Clone, IntoPyObjectRef, FromPyObject)]
#[pyo3(from_item_all)]
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

    /// An SVG of the grid, each cell shaded by its share of `counts` (its
    /// count over the largest, white to dark blue) and labelled with it in
    /// `unit` (`trials`, `episodes`),
    /// the rewarded cells outlined in green; row 0 at the bottom, as the
    /// scene's picture has it.
    pub(crate) fn svg(&self, counts: &[f64], unit: &str, title: &str) -> String {
        use std::fmt::Write;
        let cell = (480.0 / self.cols.max(self.rows) as f64).clamp(4.0, 60.0);
        let (w, h) = (self.cols as f64 * cell, self.rows as f64 * cell);
        let top = counts.iter().copied().fold(0.0, f64::max).max(1.0);
        let total: f64 = counts.iter().sum::<f64>().max(1.0);
        let mut out = format!(
            r##"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 0 {:.0} {:.0}" font-family="Helvetica, Arial, sans-serif"><rect width="100%" height="100%" fill="#ffffff"/><text x="10" y="20" font-size="14" fill="#222">{}</text>"##,
            w + 20.0,
            h + 40.0,
            w + 20.0,
            h + 40.0,
            title.replace('&', "&amp;").replace('<', "&lt;")
        );
        for (e, &c) in counts.iter().enumerate() {
            let (r, col) = (e / self.cols, e % self.cols);
            let (x, y) = (
                10.0 + col as f64 * cell,
                30.0 + (self.rows - 1 - r) as f64 * cell,
            );
            let f = c / top;
            let shade = |lo: f64, hi: f64| (hi + (lo - hi) * f).round() as u8;
            let (cr, cg, cb) = (shade(31.0, 255.0), shade(78.0, 255.0), shade(156.0, 255.0));
            let stroke = if self.rewarded.get(e).copied().unwrap_or(false) {
                r##"stroke="#2e8b57" stroke-width="3""##
            } else {
                r##"stroke="#b8c4d6" stroke-width="0.8""##
            };
            let _ = write!(
                out,
                r#"<rect x="{x:.1}" y="{y:.1}" width="{cell:.1}" height="{cell:.1}" fill="rgb({cr},{cg},{cb})" {stroke}><title>cell ({r}, {col}): {c} {unit} ({:.1}%)</title></rect>"#,
                100.0 * c / total
            );
        }
        out.push_str("</svg>");
        out
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
        let commands = Array2::from_shape_vec((t, rec.num_slots), rec.values).expect("T x slots");
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

#[pymethods]
impl PyRecord {
    /// The metrics (a copy: the record keeps its own).
    #[getter]
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.metrics.bind(py).copy()
    }

    /// Equal when every field is (arrays value by value, NaN equal to
    /// NaN): a pickled copy, or the same work run again.
    fn __eq__(&self, py: Python<'_>, other: PyRef<'_, Self>) -> PyResult<bool> {
        self.pickle_eq(py, &other)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> Reduced<'py> {
        self.pickle_reduce(py)
    }
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyTuple>) -> PyResult<Self> {
        Self::pickle_from(state)?.frozen(state.py())
    }

    /// The session as a picture, for notebooks: the effect grid with each
    /// cell shaded by its share of the trials (`effect_counts`), the
    /// rewarded cells outlined.
    fn _repr_svg_(&self, py: Python<'_>) -> PyResult<String> {
        let counts = self.effect_counts.bind(py).readonly().as_slice()?.to_vec();
        let title = format!(
            "{}: {}, seed {}, {} trials",
            self.scene, self.learner, self.seed, self.trials
        );
        Ok(self.grid.svg(&counts, "trials", &title))
    }

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
    metrics.set_item("reachable_effects", m.reachable_effects)?;
    metrics.set_item(
        "normalized_entropy_reachable",
        m.normalized_entropy_reachable,
    )?;
    metrics.set_item("coverage_cells", m.coverage_cells)?;
    metrics.set_item("coverage", m.coverage)?;
    metrics.set_item("trials_to_50_percent", m.trials_to_50_percent)?;
    metrics.set_item("trials_to_90_percent", m.trials_to_90_percent)?;
    metrics.set_item("discovery_trials", m.discovery_trials.clone())?;
    Ok(metrics)
}

pub(crate) fn record_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    seed: u64,
    rows: Rows,
    execution: String,
) -> PyResult<PyRecord> {
    let effects: Vec<i64> = rows.effects.iter().map(|&e| e as i64).collect();
    PyRecord {
        scene: scene.inner.spec().name.clone(),
        learner: learner.to_string(),
        seed,
        trials: effects.len(),
        commands: rows.commands,
        effects: effects.into_pyarray(py).unbind(),
        rewards: rows.rewards.into_pyarray(py).unbind(),
        metrics: metrics_dict(py, &rows.metrics)?.unbind(),
        effect_counts: rows.effect_counts.into_pyarray(py).unbind(),
        final_policy: rows.policy,
        policy_effect_distribution: rows.exact.map(|d| d.into_pyarray(py).unbind()),
        q: match rows.q {
            Some(q) => {
                let arrays: Vec<_> = q.into_iter().map(|s| s.into_pyarray(py)).collect();
                Some(PyList::new(py, arrays)?.into_any().unbind())
            }
            None => None,
        },
        effect_model: rows.effect_model.map(|p| p.into_pyarray(py).unbind()),
        execution,
        grid: Grid::of(&scene.inner),
    }
    .frozen(py)
}

/// Sessions of one scene run together, in lockstep (`run_sessions`):
/// per-session arrays stacked along a first axis of one entry a session.
/// `seeds` (uint64 `[S]`), `commands` (uint8 `[S, T, slots]`), `effects`
/// (int64 `[S, T]`), `rewards` (float64 `[S, T]`), `metrics` (a dict of
/// arrays `[S]`: float64, `distinct_effects`, `trials` and
/// `coverage_cells` int64, `first_reward_trial`, `reachable_effects`,
/// `normalized_entropy_reachable` and `trials_to_50_percent` / `_90_`
/// float64 with NaN for none, as in `run_sweep`; each session's
/// `discovery_trials` is in `batch[i].metrics`).
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
    commands: Py<PyAny>,
    #[pyo3(get)]
    effects: Py<numpy::PyArray2<i64>>,
    #[pyo3(get)]
    rewards: Py<numpy::PyArray2<f64>>,
    metrics: Py<PyDict>,
    #[pyo3(get)]
    execution: String,
    /// The effect grid (for each session's picture).
    grid: Grid,
    /// Each session's metrics, as `SessionRecord.metrics`.
    per_session: Vec<Py<PyDict>>,
    /// Each session's effect counts and final policy.
    counts: Vec<Py<PyArray1<f64>>>,
    policies: Vec<Option<Py<PyAny>>>,
}

#[pymethods]
impl PyBatchRecord {
    /// The metrics (a copy: the record keeps its own).
    #[getter]
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.metrics.bind(py).copy()
    }

    /// Equal when every field is (arrays value by value, NaN equal to
    /// NaN): a pickled copy, or the same work run again.
    fn __eq__(&self, py: Python<'_>, other: PyRef<'_, Self>) -> PyResult<bool> {
        self.pickle_eq(py, &other)
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> Reduced<'py> {
        self.pickle_reduce(py)
    }
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyTuple>) -> PyResult<Self> {
        let b = Self::pickle_from(state)?;
        // the commands are an array [S, T, slots] (indexed per session)
        let py = state.py();
        let commands = b.commands.bind(py);
        let sessions = b.per_session.len();
        let fits = commands
            .getattr_opt("shape")?
            .and_then(|s| s.extract::<Vec<usize>>().ok())
            .is_some_and(|s| s.len() == 3 && s[0] == sessions && s[1] == b.trials);
        if !fits {
            return Err(pyo3::exceptions::PyValueError::new_err(format!(
                "SessionBatch: not a pickled state: commands of {sessions} sessions x {} trials expected",
                b.trials
            )));
        }
        b.frozen(py)
    }

    fn __len__(&self) -> usize {
        self.per_session.len()
    }

    /// The sessions as a picture, for notebooks: the effect grid with each
    /// cell shaded by its share of the trials of every session together
    /// (the sum of their `effect_counts`), the rewarded cells outlined.
    fn _repr_svg_(&self, py: Python<'_>) -> PyResult<String> {
        let mut total = vec![0.0; self.grid.rows * self.grid.cols];
        for c in &self.counts {
            let c = c.bind(py).readonly();
            for (t, x) in total.iter_mut().zip(c.as_slice()?) {
                *t += x;
            }
        }
        let title = format!(
            "{}: {}, {} sessions of {} trials",
            self.scene,
            self.learner,
            self.per_session.len(),
            self.trials
        );
        Ok(self.grid.svg(&total, "trials", &title))
    }

    /// Session `i`'s record, as `run_session(seed=seeds[i])` returns it
    /// (its arrays are views of this batch's); a slice, the batch of
    /// those sessions (`batch[:10]`, `batch[::2]`).
    fn __getitem__<'py>(
        &self,
        py: Python<'py>,
        i: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        if let Ok(slice) = i.cast::<PySlice>() {
            return Ok(Bound::new(py, self.sliced(py, slice)?)?.into_any());
        }
        Ok(Bound::new(py, self.session(py, i)?)?.into_any())
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

impl PyBatchRecord {
    /// The sessions of `slice`, as a batch of their own: its arrays are
    /// views of this batch's rows, its metrics those sessions' values.
    fn sliced(&self, py: Python<'_>, slice: &Bound<'_, PySlice>) -> PyResult<PyBatchRecord> {
        let at = slice.indices(self.per_session.len() as isize)?;
        let rows: Vec<usize> = (0..at.slicelength)
            .map(|k| (at.start + k as isize * at.step) as usize)
            .collect();
        let seeds = self.seeds.bind(py).readonly();
        let seeds = seeds.as_slice()?;
        let metrics = PyDict::new(py);
        for (k, v) in self.metrics.bind(py).iter() {
            metrics.set_item(k, v.get_item(slice)?)?;
        }
        PyBatchRecord {
            scene: self.scene.clone(),
            learner: self.learner.clone(),
            seeds: PyArray1::from_vec(py, rows.iter().map(|&k| seeds[k]).collect()).unbind(),
            trials: self.trials,
            commands: self.commands.bind(py).get_item(slice)?.unbind(),
            effects: self.effects.bind(py).get_item(slice)?.cast_into()?.unbind(),
            rewards: self.rewards.bind(py).get_item(slice)?.cast_into()?.unbind(),
            metrics: metrics.unbind(),
            execution: self.execution.clone(),
            grid: self.grid.clone(),
            per_session: rows
                .iter()
                .map(|&k| self.per_session[k].clone_ref(py))
                .collect(),
            counts: rows.iter().map(|&k| self.counts[k].clone_ref(py)).collect(),
            policies: rows
                .iter()
                .map(|&k| self.policies[k].as_ref().map(|p| p.clone_ref(py)))
                .collect(),
        }
        .frozen(py)
    }

    /// Session `i`'s record (`__getitem__` of an integer).
    fn session(&self, py: Python<'_>, i: &Bound<'_, PyAny>) -> PyResult<PyRecord> {
        let n = self.per_session.len() as i128;
        let out_of_range = || {
            pyo3::exceptions::PyIndexError::new_err(format!(
                "session {} out of range: {n} sessions",
                i.str().map(|s| s.to_string()).unwrap_or_default()
            ))
        };
        if !crate::errors::is_integer(i)? {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "session index: expected an integer or a slice, found {}",
                crate::errors::type_name(i)
            )));
        }
        // any Python int: one beyond i128 is out of range too
        let i: i128 = match i.extract::<i128>() {
            Ok(i) => i,
            Err(_) if i.hasattr("__index__")? => return Err(out_of_range()),
            Err(_) => {
                return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                    "session index: expected an integer or a slice, found {}",
                    i.get_type().name()?
                )))
            }
        };
        let k = if i < 0 { i + n } else { i };
        if k < 0 || k >= n {
            return Err(out_of_range());
        }
        let k = k as usize;
        let seed = self.seeds.bind(py).readonly().as_slice()?[k];
        PyRecord {
            scene: self.scene.clone(),
            learner: self.learner.clone(),
            seed,
            trials: self.trials,
            commands: self.commands.bind(py).get_item(k)?.unbind(),
            effects: self.effects.bind(py).get_item(k)?.cast_into()?.unbind(),
            rewards: self.rewards.bind(py).get_item(k)?.cast_into()?.unbind(),
            metrics: self.per_session[k].bind(py).copy()?.unbind(),
            effect_counts: self.counts[k].clone_ref(py),
            final_policy: self.policies[k].as_ref().map(|p| p.clone_ref(py)),
            policy_effect_distribution: None,
            q: None,
            effect_model: None,
            execution: self.execution.clone(),
            grid: self.grid.clone(),
        }
        .frozen(py)
    }
}

/// The metrics of a batch of sessions, one array each, one value per
/// session: `SessionBatch.metrics`' keys, in order.
const BATCH_COLUMNS: [&str; 13] = [
    "normalized_entropy",
    "normalized_entropy_last_1000",
    "kl_to_target",
    "distinct_effects",
    "cumulative_reward",
    "first_reward_trial",
    "trials",
    "reachable_effects",
    "normalized_entropy_reachable",
    "coverage_cells",
    "coverage",
    "trials_to_50_percent",
    "trials_to_90_percent",
];

/// A session's metrics as numbers, in the order of [`BATCH_COLUMNS`] (NaN
/// for a metric it lacks).
fn batch_row(m: &Metrics) -> [f64; 13] {
    [
        m.normalized_entropy,
        m.normalized_entropy_last_1000,
        m.kl_to_target,
        m.distinct_effects as f64,
        m.cumulative_reward,
        m.first_reward_trial.map_or(f64::NAN, |t| t as f64),
        m.trials as f64,
        m.reachable_effects.map_or(f64::NAN, |k| k as f64),
        m.normalized_entropy_reachable.unwrap_or(f64::NAN),
        m.coverage_cells as f64,
        m.coverage,
        m.trials_to_50_percent.map_or(f64::NAN, |t| t as f64),
        m.trials_to_90_percent.map_or(f64::NAN, |t| t as f64),
    ]
}

/// `SessionBatch.metrics`: each column of [`BATCH_COLUMNS`] as an array,
/// of integers for the counts (`distinct_effects`, `trials`,
/// `coverage_cells`).
fn batch_metrics(py: Python<'_>, floats: Vec<Vec<f64>>) -> PyResult<Bound<'_, PyDict>> {
    let metrics = PyDict::new(py);
    for (name, v) in BATCH_COLUMNS.iter().zip(floats) {
        if matches!(*name, "distinct_effects" | "trials" | "coverage_cells") {
            let ints: Vec<i64> = v.iter().map(|&x| x as i64).collect();
            metrics.set_item(name, ints.into_pyarray(py))?;
        } else {
            metrics.set_item(name, v.into_pyarray(py))?;
        }
    }
    Ok(metrics)
}

/// A batch of sessions (`run_sessions`) as a `SessionBatch`: the sessions'
/// arrays stacked, one row per session, and their metrics as columns.
pub(crate) fn batch_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    seeds: &[u64],
    trials: usize,
    rows: Vec<Rows>,
    execution: String,
) -> PyResult<PyBatchRecord> {
    let s = rows.len();
    let mut effects = Vec::with_capacity(s * trials);
    let mut rewards = Vec::with_capacity(s * trials);
    let mut per_session = Vec::with_capacity(s);
    let mut counts = Vec::with_capacity(s);
    let mut policies = Vec::with_capacity(s);
    let mut commands = Vec::with_capacity(s);
    let mut floats: Vec<Vec<f64>> = vec![Vec::with_capacity(s); BATCH_COLUMNS.len()];
    for r in rows {
        let m = &r.metrics;
        per_session.push(metrics_dict(py, m)?.unbind());
        for (c, v) in floats.iter_mut().zip(batch_row(m)) {
            c.push(v);
        }
        commands.push(r.commands);
        effects.extend(r.effects.iter().map(|&e| e as i64));
        rewards.extend_from_slice(&r.rewards);
        counts.push(r.effect_counts.into_pyarray(py).unbind());
        policies.push(r.policy);
    }
    let metrics = batch_metrics(py, floats)?;
    let commands = py
        .import("numpy")?
        .call_method1("stack", (PyList::new(py, commands)?,))?
        .unbind();
    let effects = Array2::from_shape_vec((s, trials), effects).expect("S x T");
    let rewards = Array2::from_shape_vec((s, trials), rewards).expect("S x T");
    PyBatchRecord {
        scene: scene.inner.spec().name.clone(),
        learner: learner.to_string(),
        seeds: seeds.to_vec().into_pyarray(py).unbind(),
        trials,
        commands,
        effects: effects.into_pyarray(py).unbind(),
        rewards: rewards.into_pyarray(py).unbind(),
        metrics: metrics.unbind(),
        execution,
        grid: Grid::of(&scene.inner),
        per_session,
        counts,
        policies,
    }
    .frozen(py)
}

pickled!(PyRecord, "SessionRecord" {
    scene, learner, seed, trials, commands, effects, rewards, metrics, effect_counts,
    final_policy, policy_effect_distribution, q, effect_model, execution, grid,
});
pickled!(PyBatchRecord, "SessionBatch" {
    scene, learner, seeds, trials, commands, effects, rewards, metrics, execution, grid,
    per_session, counts, policies,
});
