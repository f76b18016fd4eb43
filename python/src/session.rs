//! `run_session` and `run_sessions`: sessions of built-in or Python
//! learners on the world an [`Executor`] chooses.

use crate::errors::{
    learner_names, params_arg, seed_arg, seeds_arg, sessions_arg, trials_arg, Fail,
};
use crate::learner::{builtin_kind, python_learner_name, Guarded, PyLearner, Tap};
use crate::progress::{watched, Throttle, Watch};
use crate::record::{batch_to_py, record_to_py, PyBatchRecord, PyRecord, Rows};
use crate::saved::{run_values_from, Held, PyLearnerState};
use crate::scene::{scene_of, target_arg, PyScene};
use e3d::world::{ExecOptions, Executor, Strategy, Workload, DEFAULT_MEMO_CAP};
use e3d::{
    E3d, Learner, LearnerKind, Metrics, Params, SessionConfig, SessionRecord, Target, ValueSpace,
    WorldError,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use rayon::prelude::*;
use std::cell::RefCell;
use std::path::PathBuf;

// The defaults of `run_session` and `run_sessions` are written as numbers,
// so that Python's signature shows them (`alpha=0.3`, not `alpha=...`):
// the CLI's, `Params::TASK1`.
const _: () = assert!(
    Params::TASK1.alpha == 0.3
        && Params::TASK1.beta == 1.0
        && Params::TASK1.lambda == 0.03
        && Params::TASK1.eta == 0.01
        && Params::TASK1.epsilon == 0.1
);

/// What `run_session` and `run_sessions` share: the checked parameters,
/// the executor's options and the learner (a built-in kind, or Python
/// objects).
pub(crate) struct SessionArgs {
    params: Params,
    options: ExecOptions,
    use_reward: bool,
    /// The target `p*` (E3D's, and the metrics' `kl_to_target`).
    target: Target,
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn session_args(
    trials: usize,
    use_reward: bool,
    alpha: f64,
    beta: f64,
    lambda_: f64,
    eta: f64,
    epsilon: f64,
    outcomes: Option<&str>,
    table_cache: Option<PathBuf>,
    target: Target,
) -> PyResult<SessionArgs> {
    if trials == 0 {
        return Err(PyValueError::new_err("trials = 0: expected at least 1"));
    }
    // the cap of the command line and of sweeps: a session's record holds
    // every trial, so 10^12 would exhaust memory and abort the interpreter
    if trials > e3d::sweep::MAX_TRIALS {
        return Err(PyValueError::new_err(format!(
            "trials = {trials}: expected at most {} (the command line's cap)",
            e3d::sweep::MAX_TRIALS
        )));
    }
    let params = params_arg(alpha, beta, lambda_, eta, epsilon)?;
    let force = match outcomes {
        None | Some("auto") => None,
        Some(s) => Some(s.parse::<Strategy>().map_err(|_| {
            PyValueError::new_err(format!(
                "outcomes = `{s}`: expected None, \"auto\", \"table\", \"memo\" or \"live\""
            ))
        })?),
    };
    Ok(SessionArgs {
        params,
        options: ExecOptions {
            cache: table_cache,
            memo_cap: DEFAULT_MEMO_CAP,
            force,
        },
        use_reward,
        target,
    })
}

/// The executor of `scene` for work that then runs with the GIL (a Python
/// learner): its table, if it builds one, is built without the GIL, and
/// Ctrl-C stops it (`KeyboardInterrupt`) within a chunk of commands.
fn executor<'s>(
    py: Python<'_>,
    scene: &'s e3d::Scene,
    work: &Workload,
    options: &ExecOptions,
) -> PyResult<Executor<'s>> {
    let watch = Watch::new();
    let exec = watched(py, None, 0, &watch, |w| {
        Executor::with_progress_until(scene, work, options, &|_, _| {}, &|| w.cancelled())
    })?;
    Ok(exec.map_err(Fail::from)?)
}

/// The metrics of a session of symbols as the CLI's `summary.json` gives
/// them: over the reachable cells too when a table knows them (and they
/// are fewer than all).
fn symbol_metrics(exec: &Executor<'_>, rec: &SessionRecord, target: &Target) -> Metrics {
    let n = rec.num_effects;
    match exec
        .table()
        .map(|t| t.reachable_effects())
        .filter(|&r| r < n)
    {
        Some(k) => rec.metrics_over_reachable(target, k),
        None => rec.metrics(target),
    }
}

