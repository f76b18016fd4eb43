//! `Outcome` and `BatchOutcome`: what executing one command, or a batch,
//! gives back.

use crate::pickling::{pickled, Reduced};
use numpy::{PyArray1, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// The outcome of one command: `effect` (int), `reward` (float) and the
/// terminal point `x`, `y` (metres).
#[pyclass(module = "e3d", name = "Outcome", frozen, get_all)]
#[derive(Clone)]
pub(crate) struct PyOutcome {
    pub(crate) effect: usize,
    pub(crate) reward: f64,
    pub(crate) x: f64,
    pub(crate) y: f64,
}

#[pymethods]
impl PyOutcome {
    fn __repr__(&self) -> String {
        format!(
            "Outcome(effect={}, reward={:?}, x={:?}, y={:?})",
            self.effect, self.reward, self.x, self.y
        )
    }
    fn __eq__(&self, o: &Self) -> bool {
        (self.effect, self.reward, self.x, self.y) == (o.effect, o.reward, o.x, o.y)
    }
    fn __reduce__<'py>(&self, py: Python<'py>) -> Reduced<'py> {
        self.pickle_reduce(py)
    }
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyTuple>) -> PyResult<Self> {
        Self::pickle_from(state)
    }
}

impl From<e3d::Outcome> for PyOutcome {
    fn from(o: e3d::Outcome) -> Self {
        PyOutcome {
            effect: o.effect,
            reward: o.reward,
            x: o.point[0],
            y: o.point[1],
        }
    }
}

/// An `Outcome` held in another result (`Motion.outcome`) as a new Python
/// object: what pickling that result writes.
impl<'py> IntoPyObject<'py> for &PyOutcome {
    type Target = PyOutcome;
    type Output = Bound<'py, PyOutcome>;
    type Error = PyErr;
    fn into_pyobject(self, py: Python<'py>) -> PyResult<Bound<'py, PyOutcome>> {
        Bound::new(py, self.clone())
    }
}

/// The outcomes of a batch of commands, one entry per row, as numpy
/// arrays: `effect` (int64), `reward`, `x`, `y` (float64).
#[pyclass(module = "e3d", name = "BatchOutcome", frozen, get_all)]
pub(crate) struct PyBatch {
    pub(crate) effect: Py<PyArray1<i64>>,
    pub(crate) reward: Py<PyArray1<f64>>,
    pub(crate) x: Py<PyArray1<f64>>,
    pub(crate) y: Py<PyArray1<f64>>,
}

#[pymethods]
impl PyBatch {
    fn __len__(&self, py: Python<'_>) -> usize {
        self.effect.bind(py).len()
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("BatchOutcome({} commands)", self.effect.bind(py).len())
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
        Self::pickle_from(state)
    }
}

pickled!(PyOutcome, "Outcome" { effect, reward, x, y });
pickled!(PyBatch, "BatchOutcome" { effect, reward, x, y });
