//! `run_session` and `run_sessions`: sessions of built-in or Python
//! learners on the world an [`Executor`] chooses.

use crate::errors::{learner_names, seed_arg, seeds_arg, sessions_arg, trials_arg, Fail};
use crate::learner::{builtin_kind, python_learner_name, Guarded, PyLearner};
use crate::progress::{watched, Throttle, Watch};
use crate::record::{batch_to_py, record_to_py, PyBatchRecord, PyRecord};
use crate::scene::scene_of;
use e3d::world::{ExecOptions, Executor, Strategy, Workload, DEFAULT_MEMO_CAP};
use e3d::{Params, SessionConfig, SessionRecord, Target, WorldError};
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
) -> PyResult<SessionArgs> {
    if trials == 0 {
        return Err(PyValueError::new_err("trials = 0: expected at least 1"));
    }
    let params = Params {
        alpha,
        beta,
        lambda: lambda_,
        eta,
        epsilon,
    };
    params
        .validate()
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
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
    })
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
/// `learner`: `"e3d"`, `"uniform"`, `"egreedy"`, or a Python object with
/// `propose(rng) -> symbols` and `learn(command, effect, reward)` (see
/// `docs/python.md`). `use_reward=False` is the CLI's `--no-reward`.
/// `outcomes`: `None` (the cheapest of table, memo or live, as the CLI
/// chooses) or one of `"table"`, `"memo"`, `"live"`; `table_cache`: a
/// folder to keep outcomes in (the CLI's `--table-cache`).
/// `progress`: a callable, called as `progress(trials_done, trials)` at
/// most ten times a second and once at the end. Ctrl-C stops the session
/// and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (scene, learner = None, trials = 5000, seed = 0, use_reward = true,
    alpha = 0.3, beta = 1.0, lambda_ = 0.03,
    eta = 0.01, epsilon = 0.1, outcomes = None, table_cache = None,
    progress = None))]
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
) -> PyResult<PyRecord> {
    let scene = scene_of(scene)?;
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
    let space = scene.space.clone();
    let n_eff = scene.inner.num_effects();
    if let Some(kind) = builtin_kind(learner)? {
        let mut made = kind
            .make(&a.params, &space, n_eff, &Target::Uniform)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let inner = scene.inner.clone();
        let watch = Watch::new();
        let (rec, execution) = watched(py, progress, trials as u64, &watch, |watch| {
            let exec = Executor::new(&inner, &work, &a.options)?;
            let mut world = exec.world(1);
            let mut guarded = Guarded {
                world: &mut *world,
                stop: || watch.cancelled(),
            };
            let mut rec = SessionRecord::new(&guarded, trials);
            e3d::run_session_into(&mut guarded, &mut made, &cfg, &mut rec, |t| {
                watch.set(t as u64)
            })?;
            drop(world);
            Ok::<_, Fail>((rec, execution_text(exec)))
        })??;
        return record_to_py(py, &scene, kind.as_str(), &cfg, rec, execution);
    }
    let obj = learner.expect("an object").clone();
    let name = python_learner_name(&obj)?;
    let error = RefCell::new(None);
    let mut pl = PyLearner::new(py, obj, &space, &error)?;
    let exec = Executor::new(&scene.inner, &work, &a.options).map_err(Fail::from)?;
    let mut world = exec.world(1);
    let mut guarded = Guarded {
        world: &mut *world,
        stop: || error.borrow().is_some(),
    };
    let mut rec = SessionRecord::new(&guarded, trials);
    let mut throttle = Throttle::new(py, progress, trials as u64)?;
    let status = e3d::run_session_into(&mut guarded, &mut pl, &cfg, &mut rec, |t| {
        if error.borrow().is_none() {
            if let Err(e) = throttle.tick(t as u64, t == trials) {
                *error.borrow_mut() = Some(e);
            }
        }
    });
    drop(world);
    if let Some(e) = error.into_inner() {
        return Err(e);
    }
    status.map_err(Fail::from)?;
    record_to_py(py, &scene, &name, &cfg, rec, execution_text(exec))
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
    outcomes = None, table_cache = None, progress = None))]
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
) -> PyResult<PyBatchRecord> {
    let scene = scene_of(scene)?;
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
                kind.make(&a.params, &space, n_eff, &Target::Uniform)
                    .map_err(|e| PyValueError::new_err(e.to_string()))?,
            );
        }
        let inner = scene.inner.clone();
        let watch = Watch::new();
        let (records, execution) = watched(py, progress, total, &watch, |watch| {
            let exec = Executor::new(&inner, &work, &a.options)?;
            let mut records: Vec<SessionRecord> = {
                let probe = exec.world(1);
                configs
                    .iter()
                    .map(|c| SessionRecord::new(&*probe, c.trials))
                    .collect()
            };
            // lockstep groups (one session a group on a table), in
            // parallel, as `e3d run --sessions N` forms them
            let groups = if exec.table().is_some() {
                n
            } else {
                exec.plan().groups.max(1)
            };
            let size = n.div_ceil(groups);
            let status: Vec<Result<(), WorldError>> = learners
                .par_chunks_mut(size)
                .zip(records.par_chunks_mut(size))
                .zip(configs.par_chunks(size))
                .map(|((l, r), c)| {
                    let mut world = exec.world(l.len());
                    let mut guarded = Guarded {
                        world: &mut *world,
                        stop: || watch.cancelled(),
                    };
                    e3d::run_lockstep_into(&mut guarded, l, c, r, |t| watch.add(t))
                })
                .collect::<Vec<_>>()
                .into_iter()
                .flatten()
                .collect();
            first_failure(status)?;
            Ok::<_, Fail>((records, execution_text(exec)))
        })??;
        return batch_to_py(
            py,
            &scene,
            kind.as_str(),
            &seeds,
            trials,
            records,
            execution,
        );
    }
    // Python learners: one per seed, in one lockstep group on this thread
    let objs: Vec<Bound<'_, PyAny>> = learner
        .expect("an object")
        .try_iter()
        .map_err(|_| {
            PyTypeError::new_err(
                format!("learner: expected one of {} or a sequence of Python learners, one per seed", learner_names()),
            )
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
    let exec = Executor::new(&scene.inner, &work, &a.options).map_err(Fail::from)?;
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
        records,
        execution_text(exec),
    )
}