/// Runs sessions of a continuous scene, one per seed, in parallel without
/// the GIL, each on a physics world of its own (`e3d run` on a continuous
/// scene): the Gaussian E3D (`"e3d"`) or uniform values (`"uniform"`).
#[allow(clippy::too_many_arguments)]
fn run_continuous(
    py: Python<'_>,
    scene: &PyScene,
    space: &ValueSpace,
    learner: Option<&Bound<'_, PyAny>>,
    a: &SessionArgs,
    seeds: &[u64],
    trials: usize,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(LearnerKind, Vec<Rows>, String)> {
    let name = &scene.inner.spec().name;
    let Some(kind) = builtin_kind(learner)? else {
        return Err(PyTypeError::new_err(format!(
            "learner: scene `{name}` takes continuous commands: expected one of {}",
            LearnerKind::CONTINUOUS
                .map(|k| format!("\"{}\"", k.as_str()))
                .join(", ")
        )));
    };
    if a.options.cache.is_some() {
        return Err(PyValueError::new_err(format!(
            "table_cache: scene `{name}` takes continuous commands, which have no outcome table (every trial is simulated)"
        )));
    }
    if matches!(a.options.force, Some(s) if s != Strategy::Live) {
        return Err(PyValueError::new_err(format!(
            "outcomes: scene `{name}` takes continuous commands, which run live only (no table, no memo)"
        )));
    }
    let n_eff = scene.inner.num_effects();
    let make = || kind.make_continuous(&a.params, space, n_eff, &a.target);
    make().map_err(|e| PyValueError::new_err(e.to_string()))?;
    if scene.inner.as_continuous().is_none() {
        return Err(PyValueError::new_err(format!(
            "scene `{name}`: continuous commands need a physics world"
        )));
    }
    let configs: Vec<SessionConfig> = seeds
        .iter()
        .map(|&seed| SessionConfig {
            trials,
            seed,
            use_reward: a.use_reward,
        })
        .collect();
    let inner = scene.inner.clone();
    let total = (trials as u64).saturating_mul(seeds.len() as u64);
    let watch = Watch::new();
    let records = watched(py, progress, total, &watch, |watch| {
        configs
            .par_iter()
            .map(|cfg| {
                let mut world = inner.as_continuous().map(|c| c.world(1)).ok_or_else(|| {
                    WorldError::Other("continuous commands need a physics world".into())
                })?;
                let mut guarded = Guarded {
                    world: &mut world,
                    stop: || watch.cancelled(),
                };
                let mut learner = make().map_err(|e| WorldError::Other(e.to_string()))?;
                let mut done = 0;
                e3d::run_value_session(&mut guarded, &mut learner, cfg, |t| {
                    watch.add((t - done) as u64);
                    done = t;
                })
            })
            .collect::<Result<Vec<_>, WorldError>>()
    })?
    .map_err(Fail::from)?;
    let rows = records
        .into_iter()
        .map(|r| {
            let m = r.metrics(&a.target);
            Rows::of_values(py, r, m)
        })
        .collect();
    Ok((
        kind,
        rows,
        "live: continuous commands (no table, no memo)".into(),
    ))
}

/// The plan, and what the memo simulated and kept, as `execution` says it.
pub(crate) fn execution_text(exec: Executor<'_>) -> String {
    let mut execution = exec.plan().to_string();
    if let Some(line) = exec.finish() {
        execution.push('\n');
        execution.push_str(&line);
    }
    execution
}

/// Runs one session of `trials` trials: the learner proposes a command,
/// the scene's world executes it, the learner learns from its effect and
/// reward. The same numbers as `e3d run SCENE --trials T --seed S`.
///
/// `learner`: a built-in learner's name (`"e3d"`, `"uniform"`, `"egreedy"`,
/// `"e3d_relax"`, `"count"`, `"smm"`; on a continuous scene `"e3d"`, the
/// Gaussian E3D, or `"uniform"`), or a Python object with
/// `propose(rng) -> symbols` and `learn(command, effect, reward)` (see
/// `docs/python.md`). `use_reward=False` is the CLI's `--no-reward`.
/// `outcomes`: `None` (the cheapest of table, memo or live, as the CLI
/// chooses) or one of `"table"`, `"memo"`, `"live"`; `table_cache`: a
/// folder to keep outcomes in (the CLI's `--table-cache`).
/// `progress`: a callable, called as `progress(trials_done, trials)` at
/// most ten times a second and once at the end. Ctrl-C stops the session
/// and raises `KeyboardInterrupt`. `target`: E3D's `p*` (None: uniform; an
/// array of one weight per effect, or a dict `{effect or (row, col):
/// weight}`), also the metrics' target.
///
/// `learner` may also be an `e3d.Learner` (or `E3dLearner`): the session
/// starts from its state (its own alpha, beta, lambda, eta and target; those given here
/// only set the metrics' target) and leaves it in the state it ends in.
/// `on_trials`: a callable, called as `on_trials(first, commands,
/// effects, rewards)` with the arrays of every `every` trials (the last
/// call may hold fewer), `first` the index of their first trial; it runs
/// the session on this thread (with the GIL), and an exception from it
/// stops the session and is raised.
#[pyfunction]
#[pyo3(signature = (scene, learner = None, trials = 5000, seed = 0, use_reward = true,
    alpha = 0.3, beta = 1.0, lambda_ = 0.03,
    eta = 0.01, epsilon = 0.1, outcomes = None, table_cache = None,
    progress = None, target = None, on_trials = None, every = 1000))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_session(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    learner: Option<&Bound<'_, PyAny>>,
    #[pyo3(from_py_with = trials_arg)] trials: usize,
    #[pyo3(from_py_with = seed_arg)] seed: u64,
    use_reward: bool,
    alpha: f64,
    beta: f64,
    lambda_: f64,
    eta: f64,
    epsilon: f64,
    outcomes: Option<&str>,
    table_cache: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
    target: Option<&Bound<'_, PyAny>>,
    on_trials: Option<&Bound<'_, PyAny>>,
    every: usize,
) -> PyResult<PyRecord> {
    let scene = scene_of(scene)?;
    let on_trials = on_trials.filter(|c| !c.is_none());
    if every == 0 {
        return Err(PyValueError::new_err("every = 0: expected at least 1"));
    }
    let target = target_arg(&scene, target)?;
    let a = session_args(
        trials,
        use_reward,
        alpha,
        beta,
        lambda_,
        eta,
        epsilon,
        outcomes,
        table_cache,
        target,
    )?;
    let work = Workload {
        trials: trials as u64,
        sessions: 1,
        threads: rayon::current_num_threads(),
    };
    let cfg = SessionConfig {
        trials,
        seed,
        use_reward: a.use_reward,
    };
    // a Learner: its state, checked against the scene, written back at the end
    let saved = learner.and_then(|l| l.cast::<PyLearnerState>().ok().cloned());
    if let Some(st) = &saved {
        st.borrow().check_fits(&scene)?;
    }
    let mut held = saved.as_ref().map(|s| s.borrow().held.clone());
    if let (Some(_), Some(h)) = (&scene.values, &mut held) {
        let name = h.kind().as_str();
        let l = h
            .values()
            .ok_or_else(|| PyTypeError::new_err("learner: not of values"))?;
        let rec = run_values_from(py, &scene, l, &cfg, progress)?;
        let metrics = rec.metrics(&a.target);
        let rows = Rows::of_values(py, rec, metrics);
        if let (Some(st), Some(h)) = (&saved, held) {
            st.borrow_mut().held = h;
        }
        let execution = "live: continuous commands (no table, no memo)".to_string();
        return record_to_py(py, &scene, name, seed, rows, execution);
    }
    if let Some(space) = scene.values.clone() {
        let (kind, mut rows, execution) =
            run_continuous(py, &scene, &space, learner, &a, &[seed], trials, progress)?;
        let rows = rows.remove(0);
        return record_to_py(py, &scene, kind.as_str(), seed, rows, execution);
    }
    let space = scene.space.clone();
    let n_eff = scene.inner.num_effects();
    let kind = match &held {
        Some(h) => Some(h.kind()),
        None => builtin_kind(learner)?,
    };
    if let Some(kind) = kind {
        let bad = |e: e3d::LearnerError| PyValueError::new_err(e.to_string());
        // E3D as its own type, so that its Q and effect model can be read
        let mut e3d_made = match (kind, &held) {
            (_, Some(Held::E3d(e))) => Some(e.clone()),
            (LearnerKind::E3d, None) => {
                Some(E3d::new(&space, n_eff, &a.params, &a.target).map_err(bad)?)
            }
            _ => None,
        };
        let mut boxed = match (kind, &held) {
            (LearnerKind::E3d, _) | (_, Some(_)) => None,
            _ => Some(
                kind.make(&a.params, &space, n_eff, &a.target)
                    .map_err(bad)?,
            ),
        };
        let from_held = held.as_mut().and_then(Held::symbols);
        let made: &mut (dyn Learner + Send) = match (&mut e3d_made, &mut boxed, from_held) {
            (Some(e), _, _) => e,
            (None, Some(b), _) => &mut **b,
            (None, None, Some(h)) => h,
            (None, None, None) => return Err(PyTypeError::new_err("no learner made")),
        };
        let (rec, metrics, exact, execution) = if let Some(cb) = on_trials {
            let error = RefCell::new(None);
            let (rec, exec) = run_here(
                py,
                &scene,
                &work,
                &a,
                &cfg,
                made,
                &error,
                progress,
                Some(cb),
                every,
            )?;
            let metrics = symbol_metrics(&exec, &rec, &a.target);
            let exact = exec
                .table()
                .and_then(|t| e3d::policy_effect_distribution(t, &*made));
            (rec, metrics, exact, execution_text(exec))
        } else {
            let inner = scene.inner.clone();
            let watch = Watch::new();
            watched(py, progress, trials as u64, &watch, |watch| {
                let stop = || watch.cancelled();
                let exec =
                    Executor::with_progress_until(&inner, &work, &a.options, &|_, _| {}, &stop)?;
                let mut world = exec.world(1);
                let mut guarded = Guarded {
                    world: &mut *world,
                    stop: || watch.cancelled(),
                };
                let mut rec = SessionRecord::new(&guarded, trials);
                e3d::run_session_into(&mut guarded, &mut *made, &cfg, &mut rec, |t| {
                    watch.set(t as u64)
                })?;
                drop(world);
                let metrics = symbol_metrics(&exec, &rec, &a.target);
                let exact = exec
                    .table()
                    .and_then(|t| e3d::policy_effect_distribution(t, &*made));
                Ok::<_, Fail>((rec, metrics, exact, execution_text(exec)))
            })??
        };
        let mut rows = Rows::of_symbols(py, rec, metrics, Some(&*made), exact)?;
        if let Some(e) = &e3d_made {
            rows.q = Some((0..space.num_slots()).map(|s| e.q(s).to_vec()).collect());
            rows.effect_model = Some(e.effect_model().probs());
            if let Some(Held::E3d(h)) = &mut held {
                *h = e.clone();
            }
        }
        if let (Some(st), Some(h)) = (&saved, held) {
            st.borrow_mut().held = h;
        }
        return record_to_py(py, &scene, kind.as_str(), seed, rows, execution);
    }
    let obj = learner.expect("an object").clone();
    let name = python_learner_name(&obj)?;
    let error = RefCell::new(None);
    let mut pl = PyLearner::new(py, obj, &space, &error)?;
    let (rec, exec) = run_here(
        py, &scene, &work, &a, &cfg, &mut pl, &error, progress, on_trials, every,
    )?;
    let metrics = symbol_metrics(&exec, &rec, &a.target);
    let rows = Rows::of_symbols(py, rec, metrics, None, None)?;
    record_to_py(py, &scene, &name, seed, rows, execution_text(exec))
}

