//! Episodes: `run_episodes` (sessions of episodes of a contextual or
//! closed-loop learner, the library's [`e3d::episode::run_episodes`], what
//! `e3d run --commands K [--closed-loop]` runs) and its `EpisodeRecord`;
//! `EpisodeWorld` (one episode stepped command by command, for the
//! Gymnasium environment) is in `episode_world`.

use crate::contextual::{commands_arg, context_targets, observe_arg};
use crate::errors::{params_of, Fail};
use crate::learner::{builtin_kind, learner_list, python_learner_name, PyContextual, PyLearner};
use crate::progress::{watched, Ticks, Watch};
use crate::record::Grid;
use crate::saved::PyLearnerState;
use crate::scene::{scene_of, PyScene};
use e3d::command::CommandSpace;
use e3d::episode::{EpisodeConfig, EpisodeRecord};
use e3d::learner::{ContextualLearner, LearnerSetup};
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::cell::RefCell;
use std::collections::HashMap;

/// A session of episodes as an `EpisodeRecord` (python/e3d/_results.py).
fn record_to_py(
    py: Python<'_>,
    rec: EpisodeRecord,
    seed: u64,
    learner: &str,
    scene: &e3d::Scene,
    starts: usize,
) -> PyResult<Py<PyAny>> {
    let slots = scene.command_space().num_slots();
    let ints = |v: &[usize]| v.iter().map(|&x| x as i64).collect::<Vec<_>>();
    let rows = rec.effects.len();
    let commands = Array2::from_shape_vec((rows, slots), rec.commands.clone())
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let fields = (
        seed,
        learner,
        rec.commands_per_episode,
        rec.num_effects,
        rec.episodes(),
        ints(&rec.starts).into_pyarray(py),
        ints(&rec.contexts).into_pyarray(py),
        commands.into_pyarray(py),
        ints(&rec.effects).into_pyarray(py),
        rec.rewards.clone().into_pyarray(py),
        rec.first_reward_episode(),
        rec.cumulative_reward(),
    );
    let metrics = crate::record::metrics_dict(py, &terminal_metrics(&rec))?;
    let more = (rec.entropy_per_start(starts), metrics, Grid::of(scene));
    let state = fields.into_pyobject(py)?.add(more.into_pyobject(py)?)?;
    let class = crate::record::result_class(py, "EpisodeRecord")?;
    Ok(class.call1(state.cast_into::<PyTuple>()?)?.unbind())
}

/// The metrics of a session record (`SessionRecord.metrics`) over the
/// episodes' terminal effects and rewards: one "trial" per episode, the
/// target uniform.
fn terminal_metrics(rec: &EpisodeRecord) -> e3d::Metrics {
    use e3d::session::{Recorder, RunningMetrics};
    let k = rec.commands_per_episode.max(1);
    let mut m = RunningMetrics::new(rec.num_effects);
    let ends = rec.effects.iter().zip(&rec.rewards).skip(k - 1).step_by(k);
    for (&effect, &reward) in ends {
        let outcome = e3d::Outcome {
            effect,
            reward,
            point: [0.0; 2],
        };
        Recorder::<()>::record(&mut m, &(), &outcome);
    }
    m.metrics(&e3d::Target::Uniform)
}

/// `e3d.run_episodes` (python/e3d/_run.py), its arguments checked there:
/// the records of the sessions of `seeds` (`one`: given as `seed`).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _run_episodes(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    episodes: usize,
    commands: Option<&Bound<'_, PyAny>>,
    seeds: Vec<u64>,
    one: bool,
    learner: Option<&Bound<'_, PyAny>>,
    closed_loop: bool,
    observe: Option<&str>,
    use_reward: bool,
    gamma: f64,
    params: HashMap<String, f64>,
    target: Option<&Bound<'_, PyAny>>,
    targets: Option<&Bound<'_, PyAny>>,
) -> PyResult<Vec<Py<PyAny>>> {
    let scene = scene_of(scene)?;
    scene.require_symbols("run_episodes")?;
    if episodes > e3d::sweep::MAX_TRIALS {
        return Err(PyValueError::new_err(format!(
            "episodes = {episodes}: expected at most {} (the command line's cap)",
            e3d::sweep::MAX_TRIALS
        )));
    }
    let k = commands.map(commands_arg).transpose()?.unwrap_or(1);
    e3d::episode::check_size(episodes, k)
        .map_err(|e| PyValueError::new_err(format!("episodes and commands: {e}")))?;
    let kind = builtin_kind(learner)?;
    let targets = context_targets(&scene, target, targets)?;
    let params = params_of(params)?;
    e3d::learner::contextual::check_gamma(gamma)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let observe = observe_arg(observe, k, closed_loop)?;
    crate::errors::check_held("episodes, commands and seeds", seeds.len(), episodes * k)?;
    crate::errors::reserve_records(
        &format!(
            "episodes = {episodes}, commands = {k}, {} seeds",
            seeds.len()
        ),
        crate::scene::record_bytes(
            &scene,
            (episodes as u64 * k as u64).saturating_mul(seeds.len() as u64),
        ),
    )?;
    // after the arguments' checks: a refused call warns of nothing
    crate::errors::warn_unread(py, crate::saved::reader_of(learner)?, &params, 2)?;
    crate::errors::warn_open_loop_gamma(py, closed_loop, gamma, 2)?;
    let inner = scene.inner.clone();
    let space = inner.command_space();
    let num_effects = inner.num_effects();
    let cfg = |seed| EpisodeConfig {
        episodes,
        commands: k,
        seed,
        use_reward,
        observe,
    };
    let probe = inner.build();
    let contexts = cfg(0).num_contexts(&probe);
    let starts = probe.num_contexts();
    if let Some(st) = learner.and_then(|l| l.cast::<PyLearnerState>().ok()) {
        if !one {
            return Err(PyValueError::new_err(
                "learner: an e3d.Learner runs one seed (give seed, not seeds)",
            ));
        }
        return Ok(vec![run_from_state(
            py,
            &scene,
            st,
            &cfg(seeds[0]),
            contexts,
        )?]);
    }
    let Some(kind) = kind else {
        let obj = learner.expect("an object");
        let objs = match one {
            true => vec![obj.clone()],
            false => learner_list(
                obj,
                seeds.len(),
                "with seeds, expected a built-in learner's name",
            )?,
        };
        let out = run_python_episodes(py, &inner, &space, objs, &seeds, &cfg, contexts, starts)?;
        return Ok(out);
    };
    let make = || {
        LearnerSetup::new(kind)
            .params(params)
            .targets(targets.clone())
            .closed_loop(closed_loop)
            .gamma(gamma)
            .contexts(&space, num_effects, contexts)
            .map_err(|e| Fail::Value(e.to_string()))
    };
    run_builtin_episodes(py, &inner, &seeds, &cfg, &make, starts)
}

