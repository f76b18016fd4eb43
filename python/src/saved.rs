//! `Learner`: any built-in learner's state, saved and loaded bit for bit
//! (`to_bytes`, `from_bytes`, pickling) through the library's
//! [`LearnerState`], and run by `run_session(learner=...)`, which
//! continues from it.

use crate::scene::{scene_of, target_arg, PyScene};
use e3d::learner::state::state_kind;
use e3d::learner::{CountBonus, RelaxedE3d, StateMarginalMatching};
use e3d::{
    ContinuousLearner, E3d, EpsilonGreedy, GaussianE3d, Learner, LearnerError, LearnerKind,
    LearnerState, Params, UniformPolicy, UniformValues,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

/// A built-in learner of either kind of command, as its concrete type.
#[derive(Clone)]
pub(crate) enum Held {
    E3d(E3d),
    Relaxed(RelaxedE3d),
    Count(CountBonus),
    Smm(StateMarginalMatching),
    Egreedy(EpsilonGreedy),
    Uniform(UniformPolicy),
    Gaussian(GaussianE3d),
    UniformValues(UniformValues),
}

/// Applies `$f` to the concrete learner of `$held`.
macro_rules! with_held {
    ($held:expr, $l:ident => $f:expr) => {
        match $held {
            Held::E3d($l) => $f,
            Held::Relaxed($l) => $f,
            Held::Count($l) => $f,
            Held::Smm($l) => $f,
            Held::Egreedy($l) => $f,
            Held::Uniform($l) => $f,
            Held::Gaussian($l) => $f,
            Held::UniformValues($l) => $f,
        }
    };
}

fn bad(e: LearnerError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

impl Held {
    /// A fresh learner of `kind` for `scene`.
    fn new(
        scene: &PyScene,
        kind: LearnerKind,
        params: &Params,
        target: &e3d::Target,
    ) -> PyResult<Held> {
        params.validate().map_err(|e| bad(e.into()))?;
        let n = scene.inner.num_effects();
        if let Some(values) = &scene.values {
            return match kind {
                LearnerKind::E3d => GaussianE3d::new(values, n, params, target).map(Held::Gaussian),
                LearnerKind::Uniform => Ok(Held::UniformValues(UniformValues::new(values))),
                other => Err(LearnerError::State(format!(
                    "learner `{other}`: a saved state of continuous commands is kept for \"e3d\" and \"uniform\""
                ))),
            }
            .map_err(bad);
        }
        let s = &scene.space;
        Ok(match kind {
            LearnerKind::E3d => Held::E3d(E3d::new(s, n, params, target).map_err(bad)?),
            LearnerKind::E3dRelax => Held::Relaxed(RelaxedE3d::new(s, n, params, target).map_err(bad)?),
            LearnerKind::Count => Held::Count(CountBonus::new(s, n, params)),
            LearnerKind::Smm => Held::Smm(StateMarginalMatching::new(s, n, params, target).map_err(bad)?),
            LearnerKind::Egreedy => Held::Egreedy(EpsilonGreedy::new(s, params)),
            LearnerKind::Uniform => Held::Uniform(UniformPolicy::new(s)),
            other => {
                return Err(PyValueError::new_err(format!(
                    "learner `{other}`: no saved state (kept for e3d, e3d_relax, count, smm, egreedy and uniform)"
                )))
            }
        })
    }

    /// The learner from the bytes of [`LearnerState::to_bytes`], whatever
    /// its kind.
    fn from_bytes(data: &[u8]) -> Result<Held, LearnerError> {
        let kind = state_kind(data)?;
        Ok(match kind.as_str() {
            "e3d" => Held::E3d(E3d::from_bytes(data)?),
            "e3d_relax" => Held::Relaxed(RelaxedE3d::from_bytes(data)?),
            "count" => Held::Count(CountBonus::from_bytes(data)?),
            "smm" => Held::Smm(StateMarginalMatching::from_bytes(data)?),
            "egreedy" => Held::Egreedy(EpsilonGreedy::from_bytes(data)?),
            "uniform" => Held::Uniform(UniformPolicy::from_bytes(data)?),
            "gaussian_e3d" => Held::Gaussian(GaussianE3d::from_bytes(data)?),
            "uniform_values" => Held::UniformValues(UniformValues::from_bytes(data)?),
            _ => {
                return Err(LearnerError::State(format!(
                    "the state of a `{kind}` learner, which e3d.Learner does not hold"
                )))
            }
        })
    }

    pub(crate) fn to_bytes(&self) -> Vec<u8> {
        with_held!(self, l => l.to_bytes())
    }

    /// The learner as a learner of symbols, if it is one.
    pub(crate) fn symbols(&mut self) -> Option<&mut (dyn Learner + Send)> {
        Some(match self {
            Held::E3d(l) => l,
            Held::Relaxed(l) => l,
            Held::Count(l) => l,
            Held::Smm(l) => l,
            Held::Egreedy(l) => l,
            Held::Uniform(l) => l,
            Held::Gaussian(_) | Held::UniformValues(_) => return None,
        })
    }

    /// The learner as a learner of values, if it is one.
    pub(crate) fn values(&mut self) -> Option<&mut (dyn ContinuousLearner + Send)> {
        match self {
            Held::Gaussian(l) => Some(l),
            Held::UniformValues(l) => Some(l),
            _ => None,
        }
    }

    /// The kind a session runs (`LearnerKind`'s name).
    pub(crate) fn kind(&self) -> LearnerKind {
        match self {
            Held::E3d(_) | Held::Gaussian(_) => LearnerKind::E3d,
            Held::Relaxed(_) => LearnerKind::E3dRelax,
            Held::Count(_) => LearnerKind::Count,
            Held::Smm(_) => LearnerKind::Smm,
            Held::Egreedy(_) => LearnerKind::Egreedy,
            Held::Uniform(_) | Held::UniformValues(_) => LearnerKind::Uniform,
        }
    }
}

/// A built-in learner (`"e3d"`, `"e3d_relax"`, `"count"`, `"smm"`,
/// `"egreedy"`, `"uniform"`; on a continuous scene the Gaussian `"e3d"` or
/// `"uniform"` values) as a state: saved as bytes bit for bit (`to_bytes`,
/// `Learner.from_bytes`, pickling) and read back as a learner that goes
/// on exactly as this one would. `run_session(scene, learner=l)` runs a
/// session from `l`'s state and leaves `l` in the state it ends in.
#[pyclass(module = "e3d", name = "Learner")]
#[derive(Clone)]
pub(crate) struct PyLearnerState {
    pub(crate) held: Held,
}

impl PyLearnerState {
    /// Checks that `scene` fits this learner (its slots and effects).
    pub(crate) fn check_fits(&self, scene: &PyScene) -> PyResult<()> {
        let shape = with_held!(&self.held, l => l.shape());
        let sizes: Vec<usize> = match &scene.values {
            Some(v) => vec![0; v.num_slots()],
            None => scene.space.sizes().collect(),
        };
        shape
            .fits(&sizes, scene.inner.num_effects(), None)
            .map_err(|e| {
                PyValueError::new_err(format!("learner: scene `{}`: {e}", scene.inner.name))
            })
    }
}

#[pymethods]
impl PyLearnerState {
    /// A fresh built-in learner `learner` for `scene` (a `Scene`, a path or
    /// a built-in name) with the hyper-parameters and target `p*` that
    /// `run_session` takes.
    #[new]
    #[pyo3(signature = (scene, learner = "e3d", alpha = 0.3, beta = 1.0, lambda_ = 0.03,
        eta = 0.01, epsilon = 0.1, target = None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        scene: &Bound<'_, PyAny>,
        learner: &str,
        alpha: f64,
        beta: f64,
        lambda_: f64,
        eta: f64,
        epsilon: f64,
        target: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyLearnerState> {
        let scene = scene_of(scene)?;
        let kind: LearnerKind = learner
            .parse()
            .map_err(|e: e3d::ParseLearnerError| PyValueError::new_err(format!("learner: {e}")))?;
        let target = target_arg(&scene, target)?;
        let params = Params {
            alpha,
            beta,
            lambda: lambda_,
            eta,
            epsilon,
            ..Params::TASK1
        };
        Ok(PyLearnerState {
            held: Held::new(&scene, kind, &params, &target)?,
        })
    }

    /// The name a session record gives this learner (`"e3d"`, `"count"`, ...).
    #[getter]
    fn name(&self) -> &'static str {
        self.held.kind().as_str()
    }

    /// The kind written in the saved state (`"e3d"`, `"gaussian_e3d"`,
    /// `"uniform_values"`, ...).
    #[getter]
    fn kind(&self) -> &'static str {
        with_held!(&self.held, l => kind_of(l))
    }

    /// The whole state as bytes, bit for bit.
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.held.to_bytes())
    }

    /// A learner from the bytes of `to_bytes` (or of `E3dLearner.to_bytes`),
    /// whatever its kind (`ValueError` saying what is wrong if they are not).
    #[staticmethod]
    fn from_bytes(data: &[u8]) -> PyResult<PyLearnerState> {
        Ok(PyLearnerState {
            held: Held::from_bytes(data).map_err(bad)?,
        })
    }

    /// Pickling: the bytes of `to_bytes`, read back by `from_bytes`.
    fn __reduce__<'py>(
        &self,
        py: Python<'py>,
    ) -> PyResult<(Bound<'py, PyAny>, (Bound<'py, PyBytes>,))> {
        let f = py.get_type::<PyLearnerState>().getattr("from_bytes")?;
        Ok((f, (self.to_bytes(py),)))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyLearnerState>()
            .map(|o| o.borrow().held.to_bytes() == self.held.to_bytes())
            .unwrap_or(false)
    }

    fn __repr__(&self) -> String {
        let shape = with_held!(&self.held, l => l.shape());
        format!(
            "Learner({:?}, slots {:?}, effects {})",
            self.kind(),
            shape.sizes,
            shape.effects.map_or("-".to_string(), |e| e.to_string())
        )
    }
}

/// `L::KIND` of a learner.
fn kind_of<L: LearnerState>(_: &L) -> &'static str {
    L::KIND
}

/// Runs one session of continuous commands from `learner`'s state on a
/// physics world of `scene` (off the GIL, stopped by Ctrl-C or by
/// `progress`), leaving `learner` in the state the session ends in.
pub(crate) fn run_values_from(
    py: Python<'_>,
    scene: &PyScene,
    learner: &mut (dyn ContinuousLearner + Send),
    cfg: &e3d::SessionConfig,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<e3d::ValueSessionRecord> {
    let Some(mut world) = scene.inner.physics_world() else {
        return Err(PyValueError::new_err(format!(
            "scene `{}`: continuous commands need a physics world",
            scene.inner.name
        )));
    };
    let watch = crate::progress::Watch::new();
    let rec = crate::progress::watched(py, progress, cfg.trials as u64, &watch, |watch| {
        let mut guarded = crate::learner::Guarded {
            world: &mut world,
            stop: || watch.cancelled(),
        };
        e3d::run_value_session(&mut guarded, learner, cfg, |t| watch.set(t as u64))
    })?;
    rec.map_err(|e| crate::errors::Fail::from(e).into())
}
