//! The arguments of episodes and contexts (`commands`, `observe`,
//! `targets`), and the contextual learners they make
//! (`Learner.contextual`, `run_episodes`).

use crate::errors::usize_arg;
use crate::held::{bad, Held};
use crate::scene::{target_arg, PyScene};
use e3d::episode::{EpisodeConfig, Observe};
use e3d::learner::{ClosedLoopE3d, ContextTargets, QLearning};
use e3d::{LearnerKind, Params, Target};
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

/// A contextual built-in learner, as `run_episodes` would make it for
/// `scene`, `commands` per episode, `closed_loop` and `observe`
/// (`Learner.contextual`).
#[allow(clippy::too_many_arguments)]
pub(crate) fn contextual_held(
    scene: &PyScene,
    kind: LearnerKind,
    commands: Option<&Bound<'_, PyAny>>,
    closed_loop: bool,
    observe: Option<&str>,
    gamma: f64,
    params: &Params,
    target: Option<&Bound<'_, PyAny>>,
    targets: Option<&Bound<'_, PyAny>>,
) -> PyResult<Held> {
    scene.require_symbols("Learner.contextual")?;
    let k = commands.map(commands_arg).transpose()?.unwrap_or(1);
    let ctx_targets = context_targets(scene, target, targets)?;
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
    match (closed_loop, kind) {
        (true, LearnerKind::E3d) => {
            ClosedLoopE3d::new(space, n, contexts, params, &ctx_targets, gamma)
                .map(Held::ClosedLoop)
                .map_err(bad)
        }
        (true, LearnerKind::Egreedy) => QLearning::new(space, contexts, params, gamma)
            .map(Held::QLearning)
            .map_err(bad),
        (true, other) => Err(PyValueError::new_err(format!(
            "learner `{other}`: the closed loop takes e3d (closed-loop E3D) or egreedy (Q-learning)"
        ))),
        (false, LearnerKind::GoalBabbling | LearnerKind::Archive) => {
            Err(PyValueError::new_err(format!(
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
                .map(|t| Held::new(scene, kind, params, t))
                .collect::<PyResult<Vec<Held>>>()?;
            Ok(Held::per_context(learners))
        }
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
