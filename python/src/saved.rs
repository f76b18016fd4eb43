//! `Learner`: any built-in learner's state, saved and loaded bit for bit
//! (`to_bytes`, `from_bytes`, pickling) through the library's
//! [`LearnerState`], and run by `run_session(learner=...)`, which
//! continues from it.

use crate::contextual::{commands_arg, context_targets, observe_arg};
use crate::errors::checked;
use crate::held::{bad, Held};
use crate::learn_args::{
    bad_command, check_effect, context_arg, effect_reward, free_outcome, symbols_of,
};
use crate::scene::{scene_of, target_arg, PyScene};
use e3d::episode::EpisodeConfig;
use e3d::learner::state::StateShape;
use e3d::learner::{ClosedLoopE3d, ContextTargets, QLearning};
use e3d::{LearnerKind, Params, Target};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use pyo3::types::PyTuple;

/// The native base of `e3d.Learner` (python/e3d/_learner.py, which adds
/// its tables by name, equality and pickling): any built-in learner's state,
/// made, stepped by `propose` / `learn`, saved and loaded bit for bit.
#[pyclass(module = "e3d", name = "_Learner", subclass)]
#[derive(Clone)]
pub(crate) struct PyLearnerState {
    pub(crate) held: Held,
}

impl PyLearnerState {
    /// Checks that `scene` fits this learner (its slots and effects, and
    /// with `contexts` its contexts).
    pub(crate) fn check_fits(&self, scene: &PyScene, contexts: Option<usize>) -> PyResult<()> {
        let shape = self.held.state().shape();
        let sizes: Vec<usize> = match &scene.values {
            Some(v) => vec![0; v.num_slots()],
            None => scene.space.sizes().collect(),
        };
        shape
            .fits(&sizes, scene.inner.num_effects(), contexts)
            .map_err(|e| {
                PyValueError::new_err(format!("learner: scene `{}`: {e}", scene.inner.spec().name))
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
        eta = 0.01, epsilon = 0.1, target = None, k = 2, sigma = 0.1, rarity = 0.5,
        goal_progress = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        scene: &Bound<'_, PyAny>,
        learner: &str,
        #[pyo3(from_py_with = crate::errors::float_arg)] alpha: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] beta: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] lambda_: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] eta: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] epsilon: f64,
        target: Option<&Bound<'_, PyAny>>,
        #[pyo3(from_py_with = crate::errors::k_arg)] k: usize,
        #[pyo3(from_py_with = crate::errors::float_arg)] sigma: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] rarity: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] goal_progress: f64,
    ) -> PyResult<PyLearnerState> {
        if let Ok(data) = scene.cast::<PyBytes>() {
            // a learner's bytes: how a subclass's instance is unpickled
            // (`copyreg.__newobj__(cls, data)`, see `__reduce__`)
            let held = Held::from_bytes(data.as_bytes()).map_err(bad)?;
            return Ok(PyLearnerState { held });
        }
        let scene = scene_of(scene)?;
        let kind = kind_arg(learner)?;
        let target = target_arg(&scene, target)?;
        let params = checked(Params {
            alpha,
            beta,
            lambda: lambda_,
            eta,
            epsilon,
            k,
            sigma,
            rarity,
            goal_progress,
            initial: Params::TASK1.initial,
        })?;
        let held = Held::new(&scene, kind, &params, &target)?;
        crate::errors::warn_unread(py, crate::errors::Reader::Kind(kind), &params, 1)?;
        Ok(PyLearnerState { held })
    }

    /// A contextual built-in learner for sessions of episodes on `scene`
    /// (`run_episodes(scene, learner=l, ...)` runs from its state and
    /// leaves it in the state they end in): one `learner` per context
    /// (`"e3d"`, `"e3d_relax"`, `"count"`, `"smm"`, `"egreedy"`,
    /// `"uniform"`), or with `closed_loop` closed-loop E3D (`"e3d"`) or
    /// Q-learning (`"egreedy"`); the contexts are those `run_episodes`
    /// would observe with `commands`, `closed_loop` and `observe`.
    #[staticmethod]
    #[pyo3(signature = (scene, learner = "e3d", commands = None, closed_loop = false,
        observe = None, gamma = 0.9, alpha = 0.3, beta = 1.0, lambda_ = 0.03, eta = 0.01,
        epsilon = 0.1, target = None, targets = None))]
    #[allow(clippy::too_many_arguments)]
    fn contextual<'py>(
        py: Python<'py>,
        scene: &Bound<'_, PyAny>,
        learner: &str,
        commands: Option<&Bound<'_, PyAny>>,
        closed_loop: bool,
        observe: Option<&str>,
        #[pyo3(from_py_with = crate::errors::float_arg)] gamma: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] alpha: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] beta: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] lambda_: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] eta: f64,
        #[pyo3(from_py_with = crate::errors::float_arg)] epsilon: f64,
        target: Option<&Bound<'_, PyAny>>,
        targets: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let scene = scene_of(scene)?;
        let kind = kind_arg(learner)?;
        let params = checked(Params {
            alpha,
            beta,
            lambda: lambda_,
            eta,
            epsilon,
            ..Params::TASK1
        })?;
        scene.require_symbols("Learner.contextual")?;
        let k = commands.map(commands_arg).transpose()?.unwrap_or(1);
        let ctx_targets = context_targets(&scene, target, targets)?;
        let cfg = EpisodeConfig {
            episodes: 1,
            commands: k,
            seed: 0,
            use_reward: true,
            observe: observe_arg(observe, k, closed_loop)?,
        };
        let contexts = cfg.num_contexts(&scene.inner.build());
        let (space, n) = (&scene.space, scene.inner.num_effects());
        e3d::learner::contextual::check_gamma(gamma).map_err(bad)?;
        e3d::learner::contextual::check_context_effects(contexts, n).map_err(bad)?;
        let held = match (closed_loop, kind) {
            (true, LearnerKind::E3d) => Held::ClosedLoop(
                ClosedLoopE3d::new(space, n, contexts, &params, &ctx_targets, gamma).map_err(bad)?,
            ),
            (true, LearnerKind::Egreedy) => {
                Held::QLearning(QLearning::new(space, contexts, &params, gamma).map_err(bad)?)
            }
            (_, LearnerKind::QlearningMoves) => {
                // it runs on the scene's single moves, which this scene's
                // commands are not
                return Err(PyValueError::new_err(
                    "learner `qlearning_moves`: no saved state (run_episodes(scene, learner=\"qlearning_moves\") runs it on the scene's single moves)",
                ));
            }
            (true, other) => {
                return Err(PyValueError::new_err(format!(
                    "learner `{other}`: the closed loop takes e3d (closed-loop E3D) or egreedy (Q-learning)"
                )))
            }
            (
                false,
                LearnerKind::GoalBabbling
                | LearnerKind::Archive
                | LearnerKind::ArchiveReached
                | LearnerKind::MapElites,
            ) => {
                return Err(PyValueError::new_err(format!(
                    "learner `{kind}`: no saved state per context (kept for e3d, e3d_relax, count, smm, egreedy and uniform)"
                )))
            }
            (false, kind) => {
                let per: Vec<Target> = match ctx_targets {
                    ContextTargets::Shared(t) => vec![t; contexts],
                    ContextTargets::PerContext(v) if v.len() == contexts => v,
                    ContextTargets::PerContext(v) => {
                        return Err(PyValueError::new_err(format!(
                            "targets: {} targets for {contexts} contexts: give one per context",
                            v.len()
                        )))
                    }
                };
                let learners = per
                    .iter()
                    .map(|t| Held::new(&scene, kind, &params, t))
                    .collect::<PyResult<Vec<Held>>>()?;
                Held::per_context(learners)
            }
        };
        // once everything is checked: a refused call warns of nothing
        crate::errors::warn_unread(py, crate::errors::Reader::Kind(kind), &params, 1)?;
        crate::errors::warn_open_loop_gamma(py, closed_loop, gamma, 1)?;
        // an e3d.Learner, read from the bytes: the same state bit for bit
        let data = PyBytes::new(py, &held.state().to_bytes());
        py.import("e3d._learner")?
            .getattr("Learner")?
            .call1((data,))
    }

    /// The name a session record gives this learner (`"e3d"`, `"count"`, ...).
    /// A contextual learner's is its run's (`"e3d"`, `"e3d_closed_loop"`,
    /// `"qlearning"`, ...).
    #[getter]
    fn name(&mut self) -> String {
        match self.held.contextual() {
            Some(l) => l.name().to_string(),
            None => self.held.kind().as_str().to_string(),
        }
    }

    /// The kind written in the saved state (`"e3d"`, `"gaussian_e3d"`,
    /// `"uniform_values"`, ...).
    #[getter]
    fn kind(&self) -> &'static str {
        self.held.state().kind()
    }

    /// The whole state as bytes, bit for bit.
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &self.held.state().to_bytes())
    }

    /// The learner's tables, `(name, shape, values, writable)` each, the
    /// values flat (row-major).
    #[allow(clippy::type_complexity)]
    fn _tables<'py>(
        &self,
        py: Python<'py>,
    ) -> Vec<(&'static str, Vec<usize>, Bound<'py, PyArray1<f64>>, bool)> {
        let tables = self.held.state().tables().into_iter();
        tables
            .map(|t| (t.name, t.shape, t.values.into_pyarray(py), t.writable))
            .collect()
    }

    /// Replaces the table `name` by `values` (flat, of its shape):
    /// `ValueError` naming the table if they do not fit its rules.
    fn _set_table(&mut self, name: &str, values: PyReadonlyArray1<'_, f64>) -> PyResult<()> {
        self.held
            .state_mut()
            .set_table(name, values.as_slice()?)
            .map_err(|e| PyValueError::new_err(format!("learner['{name}']: {e}")))
    }

    /// Draws the next command with `rng` (a `SessionRng`): uint8 symbol
    /// indices, or float64 values on a continuous scene; a contextual
    /// learner's `propose(context, rng)`. With `learn`, a loop of one's own
    /// that executes each command in between runs the session
    /// `run_session` (or `run_episodes`) runs (tested bit for bit).
    #[pyo3(signature = (*args))]
    fn propose<'py>(
        &mut self,
        py: Python<'py>,
        args: &Bound<'py, PyTuple>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let shape = self.held.state().shape();
        let (context, rng) = match (shape.contexts, args.len()) {
            (None, 1) => (None, args.get_item(0)?),
            (Some(n), 2) => (
                Some(context_arg(&args.get_item(0)?, n, "context")?),
                args.get_item(1)?,
            ),
            (None, _) => return Err(PyTypeError::new_err("propose(rng): one argument")),
            (Some(_), _) => {
                return Err(PyTypeError::new_err(
                    "propose(context, rng): a contextual learner takes the context first",
                ))
            }
        };
        let rng = rng.cast::<crate::rng::PyRng>()?;
        let mut r = rng.try_borrow_mut()?;
        let rng = r.lent()?;
        let mut c = e3d::Command::new(vec![0; shape.sizes.len()]);
        if let (Some(context), Some(l)) = (context, self.held.contextual()) {
            l.propose(context, rng, &mut c);
            return Ok(c.symbols.into_pyarray(py).into_any());
        }
        if let Some(l) = self.held.symbols() {
            l.propose(rng, &mut c);
            return Ok(c.symbols.into_pyarray(py).into_any());
        }
        let l = self.held.values().expect("a learner of symbols or values");
        let mut v = Vec::with_capacity(shape.sizes.len());
        l.propose(rng, &mut v);
        Ok(v.into_pyarray(py).into_any())
    }

    /// Learns from the outcome of `command` (symbol indices, or values on
    /// a continuous scene, each within its slot's range):
    /// `learn(command, outcome)` (an `Outcome`, as `World.execute`
    /// returns) or `learn(command, effect, reward, point=None)` (`point`:
    /// the terminal point `(x, y)`, which goal babbling learns from and
    /// requires); a contextual learner's
    /// `learn(context, command, effect, reward, next=None)` (`next`: the
    /// context the command led to, None after an episode's last command).
    #[pyo3(signature = (*args, point = None))]
    fn learn(
        &mut self,
        args: &Bound<'_, PyTuple>,
        point: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let shape = self.held.state().shape();
        let Some(n) = shape.contexts else {
            let (command, o, has_point) = free_outcome(args, point, &shape)?;
            if !has_point && self.held.kind() == LearnerKind::GoalBabbling {
                return Err(PyValueError::new_err(
                    "point: a goal_babbling learner learns from the terminal point: learn(command, outcome), or learn(command, effect, reward, point=(x, y))",
                ));
            }
            return self.learn_free(&command, o, &shape);
        };
        let usage = "learn(context, command, effect, reward, next=None): a contextual learner";
        type Arg<'py> = Bound<'py, PyAny>;
        let (context, command, effect, reward, next): (Arg, Arg, Arg, Arg, Option<Arg>) =
            match args.len() {
                4 => {
                    let (c, a, e, r) = args.extract()?;
                    (c, a, e, r, None)
                }
                5 => args.extract()?,
                _ => return Err(PyTypeError::new_err(usage)),
            };
        let (effect, reward) = effect_reward(&effect, &reward)?;
        let context = context_arg(&context, n, "context")?;
        let next = next
            .filter(|x| !x.is_none())
            .map(|x| context_arg(&x, n, "next"))
            .transpose()?;
        let o = check_effect(effect, reward, &shape)?;
        let command = symbols_of(&command, &shape)?;
        let l = self.held.contextual().expect("a contextual learner");
        l.learn(context, &e3d::Command::new(command), &o, next);
        Ok(())
    }

    fn __repr__(&self) -> String {
        let shape = self.held.state().shape();
        format!(
            "Learner({:?}, slots {:?}, effects {})",
            self.kind(),
            shape.sizes,
            shape.effects.map_or("-".to_string(), |e| e.to_string())
        )
    }
}

