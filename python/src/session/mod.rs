//! `run_session` and `run_sessions`: sessions of built-in or Python
//! learners on the world an [`Executor`] chooses. Sessions run with the
//! GIL (Python learners, `on_trials`) are in `python_learners`, sessions
//! of continuous commands in `values`.

use crate::errors::{check_held, learner_names, params_of, reserve_records, warn_unread, Fail};
use crate::held::Held;
use crate::learner::{builtin_kind, learner_list, Tap};
use crate::progress::{check_callable, watched, Watch};
use crate::record::{record_to_py, Rows};
use crate::saved::{reader_of, PyLearnerState};
use crate::scene::{record_bytes, scene_of, target_arg, PyScene};
use e3d::session::Learns;
use e3d::world::{ExecOptions, Executor, Strategy, Workload, DEFAULT_MEMO_CAP};
use e3d::{Learner, Metrics, Params, SessionConfig, SessionRecord, Target, WorldError};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use python_learners::{run_here, run_python};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::PathBuf;
use values::{check_values, run_values};

mod python_learners;
mod values;

/// What the sessions of a call share: the checked parameters, the
/// executor's options, and the target `p*` (E3D's, and the metrics'
/// `kl_to_target`).
pub(crate) struct SessionArgs {
    params: Params,
    options: ExecOptions,
    target: Target,
}

/// The session arguments, checked (the hyper-parameters by the library).
fn session_args(
    trials: usize,
    params: HashMap<String, f64>,
    outcomes: Option<&str>,
    table_cache: Option<PathBuf>,
    target: Target,
) -> PyResult<SessionArgs> {
    // the cap of the command line and of sweeps: a session's record holds
    // every trial, so 10^12 would exhaust memory and abort the interpreter
    if trials > e3d::sweep::MAX_TRIALS {
        return Err(PyValueError::new_err(format!(
            "trials = {trials}: expected at most {} (the command line's cap)",
            e3d::sweep::MAX_TRIALS
        )));
    }
    let force = match outcomes {
        None | Some("auto") => None,
        Some(s) => Some(s.parse::<Strategy>().map_err(|_| {
            PyValueError::new_err(format!(
                "outcomes = `{s}`: expected None, \"auto\", \"table\", \"memo\" or \"live\""
            ))
        })?),
    };
    Ok(SessionArgs {
        params: params_of(params)?,
        options: ExecOptions {
            cache: table_cache,
            memo_cap: DEFAULT_MEMO_CAP,
            force,
        },
        target,
    })
}

/// The metrics of a session of symbols as the CLI's `summary.json` gives
/// them: over the reachable cells too when a table knows them (and they
/// are fewer than all).
fn symbol_metrics(
    exec: &Executor<'_>,
    scene: &e3d::Scene,
    rec: &SessionRecord,
    target: &Target,
) -> Metrics {
    let n = rec.num_effects;
    let m = match exec
        .table()
        .map(|t| t.reachable_effects())
        .filter(|&r| r < n)
    {
        Some(k) => rec.metrics_over_reachable(target, k),
        None => rec.metrics(target),
    };
    let effort = e3d::learner::Effort::of_scene(scene);
    Metrics {
        qd_score: rec.qd_score(&effort),
        ..m
    }
}

/// The plan, and what the memo simulated and kept, as `execution` says it.
fn execution_text(exec: Executor<'_>) -> String {
    let mut execution = exec.plan().to_string();
    if let Some(line) = exec.finish() {
        execution.push('\n');
        execution.push_str(&line);
    }
    execution
}

