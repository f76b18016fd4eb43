//! `SessionRng`: the session's generator, lent to a Python learner.

use e3d::SessionRng;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The session's random generator, handed to a Python learner's
/// `propose(rng)`: the very generator the session was seeded with (PCG
/// 64-bit MCG), valid only during that call.
#[pyclass(module = "e3d", name = "SessionRng", unsendable)]
pub(crate) struct PyRng {
    pub(crate) inner: SessionRng,
}

#[pymethods]
impl PyRng {
    /// A float uniform in [0, 1).
    fn random(&mut self) -> f64 {
        use rand::RngExt;
        self.inner.random::<f64>()
    }

    /// An integer uniform in [0, n): the draw of the library's uniform
    /// policy for a slot of `n` symbols (rand's `random_range(0..n)` on
    /// `usize`).
    fn integers(&mut self, n: usize) -> PyResult<usize> {
        use rand::RngExt;
        if n == 0 {
            return Err(PyValueError::new_err("integers(n): n must be at least 1"));
        }
        Ok(self.inner.random_range(0..n))
    }

    /// An index drawn with probability proportional to `weights` (>= 0,
    /// not all 0), by one `random()` and a cumulative sum.
    fn choice(&mut self, weights: Vec<f64>) -> PyResult<usize> {
        use rand::RngExt;
        let total: f64 = weights.iter().sum();
        if weights.is_empty()
            || !total.is_finite()
            || total <= 0.0
            || weights.iter().any(|w| *w < 0.0)
        {
            return Err(PyValueError::new_err(
                "choice(weights): expected finite weights >= 0, not all 0",
            ));
        }
        let u = self.inner.random::<f64>() * total;
        let mut acc = 0.0;
        for (i, w) in weights.iter().enumerate() {
            acc += w;
            if u < acc {
                return Ok(i);
            }
        }
        Ok(weights.iter().rposition(|w| *w > 0.0).unwrap_or(0))
    }
}
