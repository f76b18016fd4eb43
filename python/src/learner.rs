//! Learners: built-in ones by name, Python objects driven as
//! [`e3d::Learner`]s, and the world guard that stops their sessions.

use crate::commands::commands_from;
use crate::errors::learner_names;
use crate::rng::PyRng;
use e3d::command::CommandSpace;
use e3d::learner::ContextualLearner;
use e3d::{Command, Learner, LearnerKind, Outcome, SessionRng};
use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{IntoPyDict, PyString};
use std::cell::RefCell;

/// A learner written in Python: an object with `propose(rng)` and
/// `learn(command, effect, reward)` (with `point=(x, y)` when its `learn`
/// takes it). Its first exception stops the session and is raised by
/// `run_session`.
pub(crate) struct PyLearner<'py, 'a> {
    py: Python<'py>,
    obj: Bound<'py, PyAny>,
    rng: Bound<'py, PyRng>,
    space: CommandSpace,
    /// `learn` takes `point=` (`e3d._args.learn_takes_point`).
    point: bool,
    error: &'a RefCell<Option<PyErr>>,
}

impl<'py, 'a> PyLearner<'py, 'a> {
    pub(crate) fn new(
        py: Python<'py>,
        obj: Bound<'py, PyAny>,
        space: &CommandSpace,
        error: &'a RefCell<Option<PyErr>>,
    ) -> PyResult<Self> {
        let rng = Bound::new(py, PyRng::idle())?;
        let point = py
            .import("e3d._args")?
            .call_method1("learn_takes_point", (&obj,))?
            .is_truthy()?;
        Ok(PyLearner {
            py,
            obj,
            rng,
            space: space.clone(),
            point,
            error,
        })
    }
}

impl<'py> PyLearner<'py, '_> {
    /// Calls `propose(*context, rng)` with the session's generator lent,
    /// and reads the command it returns (the first error stops the session).
    fn propose_in(&mut self, context: Option<usize>, rng: &mut SessionRng, command: &mut Command) {
        if self.error.borrow().is_some() {
            return;
        }
        if let Err(e) = PyRng::swap(&self.rng, rng, true) {
            *self.error.borrow_mut() = Some(e);
            return;
        }
        let r = match context {
            None => self.obj.call_method1("propose", (self.rng.clone(),)),
            Some(c) => self.obj.call_method1("propose", (c, self.rng.clone())),
        };
        // the session's generator back, even if another thread holds the
        // object now (then the session stops with that error)
        let back = PyRng::swap(&self.rng, rng, false);
        let r = back.and(r).and_then(|v| {
            commands_from(self.py, &self.space, &v, 1).map_err(|e| self.returned(context, e))
        });
        match r {
            Ok(mut cs) => *command = cs.remove(0),
            Err(e) => *self.error.borrow_mut() = Some(e),
        }
    }

    /// `e`, what is wrong with the command `propose` returned, named as
    /// the user's own method (`Uniform.propose(rng) returned ...`).
    fn returned(&self, context: Option<usize>, e: PyErr) -> PyErr {
        let args = if context.is_some() {
            "context, rng"
        } else {
            "rng"
        };
        let class = crate::errors::type_name(&self.obj);
        let msg = format!(
            "{class}.propose({args}) returned a bad command: {}",
            e.value(self.py)
        );
        PyErr::from_type(e.get_type(self.py), msg)
    }

    /// Calls `learn(command, effect, reward)`, or with a context
    /// `learn(context, command, effect, reward, next)`; `point=(x, y)` too
    /// when `learn` takes it.
    fn learn_in(
        &mut self,
        context: Option<(usize, Option<usize>)>,
        command: &Command,
        outcome: &Outcome,
    ) {
        if self.error.borrow().is_some() {
            return;
        }
        let symbols = PyArray1::from_slice(self.py, &command.symbols);
        let (e, r) = (outcome.effect, outcome.reward);
        let point = [("point", (outcome.point[0], outcome.point[1]))];
        let kwargs = self.point.then(|| point.into_py_dict(self.py)).transpose();
        let done = kwargs.and_then(|kwargs| match context {
            None => self
                .obj
                .call_method("learn", (symbols, e, r), kwargs.as_ref()),
            Some((c, next)) => {
                let args = (c, symbols, e, r, next);
                self.obj.call_method("learn", args, kwargs.as_ref())
            }
        });
        if let Err(e) = done {
            *self.error.borrow_mut() = Some(e);
        }
    }
}

impl Learner for PyLearner<'_, '_> {
    fn name(&self) -> &str {
        "python"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        self.propose_in(None, rng, command)
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        self.learn_in(None, command, outcome)
    }
}

/// A contextual learner written in Python, for `run_episodes`: an object
/// with `propose(context, rng)` and `learn(context, command, effect,
/// reward, next)` (`next`: the context the command led to, None at the
/// episode's end), over `.1` contexts.
pub(crate) struct PyContextual<'py, 'a>(pub(crate) PyLearner<'py, 'a>, pub(crate) usize);

