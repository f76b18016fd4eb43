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
use e3d::learner::state::tables::StateTable;
use e3d::learner::state::StateShape;
use e3d::learner::{ClosedLoopE3d, ContextTargets, QLearning};
use e3d::{LearnerKind, Params, Target};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyKeyError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;
use pyo3::types::PyTuple;

/// A built-in learner (`"e3d"`, `"e3d_relax"`, `"count"`, `"smm"`,
/// `"egreedy"`, `"uniform"`, `"goal_babbling"`, `"archive"`; on a
/// continuous scene the Gaussian `"e3d"`, `"uniform"`, `"goal_babbling"` or
/// `"archive"` values; with contexts, from `Learner.contextual`) as a
/// state: its tables by name (`l["q"]`, `l["target"] = ...`), stepped by
/// `propose` / `learn`, saved as bytes bit for bit (`to_bytes`,
/// `Learner.from_bytes`, pickling) and read back as a learner that goes
/// on exactly as this one would. `run_session(scene, learner=l)` (with
/// contexts `run_episodes`) runs from `l`'s state and leaves `l` in the
/// state it ends in.
#[pyclass(module = "e3d", name = "Learner", subclass)]
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
            return PyLearnerState::from_bytes(data.as_bytes());
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
    fn contextual(
        py: Python<'_>,
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
    ) -> PyResult<PyLearnerState> {
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
            (true, other) => {
                return Err(PyValueError::new_err(format!(
                    "learner `{other}`: the closed loop takes e3d (closed-loop E3D) or egreedy (Q-learning)"
                )))
            }
            (false, LearnerKind::GoalBabbling | LearnerKind::Archive) => {
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
        Ok(PyLearnerState { held })
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

    /// A learner from the bytes of `to_bytes` (an `E3dLearner`'s too),
    /// whatever its kind (`ValueError` saying what is wrong if they are not).
    #[staticmethod]
    fn from_bytes(data: &[u8]) -> PyResult<PyLearnerState> {
        Ok(PyLearnerState {
            held: Held::from_bytes(data).map_err(bad)?,
        })
    }

    /// Pickling: the bytes of `to_bytes`, read back by `from_bytes`; an
    /// instance of a subclass (`E3dLearner` too) comes back as one of that
    /// class, its `__dict__` with it (`copyreg.__newobj__(cls, data)`, then
    /// the dict).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyTuple>> {
        let py = slf.py();
        let data = slf.borrow().to_bytes(py).into_any();
        let ty = slf.get_type();
        if ty.is(py.get_type::<PyLearnerState>()) {
            let f = ty.getattr("from_bytes")?;
            return PyTuple::new(py, [f, PyTuple::new(py, [data])?.into_any()]);
        }
        let newobj = py.import("copyreg")?.getattr("__newobj__")?;
        let args = PyTuple::new(py, [ty.into_any(), data])?.into_any();
        let dict = slf
            .getattr_opt("__dict__")?
            .unwrap_or_else(|| py.None().into_bound(py));
        PyTuple::new(py, [newobj, args, dict])
    }

    /// Equal: learners whose saved bytes are equal.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyLearnerState>()
            .map(|o| o.borrow().held.state().to_bytes() == self.held.state().to_bytes())
            .unwrap_or(false)
    }

    /// The names of the learner's tables (`"q"`, `"policy"`, `"p"`,
    /// `"target"`, `"counts"`, ... as it has them), in order.
    fn keys(&self) -> Vec<&'static str> {
        self.held.state().tables().iter().map(|t| t.name).collect()
    }

    /// Whether the learner has a table of that name (`"q" in learner`).
    fn __contains__(&self, name: &Bound<'_, PyAny>) -> bool {
        name.extract::<String>()
            .is_ok_and(|n| self.held.state().tables().iter().any(|t| t.name == n))
    }

    /// The names of the tables, as `keys()` (`list(learner)`).
    fn __iter__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        pyo3::types::PyList::new(py, self.keys())?
            .try_iter()
            .map(Bound::into_any)
    }

    /// The names of the tables that `learner[name] = array` can write.
    #[getter]
    fn writable(&self) -> Vec<&'static str> {
        let t = self.held.state().tables();
        t.iter().filter(|t| t.writable).map(|t| t.name).collect()
    }

    /// The table `name` as a float64 array (a copy), e.g. `l["q"]`
    /// `(slots, k)`, `l["p"]` `(effects,)`; `KeyError` naming the tables
    /// there are if it has none of that name.
    fn __getitem__<'py>(
        &self,
        py: Python<'py>,
        name: &str,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let t = self.table(name)?;
        numpy::ndarray::ArrayD::from_shape_vec(t.shape, t.values)
            .map(|a| a.into_pyarray(py))
            .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// Replaces the table `name` by `value` (an array of its shape):
    /// `ValueError` naming the table if the shape, a value or the table's
    /// rules do not fit (the learner is then unchanged).
    fn __setitem__(&mut self, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let t = self.table(name)?;
        let py = value.py();
        let array = py
            .import("numpy")?
            .call_method1("asarray", (value, "float64", "C"))
            .and_then(|a| Ok(a.cast_into::<PyArrayDyn<f64>>()?))
            .map_err(|_| {
                PyValueError::new_err(format!("learner['{name}']: expected an array of numbers"))
            })?;
        if array.shape() != t.shape.as_slice() {
            return Err(PyValueError::new_err(format!(
                "learner['{name}']: expected an array of shape {}, found {}",
                PyTuple::new(py, &t.shape)?.repr()?,
                PyTuple::new(py, array.shape())?.repr()?
            )));
        }
        let values = array.to_vec()?;
        self.held
            .state_mut()
            .set_table(name, &values)
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

    /// The table `name`, or a `KeyError` naming the learner's tables.
    fn table(&self, name: &str) -> PyResult<StateTable> {
        let mut tables = self.held.state().tables();
        match tables.iter().position(|t| t.name == name) {
            Some(i) => Ok(tables.swap_remove(i)),
            None => {
                let names: Vec<String> = tables.iter().map(|t| format!("'{}'", t.name)).collect();
                Err(PyKeyError::new_err(format!(
                    "a `{}` learner has no table '{name}' (its tables: [{}])",
                    self.kind(),
                    names.join(", ")
                )))
            }
        }
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
