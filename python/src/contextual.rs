//! The arguments of episodes and contexts (`commands`, `observe`,
//! `targets`) that `run_episodes`, `EpisodeWorld` and `Learner.contextual`
//! take.

use crate::errors::usize_arg;
use crate::scene::{target_arg, PyScene};
use e3d::episode::Observe;
use e3d::learner::ContextTargets;
use e3d::Target;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// The commands of an episode: 1 to 64, the command line's range.
pub(crate) fn commands_arg(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    let k = usize_arg(obj, "commands", 1)?;
    if k > 64 {
        return Err(PyValueError::new_err(format!(
            "commands = {k}: expected at most 64 (the command line's cap)"
        )));
    }
    Ok(k)
}

/// `observe`: None (the command line's default for `commands` and
/// `closed_loop`), `"start"`, `"state"` or `"blind"`.
pub(crate) fn observe_arg(
    observe: Option<&str>,
    commands: usize,
    closed_loop: bool,
) -> PyResult<Observe> {
    match observe {
        None => Ok(Observe::default_for(commands, closed_loop)),
        Some("start") => Ok(Observe::StartContext),
        Some("state") => Ok(Observe::State),
        Some("blind") => Ok(Observe::Blind),
        Some(o) => Err(PyValueError::new_err(format!(
            "observe = `{o}`: expected None, \"start\", \"state\" or \"blind\""
        ))),
    }
}

pub(crate) fn observe_name(o: Observe) -> &'static str {
    match o {
        Observe::StartContext => "start",
        Observe::State => "state",
        Observe::Blind => "blind",
    }
}

/// The targets of `run_episodes`: `targets`, one per context, else
/// `target` (None: uniform) for every context.
pub(crate) fn context_targets(
    scene: &PyScene,
    target: Option<&Bound<'_, PyAny>>,
    targets: Option<&Bound<'_, PyAny>>,
) -> PyResult<ContextTargets> {
    let Some(ts) = targets.filter(|t| !t.is_none()) else {
        return Ok(ContextTargets::Shared(target_arg(scene, target)?));
    };
    if target.is_some_and(|t| !t.is_none()) {
        return Err(PyValueError::new_err(
            "targets: give either target (every context) or targets (one per context)",
        ));
    }
    let list = ts
        .try_iter()
        .map_err(|_| {
            PyTypeError::new_err("targets: expected a sequence of targets, one per context")
        })?
        .map(|t| target_arg(scene, Some(&t?)))
        .collect::<PyResult<Vec<Target>>>()?;
    Ok(ContextTargets::PerContext(list))
}
