//! `SessionRng`: the session's generator, lent to a Python learner.

use crate::errors::usize_arg;
use e3d::SessionRng;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

/// The session's random generator, handed to a Python learner's
/// `propose(rng)`: the very generator the session was seeded with (PCG
/// 64-bit MCG), valid only during that call: used after it (kept by the
/// learner, or from another thread once `propose` has returned), it raises
/// `RuntimeError`. `SessionRng(seed)` makes one of one's own, valid
/// always.
#[pyclass(module = "e3d", name = "SessionRng")]
pub(crate) struct PyRng {
    pub(crate) inner: SessionRng,
    /// Whether a `propose(rng)` call holds the session's generator.
    pub(crate) active: bool,
}

impl PyRng {
    /// A generator not lent yet.
    pub(crate) fn idle() -> PyRng {
        PyRng {
            inner: rand::SeedableRng::seed_from_u64(0),
            active: false,
        }
    }

    /// The generator, if a `propose(rng)` call holds it.
    pub(crate) fn lent(&mut self) -> PyResult<&mut SessionRng> {
        if !self.active {
            return Err(PyRuntimeError::new_err(
                "SessionRng used outside the propose(rng) call it was given to: it is the session's generator only during that call",
            ));
        }
        Ok(&mut self.inner)
    }

    /// Swaps the session's generator in (or back out), marking the
    /// object active (or not); fails if another thread is using it.
    pub(crate) fn swap(obj: &Bound<'_, PyRng>, rng: &mut SessionRng, active: bool) -> PyResult<()> {
        let mut me = obj.try_borrow_mut().map_err(|_| {
            PyRuntimeError::new_err(
                "SessionRng in use by another thread when propose(rng) returned: use it only within the call",
            )
        })?;
        std::mem::swap(&mut me.inner, rng);
        me.active = active;
        Ok(())
    }
}

#[pymethods]
impl PyRng {
    /// A generator of one's own, seeded as a session of seed `seed` seeds
    /// its generator: with it, `Learner.propose` and `learn` in a loop of
    /// one's own draw what `run_session(seed=seed)` draws.
    #[new]
    fn new(seed: &Bound<'_, PyAny>) -> PyResult<PyRng> {
        Ok(PyRng {
            inner: rand::SeedableRng::seed_from_u64(crate::errors::int_arg(seed, "seed", 0)?),
            active: true,
        })
    }

    /// A float uniform in [0, 1).
    fn random(&mut self) -> PyResult<f64> {
        use rand::RngExt;
        Ok(self.lent()?.random::<f64>())
    }

    /// An integer uniform in [0, n): the draw of the library's uniform
    /// policy for a slot of `n` symbols (rand's `random_range(0..n)` on
    /// `usize`).
    fn integers(&mut self, n: &Bound<'_, PyAny>) -> PyResult<usize> {
        use rand::RngExt;
        let n = usize_arg(n, "n", 1)?;
        Ok(self.lent()?.random_range(0..n))
    }

    /// An index drawn with probability proportional to `weights` (>= 0,
    /// not all 0), by one `random()` and a cumulative sum.
    fn choice(&mut self, weights: Vec<f64>) -> PyResult<usize> {
        use rand::RngExt;
        let total: f64 = weights.iter().sum();
        if weights.is_empty()
            || total <= 0.0
            || weights.iter().any(|w| !(w.is_finite() && *w >= 0.0))
        {
            return Err(PyValueError::new_err(
                "choice(weights): expected finite weights >= 0, not all 0",
            ));
        }
        if !total.is_finite() {
            return Err(PyValueError::new_err(format!(
                "choice(weights): the weights sum past the largest float ({total}): scale them down"
            )));
        }
        let u = self.lent()?.random::<f64>() * total;
        let mut acc = 0.0;
        let first = weights.iter().position(|w| {
            acc += w;
            u < acc
        });
        Ok(first.unwrap_or_else(|| weights.iter().rposition(|w| *w > 0.0).unwrap_or(0)))
    }

    /// Pickles as its generator's state: a copy of one's own generator
    /// draws what the original draws next; a copy of a session's
    /// generator taken outside `propose` raises as the original does.
    #[allow(clippy::type_complexity)]
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, (u64,), (String, bool))> {
        let me = slf.borrow();
        let state =
            serde_json::to_string(&me.inner).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok((slf.get_type().into_any(), (0,), (state, me.active)))
    }

    fn __setstate__(&mut self, state: (String, bool)) -> PyResult<()> {
        self.inner = serde_json::from_str(&state.0)
            .map_err(|e| PyValueError::new_err(format!("SessionRng: not a pickled state: {e}")))?;
        self.active = state.1;
        Ok(())
    }
}