impl ContextualLearner for PyContextual<'_, '_> {
    fn name(&self) -> &str {
        "python"
    }
    fn num_contexts(&self) -> usize {
        self.1
    }
    fn propose(&mut self, context: usize, rng: &mut SessionRng, command: &mut Command) {
        self.0.propose_in(Some(context), rng, command)
    }
    fn learn(&mut self, context: usize, command: &Command, outcome: &Outcome, next: Option<usize>) {
        self.0.learn_in(Some((context, next)), command, outcome)
    }
}

/// A built-in learner's kind from `learner` (None: e3d), or `None` for a
/// Python object.
pub(crate) fn builtin_kind(learner: Option<&Bound<'_, PyAny>>) -> PyResult<Option<LearnerKind>> {
    Ok(match learner {
        None => Some(LearnerKind::E3d),
        Some(l) if l.is_instance_of::<PyString>() => Some(
            l.extract::<String>()?
                .parse::<LearnerKind>()
                .map_err(|e| PyValueError::new_err(e.to_string()))?,
        ),
        Some(_) => None,
    })
}

/// Checks that `obj` is a Python learner; its name (`obj.name`, else
/// "python").
pub(crate) fn python_learner_name(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    for m in ["propose", "learn"] {
        if !obj.hasattr(m)? {
            return Err(PyTypeError::new_err(format!(
                "learner: expected one of {} or an object with propose(rng) and learn(command, effect, reward); this one has no `{m}`",
                learner_names()
            )));
        }
    }
    Ok(obj
        .getattr("name")
        .and_then(|n| n.extract())
        .unwrap_or_else(|_| "python".to_string()))
}

/// The Python learners of a call with `n` seeds: `learner`, a sequence
/// of `n` of them, one per seed (`expected` says what else it may be).
pub(crate) fn learner_list<'py>(
    learner: &Bound<'py, PyAny>,
    n: usize,
    expected: &str,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let objs: Vec<Bound<'py, PyAny>> = learner
        .try_iter()
        .and_then(|it| it.collect::<PyResult<Vec<_>>>())
        .map_err(|_| {
            PyTypeError::new_err(format!(
                "learner: {expected} or a sequence of Python learners, one per seed ({n} seeds)"
            ))
        })?;
    if objs.len() != n {
        return Err(PyValueError::new_err(format!(
            "learner: {} Python learners for {n} seeds: expected one learner per seed",
            objs.len()
        )));
    }
    Ok(objs)
}

/// A learner whose trials are also handed to a Python callable,
/// `on_trials(first, commands, effects, rewards)`, `every` trials at a
/// time and at the session's last (arrays: one call per batch, not per
/// trial). Its first exception goes to `error`, which stops the session.
pub(crate) struct Tap<'py, 'a, L: ?Sized> {
    py: Python<'py>,
    inner: &'a mut L,
    callback: Bound<'py, PyAny>,
    every: usize,
    slots: usize,
    trials: usize,
    first: usize,
    symbols: Vec<u8>,
    effects: Vec<usize>,
    rewards: Vec<f64>,
    error: &'a RefCell<Option<PyErr>>,
}

impl<'py, 'a, L: Learner + ?Sized> Tap<'py, 'a, L> {
    /// `inner` tapped for a session of `trials` trials of `slots` slots.
    pub(crate) fn new(
        inner: &'a mut L,
        callback: &Bound<'py, PyAny>,
        every: usize,
        (slots, trials): (usize, usize),
        error: &'a RefCell<Option<PyErr>>,
    ) -> Self {
        let cap = every.min(1 << 20);
        Tap {
            py: callback.py(),
            inner,
            callback: callback.clone(),
            every,
            slots,
            trials,
            first: 0,
            symbols: Vec::with_capacity(cap * slots),
            effects: Vec::with_capacity(cap),
            rewards: Vec::with_capacity(cap),
            error,
        }
    }

    /// Hands the trials kept so far to the callable.
    fn flush(&mut self) {
        let n = self.effects.len();
        if self.error.borrow().is_some() {
            return;
        }
        let commands = numpy::ndarray::Array2::from_shape_vec(
            (n, self.slots),
            std::mem::take(&mut self.symbols),
        )
        .expect("n x slots");
        let effects = PyArray1::from_iter(self.py, self.effects.drain(..).map(|e| e as i64));
        let rewards = PyArray1::from_slice(self.py, &self.rewards);
        self.rewards.clear();
        let r = self.callback.call1((
            self.first,
            numpy::IntoPyArray::into_pyarray(commands, self.py),
            effects,
            rewards,
        ));
        self.first += n;
        if let Err(e) = r {
            *self.error.borrow_mut() = Some(e);
        }
    }
}

impl<L: Learner + ?Sized> Learner for Tap<'_, '_, L> {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        self.inner.propose(rng, command)
    }
    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        self.inner.learn(command, outcome);
        self.symbols.extend_from_slice(&command.symbols);
        self.effects.push(outcome.effect);
        self.rewards.push(outcome.reward);
        if self.effects.len() >= self.every || self.first + self.effects.len() == self.trials {
            self.flush();
        }
    }
    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        self.inner.slot_policy(slot)
    }
}