/// Runs a session of symbols on this thread, with the GIL (a Python
/// learner, or a learner whose trials go to `on_trials`): the world the
/// executor chooses, stopped at the first error put in `error` (by the
/// learner, `progress` or `on_trials`), which is then raised.
#[allow(clippy::too_many_arguments)]
fn run_here<'s, L: Learner + ?Sized>(
    py: Python<'_>,
    scene: &'s PyScene,
    work: &Workload,
    a: &SessionArgs,
    cfg: &SessionConfig,
    learner: &mut L,
    error: &RefCell<Option<PyErr>>,
    progress: Option<&Bound<'_, PyAny>>,
    on_trials: Option<&Bound<'_, PyAny>>,
    every: usize,
) -> PyResult<(SessionRecord, Executor<'s>)> {
    let trials = cfg.trials;
    let exec = executor(py, &scene.inner, work, &a.options)?;
    let mut world = exec.world(1);
    let mut guarded = Guarded {
        world: &mut *world,
        stop: || error.borrow().is_some(),
    };
    let mut rec = SessionRecord::new(&guarded, trials);
    let mut throttle = Throttle::new(py, progress, trials as u64)?;
    let mut tap = Tap::new(
        py,
        learner,
        on_trials,
        every,
        scene.space.num_slots(),
        error,
    );
    let status = e3d::run_session_into(&mut guarded, &mut tap, cfg, &mut rec, |t| {
        if error.borrow().is_none() {
            if let Err(e) = throttle.tick(t as u64, t == trials) {
                *error.borrow_mut() = Some(e);
            }
        }
    });
    tap.flush();
    drop(world);
    if let Some(e) = error.take() {
        return Err(e);
    }
    status.map_err(Fail::from)?;
    Ok((rec, exec))
}

