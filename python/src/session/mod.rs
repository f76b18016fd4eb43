//! `run_session` and `run_sessions`: sessions of built-in or Python
//! learners on the world an [`Executor`] chooses. The arguments they share
//! and the sessions of built-in learners on scenes of symbols are here;
//! sessions run with the GIL (Python learners, `on_trials`) are in
//! `python_learners`, sessions of continuous commands in `values`.

use crate::errors::{check_held, learner_names, params_of, Fail};
use crate::held::Held;
use crate::learner::{builtin_kind, learner_list, Tap};
use crate::progress::{watched, Watch};
use crate::record::{batch_to_py, record_to_py, Rows};
use crate::saved::PyLearnerState;
use crate::scene::{scene_of, target_arg, PyScene};
use e3d::world::{ExecOptions, Executor, Strategy, Workload, DEFAULT_MEMO_CAP};
use e3d::{
    Control, Learner, LearnerKind, Metrics, Params, SessionConfig, SessionRecord, Target,
    WorldError,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use python_learners::{run_here, run_python, run_python_batch};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::PathBuf;
use values::{run_continuous, run_held_values};

mod python_learners;
mod values;

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

/// The arguments `run_session` and `run_sessions` share, checked (the
/// hyper-parameters by the library).
pub(crate) fn session_args(
    trials: usize,
    use_reward: bool,
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
        use_reward,
        target,
    })
}

impl SessionArgs {
    /// The configurations of sessions of `trials` trials, one per seed.
    fn configs(&self, trials: usize, seeds: &[u64]) -> Vec<SessionConfig> {
        let use_reward = self.use_reward;
        let config = |&seed| SessionConfig {
            trials,
            seed,
            use_reward,
        };
        seeds.iter().map(config).collect()
    }
}

/// The work the executor plans for: `sessions` sessions of `trials`
/// trials, on rayon's threads.
fn workload(trials: usize, sessions: usize) -> Workload {
    Workload {
        trials: (trials as u64).saturating_mul(sessions as u64),
        sessions,
        threads: rayon::current_num_threads(),
    }
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

/// The plan, and what the memo simulated and kept, as `execution` says it.
pub(crate) fn execution_text(exec: Executor<'_>) -> String {
    let mut execution = exec.plan().to_string();
    if let Some(line) = exec.finish() {
        execution.push('\n');
        execution.push_str(&line);
    }
    execution
}

/// `e3d.run_session` (python/e3d/_run.py), its arguments checked there.
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _run_session(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    learner: Option<&Bound<'_, PyAny>>,
    trials: usize,
    seed: u64,
    use_reward: bool,
    params: HashMap<String, f64>,
    outcomes: Option<&str>,
    table_cache: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
    target: Option<&Bound<'_, PyAny>>,
    on_trials: Option<&Bound<'_, PyAny>>,
    every: usize,
) -> PyResult<Py<PyAny>> {
    let scene = scene_of(scene)?;
    let on_trials = on_trials.filter(|c| !c.is_none());
    if let (Some(_), Some(_)) = (on_trials, &scene.values) {
        return Err(PyValueError::new_err(format!(
            "on_trials: scene `{}` is continuous: its sessions run without a per-trial callback; the record holds every trial's values, effects and rewards",
            scene.inner.spec().name
        )));
    }
    let target = target_arg(&scene, target)?;
    let a = session_args(trials, use_reward, params, outcomes, table_cache, target)?;
    crate::errors::reserve_records(
        &format!("trials = {trials}"),
        crate::scene::record_bytes(&scene, trials as u64),
    )?;
    let run = OneSession {
        work: workload(trials, 1),
        cfg: a.configs(trials, &[seed]).remove(0),
        progress,
        on_trials,
        every,
    };
    // a Learner: its state, checked against the scene, written back at the end
    let saved = saved_state(learner, &scene)?;
    crate::errors::warn_unread(py, crate::saved::reader_of(learner)?, &a.params, 2)?;
    let held = saved.as_ref().map(|s| s.borrow().held.clone());
    if scene.values.is_some() {
        if let Some(h) = held {
            return run_held_values(py, &scene, saved.as_ref(), h, &a, &run);
        }
    }
    if let Some(space) = scene.values.clone() {
        let (kind, mut rows, execution) =
            run_continuous(py, &scene, &space, learner, &a, &[seed], trials, progress)?;
        let rows = rows.remove(0);
        return record_to_py(py, &scene, kind.as_str(), seed, rows, execution);
    }
    let kind = match &held {
        Some(h) => Some(h.kind()),
        None => builtin_kind(learner)?,
    };
    match kind {
        Some(kind) => run_builtin(py, &scene, kind, saved.as_ref(), held, &a, &run),
        None => run_python(py, &scene, learner.expect("an object"), &a, &run),
    }
}

/// One session as `run_session` runs it: its workload, its configuration
/// and the Python callbacks that watch it.
struct OneSession<'b, 'py> {
    work: Workload,
    cfg: SessionConfig,
    progress: Option<&'b Bound<'py, PyAny>>,
    on_trials: Option<&'b Bound<'py, PyAny>>,
    every: usize,
}

/// The `e3d.Learner` that `learner` is, if it is one, its state checked
/// against the scene: the session starts from that state and writes back
/// the state it ends in.
fn saved_state<'py>(
    learner: Option<&Bound<'py, PyAny>>,
    scene: &PyScene,
) -> PyResult<Option<Bound<'py, PyLearnerState>>> {
    let saved = learner.and_then(|l| l.cast::<PyLearnerState>().ok().cloned());
    if let Some(st) = &saved {
        st.borrow().check_fits(scene, None)?;
    }
    Ok(saved)
}

