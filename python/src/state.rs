//! `E3dLearner`: an `e3d.Learner` of kind `"e3d"` with E3D's own words
//! for its state: Q and the policy per slot, the effect model. Saving,
//! loading, pickling, `propose` / `learn`, the tables by name and
//! `run_session(learner=...)` are `Learner`'s.

use crate::errors::usize_arg;
use crate::held::{bad, Held};
use crate::saved::PyLearnerState;
use crate::scene::{scene_of, target_arg};
use e3d::learner::{E3d, LearnerState};
use e3d::Params;
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An E3D learner (the paper's Algorithm 1) for a scene of symbols: an
/// `e3d.Learner` whose Q table, policy and effect model also read and
/// write per slot.
#[pyclass(module = "e3d", name = "E3dLearner", extends = PyLearnerState)]
pub(crate) struct PyE3dLearner;

/// The E3D learner of `slf`.
fn e3d_of<'a>(slf: &'a PyRef<'_, PyE3dLearner>) -> &'a E3d {
    match &slf.as_super().held {
        Held::E3d(l) => l,
        _ => unreachable!("an E3dLearner holds E3D"),
    }
}

/// The E3D learner of `slf`, to write.
fn e3d_mut<'a>(slf: &'a mut PyRefMut<'_, PyE3dLearner>) -> &'a mut E3d {
    slf.as_super().held.e3d().expect("an E3dLearner holds E3D")
}

fn with(inner: E3d) -> PyClassInitializer<PyE3dLearner> {
    PyClassInitializer::from(PyLearnerState {
        held: Held::E3d(inner),
    })
    .add_subclass(PyE3dLearner)
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
        #[pyo3(from_py_with = crate::errors::float_arg)] alpha: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] beta: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] lambda_: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] eta: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyClassInitializer<PyE3dLearner>> {
        let scene = scene_of(scene)?;
        scene.require_symbols("E3dLearner")?;
        let target = target_arg(&scene, target)?;
        let params = crate::errors::checked(Params {
            alpha,
            beta,
            lambda: lambda_,
            eta,
            ..Params::TASK1
        })?;
        let l = E3d::new(&scene.space, scene.inner.num_effects(), &params, &target).map_err(bad)?;
        Ok(with(l))
    }

    /// A learner from the bytes of `to_bytes` (`ValueError` if they are
    /// not an E3D learner's).
    #[staticmethod]
    fn from_bytes(py: Python<'_>, data: &[u8]) -> PyResult<Py<PyE3dLearner>> {
        let l = E3d::from_bytes(data).map_err(bad)?;
        Py::new(py, with(l))
    }

    /// The alphabet size of each slot.
    #[getter]
    fn alphabet_sizes(slf: PyRef<'_, Self>) -> Vec<usize> {
        let l = e3d_of(&slf);
        (0..l.num_slots()).map(|s| l.q(s).len()).collect()
    }

    /// The number of effects.
    #[getter]
    fn num_effects(slf: PyRef<'_, Self>) -> usize {
        e3d_of(&slf).effect_model().num_effects()
    }

    /// `Q`, one float64 array per slot (copies: write with `set_q` or by
    /// assigning the whole list).
    #[getter]
    fn q<'py>(slf: PyRef<'py, Self>) -> Vec<Bound<'py, PyArray1<f64>>> {
        let l = e3d_of(&slf);
        let py = slf.py();
        (0..l.num_slots())
            .map(|s| l.q(s).to_vec().into_pyarray(py))
            .collect()
    }

    #[setter(q)]
    fn set_q_all(mut slf: PyRefMut<'_, Self>, q: Vec<Vec<f64>>) -> PyResult<()> {
        let l = e3d_mut(&mut slf);
        if q.len() != l.num_slots() {
            return Err(PyValueError::new_err(format!(
                "q: {} slots given, the learner has {}",
                q.len(),
                l.num_slots()
            )));
        }
        let mut next = l.clone();
        for (s, v) in q.iter().enumerate() {
            next.set_q(s, v).map_err(bad)?;
        }
        *l = next;
        Ok(())
    }

    /// Replaces `Q[:, slot]` (one finite value per symbol of the slot).
    fn set_q(mut slf: PyRefMut<'_, Self>, slot: &Bound<'_, PyAny>, q: Vec<f64>) -> PyResult<()> {
        let slot = usize_arg(slot, "slot", 0)?;
        e3d_mut(&mut slf).set_q(slot, &q).map_err(bad)
    }

    /// The policy, one array per slot: `softmax(beta Q[:, slot])`.
    #[getter]
    fn policy<'py>(slf: PyRef<'py, Self>) -> Vec<Bound<'py, PyArray1<f64>>> {
        let l = e3d_of(&slf);
        let py = slf.py();
        (0..l.num_slots())
            .map(|s| l.policy(s).into_pyarray(py))
            .collect()
    }

    /// Sets slot `slot`'s policy to `probs` (each > 0, summing to 1): Q of
    /// the slot becomes `log(probs) / beta` (softmax is unchanged
    /// by a constant added to a slot's Q).
    fn set_policy(
        mut slf: PyRefMut<'_, Self>,
        slot: &Bound<'_, PyAny>,
        probs: Vec<f64>,
    ) -> PyResult<()> {
        let slot = usize_arg(slot, "slot", 0)?;
        let l = e3d_mut(&mut slf);
        if slot >= l.num_slots() {
            // set_q words it
            return l.set_q(slot, &probs).map_err(bad);
        }
        let k = l.q(slot).len();
        if probs.len() != k {
            return Err(PyValueError::new_err(format!(
                "policy of slot {slot}: {} probabilities given, the slot has {k} symbols",
                probs.len()
            )));
        }
        let total: f64 = probs.iter().sum();
        if probs.iter().any(|p| !(p.is_finite() && *p > 0.0)) || (total - 1.0).abs() > 1e-9 {
            return Err(PyValueError::new_err(format!(
                "policy of slot {slot}: expected probabilities > 0 summing to 1, found {probs:?}"
            )));
        }
        let l = e3d_mut(&mut slf);
        let beta = l.beta();
        let q: Vec<f64> = probs.iter().map(|p| p.ln() / beta).collect();
        l.set_q(slot, &q).map_err(bad)
    }

    /// The inverse temperature `beta`.
    #[getter]
    fn beta(slf: PyRef<'_, Self>) -> f64 {
        e3d_of(&slf).beta()
    }

    /// The effect model `p`, the running histogram of effects (a copy;
    /// assign an array of `num_effects` probabilities to replace it).
    #[getter]
    fn effect_model<'py>(slf: PyRef<'py, Self>) -> Bound<'py, PyArray1<f64>> {
        e3d_of(&slf).effect_model().probs().into_pyarray(slf.py())
    }

    #[setter]
    fn set_effect_model(mut slf: PyRefMut<'_, Self>, effect_model: Vec<f64>) -> PyResult<()> {
        let probs = effect_model;
        let l = e3d_mut(&mut slf);
        let n = l.effect_model().num_effects();
        if probs.len() != n {
            return Err(PyValueError::new_err(format!(
                "effect_model: {} probabilities given, the learner has {n} effects",
                probs.len()
            )));
        }
        l.set_effect_model(&probs).map_err(bad)
    }

    fn __repr__(slf: PyRef<'_, Self>) -> String {
        let l = e3d_of(&slf);
        let sizes: Vec<usize> = (0..l.num_slots()).map(|s| l.q(s).len()).collect();
        format!(
            "E3dLearner({} slots of sizes {:?}, {} effects)",
            sizes.len(),
            sizes,
            l.effect_model().num_effects()
        )
    }
}
