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
use crate::scene::scene_of;
use e3d::command::CommandSpace;
use e3d::episode::{EpisodeConfig, EpisodeRecord};
use e3d::learner::{ContextualLearner, LearnerSetup};
use e3d::LearnerKind;
use numpy::ndarray::Array2;
use numpy::IntoPyArray;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyTuple;
use std::cell::RefCell;
use std::collections::HashMap;
use std::ops::DerefMut;
use std::sync::Mutex;

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
    let kind = builtin_kind(learner)?;
    let mut k = commands.map(commands_arg).transpose()?.unwrap_or(1);
    // per-move Q-learning: each move of the K commands a command of its own
    let mut inner = scene.inner.clone();
    if kind == Some(LearnerKind::QlearningMoves) {
        let moves = inner.spec().num_slots();
        inner = match inner.with_moves(1) {
            Some(single) => std::sync::Arc::new(single.map_err(|e| PyValueError::new_err(e.to_string()))?),
            None => {
                return Err(PyValueError::new_err(format!(
                    "learner `qlearning_moves` takes a scene whose command is `Repeat` (every move from one alphabet); `{}`'s is not",
                    inner.spec().name
                )))
            }
        };
        k *= moves;
    }
    e3d::episode::check_size(episodes, k)
        .map_err(|e| PyValueError::new_err(format!("episodes and commands: {e}")))?;
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
    let space = inner.command_space();
    let configs: Vec<EpisodeConfig> = seeds
        .iter()
        .map(|&seed| EpisodeConfig {
            episodes,
            commands: k,
            seed,
            use_reward,
            observe,
        })
        .collect();
    let probe = inner.build();
    let contexts = configs[0].num_contexts(&probe);
    let starts = probe.num_contexts();
    let records = |records: Vec<EpisodeRecord>, name: &str| {
        let record =
            |(rec, c): (_, &EpisodeConfig)| record_to_py(py, rec, c.seed, name, &inner, starts);
        records.into_iter().zip(&configs).map(record).collect()
    };
    if let Some(st) = learner.and_then(|l| l.cast::<PyLearnerState>().ok()) {
        if !one {
            return Err(PyValueError::new_err(
                "learner: an e3d.Learner runs one seed (give seed, not seeds)",
            ));
        }
        // its state, lent to the run and left in the state it ends in
        st.borrow().check_fits(&scene, Some(contexts))?;
        let mut held = st.borrow().held.clone();
        let l = held.contextual().expect("a learner with contexts");
        let name = l.name().to_string();
        let lent = Mutex::new(Some(l));
        let take = || lent.lock().unwrap_or_else(|e| e.into_inner()).take();
        let recs = run_builtin_episodes(py, &inner, &configs, &|| Ok(take().expect("one seed")))?;
        st.borrow_mut().held = held;
        return records(recs, &name);
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
        return run_python_episodes(py, &inner, &space, objs, &configs, contexts, starts);
    };
    let make = || {
        LearnerSetup::new(kind)
            .params(params)
            .targets(targets.clone())
            .closed_loop(closed_loop)
            .gamma(gamma)
            .contexts(&space, inner.num_effects(), contexts)
            .map_err(|e| Fail::Value(e.to_string()))
    };
    let name = make()?.name().to_string();
    records(run_builtin_episodes(py, &inner, &configs, &make)?, &name)
}

/// Runs sessions of episodes of Python learners, one per configuration,
/// one after the other on this thread: the first exception a learner
/// raises stops the run and is raised.
fn run_python_episodes(
    py: Python<'_>,
    inner: &e3d::Scene,
    space: &CommandSpace,
    objs: Vec<Bound<'_, PyAny>>,
    configs: &[EpisodeConfig],
    contexts: usize,
    starts: usize,
) -> PyResult<Vec<Py<PyAny>>> {
    let mut out = Vec::with_capacity(configs.len());
    for (obj, cfg) in objs.into_iter().zip(configs) {
        let name = python_learner_name(&obj)?;
        let error = RefCell::new(None);
        let mut l = PyContextual(PyLearner::new(py, obj, space, &error)?, contexts);
        let mut world = inner.build();
        let raised = Ticks::new(py, None, 0, &error)?;
        let rec = e3d::episode::run_episodes(&mut *world, &mut l, cfg, &raised);
        drop(l);
        if let Some(e) = error.take() {
            return Err(e);
        }
        let rec = rec.map_err(Fail::from)?;
        out.push(record_to_py(py, rec, cfg.seed, &name, inner, starts)?);
    }
    Ok(out)
}

/// Runs sessions of episodes of built-in learners (`make` makes each), one
/// per configuration, in parallel without the GIL, each on a world of its
/// own; Ctrl-C stops every one at its next command.
fn run_builtin_episodes<L: DerefMut<Target: ContextualLearner>>(
    py: Python<'_>,
    inner: &e3d::Scene,
    configs: &[EpisodeConfig],
    make: &(impl Fn() -> Result<L, Fail> + Sync),
) -> PyResult<Vec<EpisodeRecord>> {
    Ok(watched(py, None, 0, &Watch::default(), |w| {
        w.control(|control| {
            let make = |_| Ok((inner.build(), make()?));
            let mut records = vec![EpisodeRecord::default(); configs.len()];
            e3d::session::run_episode_sessions(configs, make, &mut records, control)
                .into_iter()
                .collect::<Result<(), Fail>>()
                .map(|()| records)
        })
    })??)
}