/// Writes the state a session ended in back to the `e3d.Learner` it
/// started from.
fn write_back(saved: Option<&Bound<'_, PyLearnerState>>, held: Option<Held>) {
    if let (Some(st), Some(h)) = (saved, held) {
        st.borrow_mut().held = h;
    }
}

/// Runs one session of a built-in learner (new, or an `e3d.Learner`'s
/// state, then written back) on a scene of symbols; E3D's Q and effect
/// model go into the record.
fn run_builtin(
    py: Python<'_>,
    scene: &PyScene,
    kind: LearnerKind,
    saved: Option<&Bound<'_, PyLearnerState>>,
    held: Option<Held>,
    a: &SessionArgs,
    run: &OneSession<'_, '_>,
) -> PyResult<Py<PyAny>> {
    let mut held = match held {
        Some(h) => h,
        None => Held::new(scene, kind, &a.params, &a.target)?,
    };
    let made = held.symbols().expect("a learner of symbols");
    let (rec, metrics, exact, execution) = run_symbols(py, scene, a, run, made)?;
    let mut rows = Rows::of_symbols(py, rec, metrics, Some(&*made), exact)?;
    final_e3d(&mut rows, &mut held);
    write_back(saved, Some(held));
    record_to_py(py, scene, kind.as_str(), run.cfg.seed, rows, execution)
}

/// A session of symbols as a built-in learner's record takes it: the
/// session, its metrics, the learner's exact effect distribution (when a
/// table knows the outcomes) and the execution text.
type SymbolRun = (SessionRecord, Metrics, Option<Vec<f64>>, String);