impl PyLearnerState {
    /// `learn(command, effect, reward)` of a learner without contexts.
    fn learn_free(
        &mut self,
        command: &Bound<'_, PyAny>,
        o: e3d::Outcome,
        shape: &StateShape,
    ) -> PyResult<()> {
        if self.held.symbols().is_some() {
            // `o` is checked (free_outcome)
            let symbols = symbols_of(command, shape)?;
            let l = self.held.symbols().expect("symbols");
            l.learn(&e3d::Command::new(symbols), &o);
            return Ok(());
        }
        let values: Vec<f64> = command.extract().map_err(|_| bad_command(shape))?;
        if values.len() != shape.sizes.len() {
            return Err(bad_command(shape));
        }
        if let Some((slot, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "command: value {v} at slot {slot}: expected finite numbers, one per slot"
            )));
        }
        let l = self.held.values().expect("values");
        if let Some(space) = l.value_space() {
            // values out of their ranges would move the policy where it
            // never proposes (World.execute refuses them alike)
            space
                .check(&values)
                .map_err(|e| PyValueError::new_err(format!("command: {e}")))?;
        }
        l.learn(&values, &o);
        Ok(())
    }
}

/// The built-in learner named `learner`, or a `ValueError` naming the
/// argument and the learners there are.
fn kind_arg(learner: &str) -> PyResult<LearnerKind> {
    learner
        .parse()
        .map_err(|e: e3d::learner::ParseLearnerError| {
            PyValueError::new_err(format!("learner: {e}"))
        })
}

/// Whose hyper-parameters a call's `alpha` ... `epsilon` would be, from
/// its `learner` argument (None: `"e3d"`; see [`crate::errors::warn_unread`]).
pub(crate) fn reader_of(learner: Option<&Bound<'_, PyAny>>) -> PyResult<crate::errors::Reader> {
    use crate::errors::Reader;
    if learner.is_some_and(|l| l.cast::<PyLearnerState>().is_ok()) {
        return Ok(Reader::State);
    }
    Ok(match crate::learner::builtin_kind(learner)? {
        Some(kind) => Reader::Kind(kind),
        None => Reader::Object,
    })
}