/// Runs sessions of episodes of Python learners, one per seed, one after
/// the other on this thread: the first exception a learner raises stops
/// the run and is raised.
#[allow(clippy::too_many_arguments)]
fn run_python_episodes(
    py: Python<'_>,
    inner: &e3d::Scene,
    space: &CommandSpace,
    objs: Vec<Bound<'_, PyAny>>,
    seeds: &[u64],
    cfg: &impl Fn(u64) -> EpisodeConfig,
    contexts: usize,
    starts: usize,
) -> PyResult<Vec<Py<PyAny>>> {
    let mut out = Vec::with_capacity(seeds.len());
    for (obj, &seed) in objs.into_iter().zip(seeds) {
        let name = python_learner_name(&obj)?;
        let error = RefCell::new(None);
        let mut l = PyContextual(PyLearner::new(py, obj, space, &error)?, contexts);
        let mut world = inner.build();
        let raised = Ticks::new(py, None, 0, &error)?;
        let rec = e3d::episode::run_episodes(&mut *world, &mut l, &cfg(seed), &raised);
        drop(l);
        if let Some(e) = error.take() {
            return Err(e);
        }
        let rec = rec.map_err(Fail::from)?;
        out.push(record_to_py(py, rec, seed, &name, inner, starts)?);
    }
    Ok(out)
}

/// Runs sessions of episodes of a built-in learner (`make` makes it), one
/// per seed, in parallel without the GIL, each on a world of its own.
fn run_builtin_episodes(
    py: Python<'_>,
    inner: &e3d::Scene,
    seeds: &[u64],
    cfg: &(impl Fn(u64) -> EpisodeConfig + Sync),
    make: &(impl Fn() -> Result<Box<dyn ContextualLearner + Send>, Fail> + Sync),
    starts: usize,
) -> PyResult<Vec<Py<PyAny>>> {
    let name = make()?.name().to_string();
    // Ctrl-C stops every seed at its next command
    let configs: Vec<EpisodeConfig> = seeds.iter().map(|&s| cfg(s)).collect();
    let records = watched(py, None, 0, &Watch::new(), |w| {
        w.control(|control| {
            let make = |_| Ok((inner.build(), make()?));
            let mut records = vec![EpisodeRecord::default(); configs.len()];
            e3d::session::run_episode_sessions(&configs, make, &mut records, control)
                .into_iter()
                .collect::<Result<(), Fail>>()
                .map(|()| records)
        })
    })??;
    let mut out = Vec::with_capacity(records.len());
    for (rec, &seed) in records.into_iter().zip(seeds) {
        out.push(record_to_py(py, rec, seed, &name, inner, starts)?);
    }
    Ok(out)
}

/// Runs episodes from the contextual `e3d.Learner` `st` (one seed) and
/// leaves it in the state they end in.
fn run_from_state(
    py: Python<'_>,
    scene: &PyScene,
    st: &Bound<'_, PyLearnerState>,
    cfg: &EpisodeConfig,
    contexts: usize,
) -> PyResult<Py<PyAny>> {
    st.borrow().check_fits(scene, Some(contexts))?;
    let mut held = st.borrow().held.clone();
    let l = held.contextual().expect("a learner with contexts");
    let name = l.name().to_string();
    let inner = scene.inner.clone();
    let rec = watched(py, None, 0, &Watch::new(), |w| {
        let mut world = inner.build();
        w.control(|control| e3d::episode::run_episodes(&mut *world, l, cfg, control))
            .map_err(Fail::from)
    })??;
    st.borrow_mut().held = held;
    let starts = scene.inner.build().num_contexts();
    record_to_py(py, rec, cfg.seed, &name, &scene.inner, starts)
}