/// Runs one session of a built-in learner on a scene of symbols: on this
/// thread when its trials go to `on_trials`, else without the GIL.
fn run_symbols(
    py: Python<'_>,
    scene: &PyScene,
    a: &SessionArgs,
    run: &OneSession<'_, '_>,
    made: &mut (dyn Learner + Send),
) -> PyResult<SymbolRun> {
    if let Some(cb) = run.on_trials {
        let error = RefCell::new(None);
        let shape = (scene.space.num_slots(), run.cfg.trials);
        let mut tap = [Tap::new(&mut *made, cb, run.every, shape, &error)];
        let configs = std::slice::from_ref(&run.cfg);
        let (mut recs, exec) = run_here(
            py,
            scene,
            a,
            &run.work,
            configs,
            &mut tap,
            &error,
            run.progress,
        )?;
        drop(tap);
        let rec = recs.remove(0);
        let metrics = symbol_metrics(&exec, &rec, &a.target);
        let exact = exact_of(&exec, made);
        return Ok((rec, metrics, exact, execution_text(exec)));
    }
    let cfg = &run.cfg;
    let trials = cfg.trials;
    unlocked(
        py,
        scene,
        &run.work,
        &a.options,
        run.progress,
        trials as u64,
        |exec, watch| {
            let mut world = exec.world(1);
            let mut rec = SessionRecord::new(&*world, trials);
            watch.control(|control| {
                e3d::session::run_session_into(&mut *world, &mut *made, cfg, &mut rec, control)
            })?;
            drop(world);
            let metrics = symbol_metrics(&exec, &rec, &a.target);
            let exact = exact_of(&exec, made);
            Ok((rec, metrics, exact, execution_text(exec)))
        },
    )
}

/// The distribution of effects `learner`'s policy gives, exactly, when the
/// executor has a table of the outcomes.
fn exact_of(exec: &Executor<'_>, learner: &dyn Learner) -> Option<Vec<f64>> {
    exec.table()
        .and_then(|t| e3d::session::policy_effect_distribution(t, learner))
}

/// Runs `run` on the executor of `scene` without the GIL, watched (see
/// [`watched`]): Ctrl-C stops it and `progress` sees `total` trials; the
/// executor's table, if it builds one, can be stopped too.
fn unlocked<T, F>(
    py: Python<'_>,
    scene: &PyScene,
    work: &Workload,
    options: &ExecOptions,
    progress: Option<&Bound<'_, PyAny>>,
    total: u64,
    run: F,
) -> PyResult<T>
where
    T: Send,
    F: for<'s> FnOnce(Executor<'s>, &Watch) -> Result<T, Fail> + Send,
{
    let inner = scene.inner.clone();
    let watch = Watch::new();
    Ok(watched(py, progress, total, &watch, |watch| {
        let stop = || watch.cancelled();
        let control = Control {
            stop: &stop,
            ..Control::default()
        };
        let exec = Executor::with_control(&inner, work, options, &control)?;
        run(exec, watch)
    })??)
}

/// `e3d.run_sessions` (python/e3d/_run.py), its arguments checked there
/// (`seeds`: at least one).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub(crate) fn _run_sessions(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    learner: Option<&Bound<'_, PyAny>>,
    trials: usize,
    seeds: Vec<u64>,
    use_reward: bool,
    params: HashMap<String, f64>,
    outcomes: Option<&str>,
    table_cache: Option<PathBuf>,
    progress: Option<&Bound<'_, PyAny>>,
    target: Option<&Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let scene = scene_of(scene)?;
    if learner.is_some_and(|l| l.is_instance_of::<PyLearnerState>()) {
        return Err(PyTypeError::new_err(
            "learner: an e3d.Learner holds one session's state: run it with run_session (run_sessions takes a learner's name, or a sequence of Python learners, one per seed)",
        ));
    }
    let target = target_arg(&scene, target)?;
    let a = session_args(trials, use_reward, params, outcomes, table_cache, target)?;
    check_held("trials and sessions", seeds.len(), trials)?;
    crate::errors::reserve_records(
        &format!("trials = {trials}, {} sessions", seeds.len()),
        crate::scene::record_bytes(&scene, (trials as u64).saturating_mul(seeds.len() as u64)),
    )?;
    crate::errors::warn_unread(py, crate::saved::reader_of(learner)?, &a.params, 2)?;
    let (name, rows, execution) = if let Some(space) = scene.values.clone() {
        let (kind, rows, execution) =
            run_continuous(py, &scene, &space, learner, &a, &seeds, trials, progress)?;
        (kind.as_str().to_string(), rows, execution)
    } else {
        let work = workload(trials, seeds.len());
        let configs = a.configs(trials, &seeds);
        match builtin_kind(learner)? {
            Some(kind) => {
                let (rows, execution) =
                    run_builtin_batch(py, &scene, kind, &a, &work, &configs, progress)?;
                (kind.as_str().to_string(), rows, execution)
            }
            None => {
                let expected = format!("expected one of {}", learner_names());
                let objs = learner_list(learner.expect("an object"), seeds.len(), &expected)?;
                run_python_batch(py, &scene, objs, &a, &work, &configs, progress)?
            }
        }
    };
    batch_to_py(py, &scene, &name, &seeds, rows, execution)
}

