//! `Outcome` and `BatchOutcome`: what executing one command, or a batch,
//! gives back.

use crate::pickling::{reduce, state, Fields};
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
    /// Pickling (see `pickling`): `(effect, reward, x, y)`.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyTuple>,))> {
        reduce::<Self>(py, state![py; self.effect, self.reward, self.x, self.y])
    }
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyTuple>) -> PyResult<Self> {
        let mut f = Fields::of(state, "Outcome", 4)?;
        Ok(PyOutcome {
            effect: f.take()?,
            reward: f.take()?,
            x: f.take()?,
            y: f.take()?,
        })
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
    /// Pickling (see `pickling`): `(effect, reward, x, y)`.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyTuple>,))> {
        reduce::<Self>(py, state![py; &self.effect, &self.reward, &self.x, &self.y])
    }
    #[staticmethod]
    fn _from_state(state: &Bound<'_, PyTuple>) -> PyResult<Self> {
        let mut f = Fields::of(state, "BatchOutcome", 4)?;
        Ok(PyBatch {
            effect: f.take()?,
            reward: f.take()?,
            x: f.take()?,
            y: f.take()?,
        })
    }
}
