//! `E3dLearner`: an E3D learner's state, read and written from Python (Q,
//! the policy, the effect model), saved and loaded bit for bit, pickled,
//! and run by `run_session(learner=...)`, which continues from it.

use crate::scene::{scene_of, target_arg, PyScene};
use e3d::{E3d, Learner, LearnerState, Params};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// An E3D learner (the paper's Algorithm 1) for a scene of symbols: its
/// Q table, its policy and its effect model can be read and written, its
/// whole state saved as bytes (`to_bytes`, `from_bytes`, pickling) and
/// read back bit for bit. `run_session(scene, learner=l)` runs a session
/// from `l`'s state and leaves `l` in the state the session ends in.
#[pyclass(module = "e3d", name = "E3dLearner")]
#[derive(Clone)]
pub(crate) struct PyE3dLearner {
    pub(crate) inner: E3d,
    /// The alphabet size of each slot, and the number of effects (to
    /// check a scene given to `run_session`).
    pub(crate) sizes: Vec<usize>,
    pub(crate) num_effects: usize,
}

fn bad(e: e3d::LearnerError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

impl PyE3dLearner {
    fn of(inner: E3d) -> PyE3dLearner {
        let num_effects = inner.effect_model().num_effects();
        let sizes = (0..inner.num_slots()).map(|s| inner.q(s).len()).collect();
        PyE3dLearner {
            inner,
            sizes,
            num_effects,
        }
    }

    /// Checks that `scene` fits this learner (its slots' alphabet sizes
    /// and its number of effects).
    pub(crate) fn check_fits(&self, scene: &PyScene) -> PyResult<()> {
        scene.require_symbols("E3dLearner")?;
        let sizes: Vec<usize> = scene.space.sizes().collect();
        if sizes != self.sizes || scene.inner.num_effects() != self.num_effects {
            return Err(PyValueError::new_err(format!(
                "learner: this E3dLearner has alphabet sizes {:?} and {} effects; scene `{}` has {:?} and {}",
                self.sizes,
                self.num_effects,
                scene.inner.name,
                sizes,
                scene.inner.num_effects()
            )));
        }
        Ok(())
    }
}

#[pymethods]
impl PyE3dLearner {
    /// A fresh learner (Q = 0, p uniform) for `scene` (a `Scene`, a path or
    /// a built-in name) with E3D's hyper-parameters and target `p*` (as
    /// `run_session` takes them).
    #[new]
    #[pyo3(signature = (scene, alpha = 0.3, beta = 1.0, lambda_ = 0.03, eta = 0.01, target = None))]
    fn new(
        scene: &Bound<'_, PyAny>,
        alpha: f64,
        beta: f64,
        lambda_: f64,
        eta: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyE3dLearner> {
        let scene = scene_of(scene)?;
        scene.require_symbols("E3dLearner")?;
        let target = target_arg(&scene, target)?;
        let params = Params {
            alpha,
            beta,
            lambda: lambda_,
            eta,
            ..Params::TASK1
        };
        let l = E3d::new(&scene.space, scene.inner.num_effects(), &params, &target).map_err(bad)?;
        Ok(PyE3dLearner::of(l))
    }

    /// The alphabet size of each slot.
    #[getter]
    fn alphabet_sizes(&self) -> Vec<usize> {
        self.sizes.clone()
    }

    /// The number of effects.
    #[getter]
    fn num_effects(&self) -> usize {
        self.num_effects
    }

    /// `Q`, one float64 array per slot (copies: write with `set_q` or by
    /// assigning the whole list).
    #[getter]
    fn q<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<f64>>> {
        (0..self.sizes.len())
            .map(|s| self.inner.q(s).to_vec().into_pyarray(py))
            .collect()
    }

    #[setter(q)]
    fn set_q_all(&mut self, q: Vec<Vec<f64>>) -> PyResult<()> {
        if q.len() != self.sizes.len() {
            return Err(PyValueError::new_err(format!(
                "q: {} slots given, the learner has {}",
                q.len(),
                self.sizes.len()
            )));
        }
        let mut next = self.inner.clone();
        for (s, v) in q.iter().enumerate() {
            next.set_q(s, v).map_err(bad)?;
        }
        self.inner = next;
        Ok(())
    }

    /// Replaces `Q[:, slot]` (one finite value per symbol of the slot).
    fn set_q(&mut self, slot: usize, q: Vec<f64>) -> PyResult<()> {
        self.inner.set_q(slot, &q).map_err(bad)
    }

    /// The policy, one array per slot: `softmax(beta Q[:, slot])`.
    #[getter]
    fn policy<'py>(&self, py: Python<'py>) -> Vec<Bound<'py, PyArray1<f64>>> {
        (0..self.sizes.len())
            .map(|s| self.inner.policy(s).into_pyarray(py))
            .collect()
    }

    /// Sets slot `slot`'s policy to `probs` (each > 0, summing to 1): Q of
    /// the slot becomes `log(probs) / beta` (softmax is unchanged
    /// by a constant added to a slot's Q).
    fn set_policy(&mut self, slot: usize, probs: Vec<f64>) -> PyResult<()> {
        let total: f64 = probs.iter().sum();
        if probs.iter().any(|p| !(p.is_finite() && *p > 0.0)) || (total - 1.0).abs() > 1e-9 {
            return Err(PyValueError::new_err(format!(
                "policy of slot {slot}: expected probabilities > 0 summing to 1, found {probs:?}"
            )));
        }
        let beta = self.beta();
        let q: Vec<f64> = probs.iter().map(|p| p.ln() / beta).collect();
        self.inner.set_q(slot, &q).map_err(bad)
    }

    /// The inverse temperature `beta`.
    #[getter]
    fn beta(&self) -> f64 {
        self.inner.beta()
    }

    /// The effect model `p`, the running histogram of effects (a copy;
    /// assign an array of `num_effects` probabilities to replace it).
    #[getter]
    fn effect_model<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.effect_model().probs().into_pyarray(py)
    }

    #[setter]
    fn set_effect_model(&mut self, probs: Vec<f64>) -> PyResult<()> {
        if probs.len() != self.num_effects {
            return Err(PyValueError::new_err(format!(
                "effect_model: {} probabilities given, the learner has {} effects",
                probs.len(),
                self.num_effects
            )));
        }
        self.inner.set_effect_model(&probs).map_err(bad)
    }

    /// The learner's whole state as bytes, bit for bit: `from_bytes` reads
    /// it back as a learner that proposes and learns exactly as this one.
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.inner.to_bytes())
    }

    /// A learner from the bytes of `to_bytes` (`ValueError` if they are not).
    #[staticmethod]
    fn from_bytes(data: &[u8]) -> PyResult<PyE3dLearner> {
        E3d::from_bytes(data).map(PyE3dLearner::of).map_err(bad)
    }

    /// Draws a command from the policy with `rng` (a `SessionRng` lent
    /// to a Python learner's `propose`): a uint8 array of symbol indices.
    fn propose<'py>(
        &mut self,
        py: Python<'py>,
        rng: &Bound<'py, crate::rng::PyRng>,
    ) -> PyResult<Bound<'py, PyArray1<u8>>> {
        let mut r = rng.try_borrow_mut()?;
        let rng = r.lent()?;
        let mut c = e3d::Command::new(vec![0; self.sizes.len()]);
        self.inner.propose(rng, &mut c);
        Ok(c.symbols.into_pyarray(py))
    }

    /// Learns from the outcome of `command` (symbol indices): E3D's update.
    fn learn(&mut self, command: Vec<u8>, effect: usize, reward: f64) -> PyResult<()> {
        if command.len() != self.sizes.len()
            || command
                .iter()
                .zip(&self.sizes)
                .any(|(&a, &k)| usize::from(a) >= k)
        {
            return Err(PyValueError::new_err(format!(
                "command {command:?}: expected one symbol index per slot, within the alphabet sizes {:?}",
                self.sizes
            )));
        }
        if effect >= self.num_effects {
            return Err(PyValueError::new_err(format!(
                "effect {effect}: expected an effect in [0, {})",
                self.num_effects
            )));
        }
        let o = e3d::Outcome {
            effect,
            reward,
            point: [0.0, 0.0],
        };
        self.inner.learn(&e3d::Command::new(command), &o);
        Ok(())
    }

    /// The name a session record gives this learner.
    #[getter]
    fn name(&self) -> &'static str {
        "e3d"
    }

    /// Pickling: the bytes of `to_bytes`, read back by `from_bytes`.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let f = py.get_type::<PyE3dLearner>().getattr("from_bytes")?;
        Ok((f, (self.to_bytes(py),)))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyE3dLearner>()
            .map(|o| o.borrow().inner.to_bytes() == self.inner.to_bytes())
            .unwrap_or(false)
    }

    fn __repr__(&self) -> String {
        format!(
            "E3dLearner({} slots of sizes {:?}, {} effects)",
            self.sizes.len(),
            self.sizes,
            self.num_effects
        )
    }
}