/// `e3d.run_session` (`one`: `learner` may then be an `e3d.Learner`, which
/// the session starts from and leaves in the state it ends in, and
/// `on_trials` a callable) and `e3d.run_sessions` (python/e3d/_run.py,
/// which checks the arguments' types): the `SessionRecord` of each seed.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _run_sessions(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    learner: Option<&Bound<'_, PyAny>>,
    trials: usize,
    seeds: Vec<u64>,
    one: bool,
    use_reward: bool,
    params: HashMap<String, f64>,
    outcomes: Option<&str>,
    table_cache: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
    target: Option<&Bound<'_, PyAny>>,
    on_trials: Option<&Bound<'_, PyAny>>,
    every: usize,
) -> PyResult<Vec<Py<PyAny>>> {
    let scene = scene_of(scene)?;
    let on_trials = on_trials.filter(|c| !c.is_none());
    if let (Some(_), Some(_)) = (on_trials, &scene.values) {
        return Err(PyValueError::new_err(format!(
            "on_trials: scene `{}` is continuous: its sessions run without a per-trial callback; the record holds every trial's values, effects and rewards",
            scene.inner.spec().name
        )));
    }
    let saved = learner.and_then(|l| l.cast::<PyLearnerState>().ok());
    if saved.is_some() && !one {
        return Err(PyTypeError::new_err(
            "learner: an e3d.Learner holds one session's state: run it with run_session (run_sessions takes a learner's name, or a sequence of Python learners, one per seed)",
        ));
    }
    let target = target_arg(&scene, target)?;
    let a = session_args(trials, params, outcomes, table_cache, target)?;
    let n = seeds.len();
    let what = if one {
        format!("trials = {trials}")
    } else {
        check_held("trials and sessions", n, trials)?;
        format!("trials = {trials}, {n} sessions")
    };
    let all = (trials as u64).saturating_mul(n as u64);
    reserve_records(&what, record_bytes(&scene, all))?;
    // a Learner: its state, checked against the scene, written back at the end
    if let Some(st) = saved {
        st.borrow().check_fits(&scene, None)?;
    }
    warn_unread(py, reader_of(learner)?, &a.params, 2)?;
    check_callable(progress)?;
    let configs: Vec<SessionConfig> = seeds
        .iter()
        .map(|&seed| SessionConfig {
            trials,
            seed,
            use_reward,
        })
        .collect();
    let work = Workload {
        trials: all,
        sessions: n,
        threads: rayon::current_num_threads(),
    };
    let run = Run {
        scene: &scene,
        a: &a,
        work: &work,
        configs: &configs,
        progress,
    };
    let kind = match saved {
        Some(st) => Some(st.borrow().held.kind()),
        None => builtin_kind(learner)?,
    };
    if scene.values.is_some() && saved.is_none() {
        check_values(&scene, kind, &a)?;
    }
    let (name, rows, execution) = match kind {
        None => {
            let obj = learner.expect("an object");
            let objs = match one {
                true => vec![obj.clone()],
                false => learner_list(obj, n, &format!("expected one of {}", learner_names()))?,
            };
            run_python(py, &run, objs)?
        }
        Some(kind) => {
            let mut held = match saved {
                Some(st) => vec![st.borrow().held.clone()],
                None => {
                    let fresh = |_| Held::new(&scene, kind, &a.params, &a.target);
                    configs.iter().map(fresh).collect::<PyResult<_>>()?
                }
            };
            let (rows, execution) = match (&scene.values, on_trials) {
                (Some(_), _) => run_values(py, &run, &mut held)?,
                (None, tap) => run_builtin(py, &run, &mut held, tap.map(|cb| (cb, every)))?,
            };
            if let Some(st) = saved {
                st.borrow_mut().held = held.remove(0);
            }
            (kind.as_str().to_string(), rows, execution)
        }
    };
    let record = |(&seed, rows)| record_to_py(py, &scene, &name, seed, rows, execution.clone());
    seeds.iter().zip(rows).map(record).collect()
}

/// The sessions of a call: their scene, arguments, workload and
/// configurations, and the progress callback that watches them.
struct Run<'a, 'py> {
    scene: &'a PyScene,
    a: &'a SessionArgs,
    work: &'a Workload,
    configs: &'a [SessionConfig],
    progress: Option<&'a Bound<'py, PyAny>>,
}