/// Runs several sessions of one scene together, in lockstep: at every
/// trial each session proposes its command, the new commands of all are
/// simulated together (several copies of a physics scene stepped at
/// once, as `e3d run --sessions N` does), then each session learns from
/// its own outcome. Each session's numbers are those of `run_session`
/// with its seed, and of `e3d run SCENE --sessions N --seed S`.
///
/// `seeds`: the sessions' seeds; or `sessions=N` with `seed=S` for the
/// CLI's seeds `S, S+1, ..., S+N-1`. `learner`: a built-in learner's name
/// (the sessions run in parallel groups, without the GIL), or a sequence
/// of Python learners, one per seed (they run on this thread, with the
/// GIL). The other arguments are `run_session`'s; `progress` is called
/// as `progress(trials_done, trials * sessions)`. The first session that
/// fails (a simulation that blows up) raises its error.
#[pyfunction]
#[pyo3(signature = (scene, learner = None, trials = 5000, seeds = None, sessions = None, seed = 0,
    use_reward = true, alpha = 0.3, beta = 1.0,
    lambda_ = 0.03, eta = 0.01, epsilon = 0.1,
    outcomes = None, table_cache = None, progress = None, target = None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_sessions(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    learner: Option<&Bound<'_, PyAny>>,
    #[pyo3(from_py_with = trials_arg)] trials: usize,
    #[pyo3(from_py_with = seeds_arg)] seeds: Option<Vec<u64>>,
    #[pyo3(from_py_with = sessions_arg)] sessions: Option<usize>,
    #[pyo3(from_py_with = seed_arg)] seed: u64,
    use_reward: bool,
    alpha: f64,
    beta: f64,
    lambda_: f64,
    eta: f64,
    epsilon: f64,
    outcomes: Option<&str>,
    table_cache: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
    target: Option<&Bound<'_, PyAny>>,
) -> PyResult<PyBatchRecord> {
    let scene = scene_of(scene)?;
    let target = target_arg(&scene, target)?;
    let seeds: Vec<u64> = match (seeds, sessions) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err(
                "give either seeds or sessions (with seed), not both",
            ))
        }
        (Some(s), None) => s,
        (None, Some(n)) => (0..n as u64)
            .map(|i| seed.checked_add(i))
            .collect::<Option<_>>()
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "seed = {seed} with sessions = {n}: the seeds seed..seed+N-1 pass 2^64 - 1"
                ))
            })?,
        (None, None) => {
            return Err(PyValueError::new_err(
                "expected seeds=[...] or sessions=N (seeds seed, seed+1, ..., as e3d run --sessions N --seed S)",
            ))
        }
    };
    if seeds.is_empty() {
        return Err(PyValueError::new_err(
            "no session: expected at least one seed",
        ));
    }
    let a = session_args(
        trials,
        use_reward,
        alpha,
        beta,
        lambda_,
        eta,
        epsilon,
        outcomes,
        table_cache,
        target,
    )?;
    let n = seeds.len();
    let work = Workload {
        trials: (trials as u64).saturating_mul(n as u64),
        sessions: n,
        threads: rayon::current_num_threads(),
    };
    let configs: Vec<SessionConfig> = seeds
        .iter()
        .map(|&seed| SessionConfig {
            trials,
            seed,
            use_reward: a.use_reward,
        })
        .collect();
    if let Some(space) = scene.values.clone() {
        let (kind, rows, execution) =
            run_continuous(py, &scene, &space, learner, &a, &seeds, trials, progress)?;
        return batch_to_py(py, &scene, kind.as_str(), &seeds, trials, rows, execution);
    }
    let space = scene.space.clone();
    let n_eff = scene.inner.num_effects();
    let total = work.trials;
    // the first failing session fails the call, naming its command
    let first_failure = |status: Vec<Result<(), WorldError>>| -> Result<(), Fail> {
        status.into_iter().collect::<Result<(), _>>()?;
        Ok(())
    };
    if let Some(kind) = builtin_kind(learner)? {
        let mut learners = Vec::with_capacity(n);
        for _ in 0..n {
            learners.push(
                kind.make(&a.params, &space, n_eff, &a.target)
                    .map_err(|e| PyValueError::new_err(e.to_string()))?,
            );
        }
        let inner = scene.inner.clone();
        let watch = Watch::new();
        let (records, metrics, execution) = watched(py, progress, total, &watch, |watch| {
            let stop = || watch.cancelled();
            let exec = Executor::with_progress_until(&inner, &work, &a.options, &|_, _| {}, &stop)?;
            let mut records: Vec<SessionRecord> = {
                let probe = exec.world(1);
                configs
                    .iter()
                    .map(|c| SessionRecord::new(&*probe, c.trials))
                    .collect()
            };
            // the sessions as `e3d run --sessions N` runs them
            let status = e3d::run_sessions_until(
                &exec,
                &mut learners,
                &configs,
                &mut records,
                &|t| watch.add(t),
                &|| watch.cancelled(),
            );
            first_failure(status)?;
            let metrics: Vec<Metrics> = records
                .iter()
                .map(|r| symbol_metrics(&exec, r, &a.target))
                .collect();
            Ok::<_, Fail>((records, metrics, execution_text(exec)))
        })??;
        let rows = records
            .into_iter()
            .zip(metrics)
            .zip(&learners)
            .map(|((r, m), l)| Rows::of_symbols(py, r, m, Some(&**l), None))
            .collect::<PyResult<_>>()?;
        return batch_to_py(py, &scene, kind.as_str(), &seeds, trials, rows, execution);
    }
    // Python learners: one per seed, in one lockstep group on this thread
    let objs: Vec<Bound<'_, PyAny>> = learner
        .expect("an object")
        .try_iter()
        .map_err(|_| {
            PyTypeError::new_err(format!(
                "learner: expected one of {} or a sequence of Python learners, one per seed",
                learner_names()
            ))
        })?
        .collect::<PyResult<_>>()?;
    if objs.len() != n {
        return Err(PyValueError::new_err(format!(
            "{} Python learners for {n} seeds: expected one learner per seed",
            objs.len()
        )));
    }
    let names: Vec<String> = objs
        .iter()
        .map(python_learner_name)
        .collect::<PyResult<_>>()?;
    let error = RefCell::new(None);
    let mut learners: Vec<PyLearner<'_, '_>> = objs
        .into_iter()
        .map(|o| PyLearner::new(py, o, &space, &error))
        .collect::<PyResult<_>>()?;
    let exec = executor(py, &scene.inner, &work, &a.options)?;
    let mut world = exec.world(n);
    let mut guarded = Guarded {
        world: &mut *world,
        stop: || error.borrow().is_some(),
    };
    let mut records: Vec<SessionRecord> = configs
        .iter()
        .map(|c| SessionRecord::new(&guarded, c.trials))
        .collect();
    let mut throttle = Throttle::new(py, progress, total)?;
    let mut done = 0u64;
    let status = e3d::run_lockstep_into(&mut guarded, &mut learners, &configs, &mut records, |t| {
        done += t;
        if error.borrow().is_none() {
            if let Err(e) = throttle.tick(done, done == total) {
                *error.borrow_mut() = Some(e);
            }
        }
    });
    drop(learners);
    drop(world);
    if let Some(e) = error.into_inner() {
        return Err(e);
    }
    first_failure(status)?;
    let rows = records
        .into_iter()
        .map(|r| {
            let m = symbol_metrics(&exec, &r, &a.target);
            Rows::of_symbols(py, r, m, None, None)
        })
        .collect::<PyResult<_>>()?;
    let name = if names.iter().all(|m| *m == names[0]) {
        names[0].clone()
    } else {
        names.join(",")
    };
    batch_to_py(
        py,
        &scene,
        &name,
        &seeds,
        trials,
        rows,
        execution_text(exec),
    )
}
