//! Learners: built-in ones by name, Python objects driven as
//! [`e3d::Learner`]s, and the world guard that stops their sessions.

use crate::commands::commands_from;
use crate::errors::{learner_names, STOPPED};
use crate::rng::PyRng;
use e3d::{
    Command, CommandSpace, ContinuousWorld, Learner, LearnerKind, Outcome, SessionRng, ValueSpace,
    World, WorldError,
};
use numpy::PyArray1;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyString;
use std::cell::RefCell;

/// A learner written in Python: an object with `propose(rng)` and
/// `learn(command, effect, reward)`. Its first exception stops the session
/// and is raised by `run_session`.
pub(crate) struct PyLearner<'py, 'a> {
    py: Python<'py>,
    obj: Bound<'py, PyAny>,
    rng: Bound<'py, PyRng>,
    space: CommandSpace,
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
        Ok(PyLearner {
            py,
            obj,
            rng,
            space: space.clone(),
            error,
        })
    }
}

impl Learner for PyLearner<'_, '_> {
    fn name(&self) -> &str {
        "python"
    }

    fn propose(&mut self, rng: &mut SessionRng, command: &mut Command) {
        if self.error.borrow().is_some() {
            return;
        }
        if let Err(e) = PyRng::swap(&self.rng, rng, true) {
            *self.error.borrow_mut() = Some(e);
            return;
        }
        let r = self.obj.call_method1("propose", (self.rng.clone(),));
        // the session's generator back, even if another thread holds the
        // object now (then the session stops with that error)
        let back = PyRng::swap(&self.rng, rng, false);
        let r = back
            .and(r)
            .and_then(|v| commands_from(self.py, &self.space, &v, 1));
        match r {
            Ok(mut cs) => *command = cs.remove(0),
            Err(e) => *self.error.borrow_mut() = Some(e),
        }
    }

    fn learn(&mut self, command: &Command, outcome: &Outcome) {
        if self.error.borrow().is_some() {
            return;
        }
        let symbols = PyArray1::from_slice(self.py, &command.symbols);
        if let Err(e) = self
            .obj
            .call_method1("learn", (symbols, outcome.effect, outcome.reward))
        {
            *self.error.borrow_mut() = Some(e);
        }
    }
}

/// A world that refuses to execute once `stop()` says so (the Python
/// learner raised, or the caller asked to stop: Ctrl-C or an exception
/// from a progress callback), so that the session loop ends there. It
/// passes everything else through, batches included (sessions in lockstep
/// keep their multi-copy stepping).
pub(crate) struct Guarded<'a, W: ?Sized, S: Fn() -> bool> {
    pub(crate) world: &'a mut W,
    pub(crate) stop: S,
}

impl<W: World + ?Sized, S: Fn() -> bool> World for Guarded<'_, W, S> {
    fn command_space(&self) -> &CommandSpace {
        self.world.command_space()
    }
    fn num_effects(&self) -> usize {
        self.world.num_effects()
    }
    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        if (self.stop)() {
            return Err(WorldError::Other(STOPPED.into()));
        }
        self.world.execute(command)
    }
    fn is_deterministic(&self) -> bool {
        self.world.is_deterministic()
    }
    fn execute_batch(&mut self, commands: &[Command], out: &mut Vec<Result<Outcome, WorldError>>) {
        if (self.stop)() {
            out.extend(
                commands
                    .iter()
                    .map(|_| Err(WorldError::Other(STOPPED.into()))),
            );
        } else {
            self.world.execute_batch(commands, out)
        }
    }
    fn mirror_of(&self, command: &Command) -> Option<Command> {
        self.world.mirror_of(command)
    }
    fn mirror_outcome(&self, outcome: Outcome) -> Outcome {
        self.world.mirror_outcome(outcome)
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

impl<W: ContinuousWorld + ?Sized, S: Fn() -> bool> ContinuousWorld for Guarded<'_, W, S> {
    fn value_space(&self) -> &ValueSpace {
        self.world.value_space()
    }
    fn num_effects(&self) -> usize {
        self.world.num_effects()
    }
    fn execute_values(&mut self, values: &[f64]) -> Result<Outcome, WorldError> {
        if (self.stop)() {
            return Err(WorldError::Other(STOPPED.into()));
        }
        self.world.execute_values(values)
    }
}
