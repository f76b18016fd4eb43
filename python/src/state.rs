//! `_E3dLearner`: what `e3d.E3dLearner` (python/e3d/_learner.py, which
//! reads it through `Learner`'s tables) needs of E3D itself: made from a
//! scene or from bytes, its `beta`, and Q, the policy and the effect model
//! written per slot.

use crate::errors::usize_arg;
use crate::held::{bad, Held};
use crate::saved::PyLearnerState;
use crate::scene::{scene_of, target_arg};
use e3d::learner::{E3d, LearnerState};
use e3d::Params;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// The native base of `E3dLearner`: a `Learner` that holds E3D (the
/// paper's Algorithm 1) on a scene of symbols.
#[pyclass(module = "e3d", name = "_E3dLearner", extends = PyLearnerState, subclass)]
pub(crate) struct PyE3dLearner;

/// The E3D learner of `slf`, to write.
fn e3d_mut<'a>(slf: &'a mut PyRefMut<'_, PyE3dLearner>) -> &'a mut E3d {
    slf.as_super().held.e3d().expect("an E3dLearner holds E3D")
}

#[pymethods]
impl PyE3dLearner {
    /// A fresh learner (Q = 0, p uniform) for `scene` (a `Scene`, a path or
    /// a built-in name) with E3D's hyper-parameters and target `p*` (as
    /// `run_session` takes them); or the learner of the bytes of
    /// `to_bytes` (`ValueError` if they are not an E3D learner's).
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
        let l = if let Ok(data) = scene.cast::<PyBytes>() {
            E3d::from_bytes(data.as_bytes()).map_err(bad)?
        } else {
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
            E3d::new(&scene.space, scene.inner.num_effects(), &params, &target).map_err(bad)?
        };
        let held = Held::E3d(l);
        Ok(PyClassInitializer::from(PyLearnerState { held }).add_subclass(PyE3dLearner))
    }

    /// The inverse temperature `beta`.
    #[getter]
    fn beta(slf: PyRef<'_, Self>) -> f64 {
        match &slf.as_super().held {
            Held::E3d(l) => l.beta(),
            _ => unreachable!("an E3dLearner holds E3D"),
        }
    }

    /// Replaces `Q[:, slot]` (one finite value per symbol of the slot).
    fn set_q(mut slf: PyRefMut<'_, Self>, slot: &Bound<'_, PyAny>, q: Vec<f64>) -> PyResult<()> {
        let slot = usize_arg(slot, "slot", 0)?;
        e3d_mut(&mut slf).set_q(slot, &q).map_err(bad)
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
        let beta = l.beta();
        let q: Vec<f64> = probs.iter().map(|p| p.ln() / beta).collect();
        l.set_q(slot, &q).map_err(bad)
    }

    /// Replaces the effect model `p` by `effect_model`, `num_effects`
    /// probabilities (`E3dLearner.effect_model = ...`).
    fn _set_effect_model(mut slf: PyRefMut<'_, Self>, effect_model: Vec<f64>) -> PyResult<()> {
        let l = e3d_mut(&mut slf);
        let n = l.effect_model().num_effects();
        if effect_model.len() != n {
            return Err(PyValueError::new_err(format!(
                "effect_model: {} probabilities given, the learner has {n} effects",
                effect_model.len()
            )));
        }
        l.set_effect_model(&effect_model).map_err(bad)
    }
}