/// The first failing session fails the call, naming its command.
fn first_failure(status: Vec<Result<(), WorldError>>) -> Result<(), Fail> {
    status.into_iter().collect::<Result<(), _>>()?;
    Ok(())
}

/// Runs sessions of a built-in learner, one per configuration, in
/// parallel lockstep groups without the GIL (as `e3d run --sessions N`
/// runs them). Returns their rows and the execution text.
fn run_builtin_batch(
    py: Python<'_>,
    scene: &PyScene,
    kind: LearnerKind,
    a: &SessionArgs,
    work: &Workload,
    configs: &[SessionConfig],
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(Vec<Rows>, String)> {
    // the learners run_session makes, kept to read E3D's final state
    let mut held = (0..configs.len())
        .map(|_| Held::new(scene, kind, &a.params, &a.target))
        .collect::<PyResult<Vec<Held>>>()?;
    let mut learners: Vec<Lent<'_>> = held
        .iter_mut()
        .map(|h| Lent(h.symbols().expect("a learner of symbols")))
        .collect();
    let (records, metrics, execution) = unlocked(
        py,
        scene,
        work,
        &a.options,
        progress,
        work.trials,
        |exec, watch| {
            let mut records: Vec<SessionRecord> = {
                let probe = exec.world(1);
                configs
                    .iter()
                    .map(|c| SessionRecord::new(&*probe, c.trials))
                    .collect()
            };
            let status = watch.control(|control| {
                e3d::run_sessions(&exec, &mut learners, configs, &mut records, control)
            });
            first_failure(status)?;
            let metrics: Vec<Metrics> = records
                .iter()
                .map(|r| symbol_metrics(&exec, r, &a.target))
                .collect();
            let exact: Vec<_> = learners.iter().map(|l| exact_of(&exec, l)).collect();
            Ok((records, (metrics, exact), execution_text(exec)))
        },
    )?;
    drop(learners);
    let rows = records
        .into_iter()
        .zip(metrics.0.into_iter().zip(metrics.1))
        .zip(&mut held)
        .map(|((r, (m, exact)), h)| {
            let l = h.symbols().map(|l| &*l as &dyn Learner);
            let mut rows = Rows::of_symbols(py, r, m, l, exact)?;
            final_e3d(&mut rows, h);
            Ok(rows)
        })
        .collect::<PyResult<_>>()?;
    Ok((rows, execution))
}

/// E3D's final `Q` and effect model into `rows` (other learners: none).
fn final_e3d(rows: &mut Rows, held: &mut Held) {
    if let Some(e) = held.e3d() {
        rows.q = Some((0..e.num_slots()).map(|s| e.q(s).to_vec()).collect());
        rows.effect_model = Some(e.effect_model().probs());
    }
}

/// A held learner lent to the engine, which takes learners by value.
struct Lent<'a>(&'a mut (dyn Learner + Send));

impl Learner for Lent<'_> {
    fn name(&self) -> &str {
        self.0.name()
    }
    fn propose(&mut self, rng: &mut e3d::SessionRng, command: &mut e3d::Command) {
        self.0.propose(rng, command)
    }
    fn learn(&mut self, command: &e3d::Command, outcome: &e3d::Outcome) {
        self.0.learn(command, outcome)
    }
    fn slot_policy(&self, slot: usize) -> Option<Vec<f64>> {
        self.0.slot_policy(slot)
    }
}