/// The executor of `scene`, built without the GIL (a table can take a
/// while): Ctrl-C stops it (`KeyboardInterrupt`) within a chunk of
/// commands.
fn executor<'s>(
    py: Python<'_>,
    scene: &'s e3d::Scene,
    run: &Run<'_, '_>,
) -> PyResult<Executor<'s>> {
    let exec = watched(py, None, 0, &Watch::default(), |w| {
        let stop = || w.cancelled();
        let control = e3d::Control {
            stop: &stop,
            ..e3d::Control::default()
        };
        Executor::with_control(scene, run.work, &run.a.options, &control)
    })?;
    Ok(exec.map_err(Fail::from)?)
}

/// The first failing session fails the call, naming its command.
fn first_failure(status: Vec<Result<(), WorldError>>) -> Result<(), Fail> {
    status.into_iter().collect::<Result<(), _>>()?;
    Ok(())
}

/// Runs sessions of built-in learners (`held`, one per configuration) on
/// a scene of symbols, in parallel lockstep groups without the GIL (as
/// `e3d run --sessions N` runs them); with `tap` (`on_trials` and its
/// `every`, one session), on this thread, its trials handed to the
/// callable. Returns their rows (E3D's final Q and effect model in them)
/// and the execution text.
fn run_builtin(
    py: Python<'_>,
    run: &Run<'_, '_>,
    held: &mut [Held],
    tap: Option<(&Bound<'_, PyAny>, usize)>,
) -> PyResult<(Vec<Rows>, String)> {
    let exec = executor(py, &run.scene.inner, run)?;
    let mut learners: Vec<Lent<'_, dyn Learner + Send>> = held
        .iter_mut()
        .map(|h| Lent(h.symbols().expect("a learner of symbols")))
        .collect();
    let records = if let Some((cb, every)) = tap {
        let error = RefCell::new(None);
        let shape = (run.scene.space.num_slots(), run.configs[0].trials);
        let mut tap = [Tap::new(&mut *learners[0].0, cb, every, shape, &error)];
        run_here(py, &exec, run, &mut tap, &error)?
    } else {
        let mut records = new_records(&exec, run.configs);
        let status = watched(py, run.progress, run.work.trials, &Watch::default(), |w| {
            w.control(|c| e3d::run_sessions(&exec, &mut learners, run.configs, &mut records, c))
        })?;
        first_failure(status)?;
        records
    };
    drop(learners);
    let mut held = held.iter_mut();
    let rows = records
        .into_iter()
        .map(|r| {
            let m = symbol_metrics(&exec, &run.scene.inner, &r, &run.a.target);
            let Some(h) = held.next() else {
                return Rows::of_symbols(py, r, m, None, None);
            };
            let l = h.symbols().expect("a learner of symbols");
            let exact = exec
                .table()
                .and_then(|t| e3d::session::policy_effect_distribution(t, &*l));
            let mut rows = Rows::of_symbols(py, r, m, Some(&*l), exact)?;
            if let Some(e) = h.e3d() {
                rows.q = Some((0..e.num_slots()).map(|s| e.q(s).to_vec()).collect());
                rows.effect_model = Some(e.effect_model().probs());
            }
            Ok(rows)
        })
        .collect::<PyResult<_>>()?;
    Ok((rows, execution_text(exec)))
}

/// A record for each configuration, of the world `exec` makes.
fn new_records(exec: &Executor<'_>, configs: &[SessionConfig]) -> Vec<SessionRecord> {
    let probe = exec.world(1);
    let new = |c: &SessionConfig| SessionRecord::new(&*probe, c.trials);
    configs.iter().map(new).collect()
}

/// A held learner lent to the engine, which takes learners by value.
struct Lent<'a, L: ?Sized>(&'a mut L);

impl<C, L: Learns<C> + ?Sized> Learns<C> for Lent<'_, L> {
    fn propose_next(&mut self, rng: &mut e3d::SessionRng, command: &mut C) {
        self.0.propose_next(rng, command)
    }
    fn learn_from(&mut self, command: &C, outcome: &e3d::Outcome) {
        self.0.learn_from(command, outcome)
    }
    fn likely(&self, blank: &C, n: usize, rng: &mut e3d::SessionRng) -> Option<Vec<C>> {
        self.0.likely(blank, n, rng)
    }
}
