//! Errors: the package's exceptions, and the library's errors made Python
//! exceptions with the CLI's text.

use e3d::sweep::SweepError;
use e3d::{LearnerKind, WorldError};
use pyo3::create_exception;
use pyo3::exceptions::{PyOverflowError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    e3d,
    SceneError,
    PyValueError,
    "A scene or sweep file (or text) that cannot be used; the message names the file, line and column, as the CLI does, and the attributes `file`, `line`, `column` (1-based) and `field` (the field at fault, for a value out of range) hold them, each None where the error has none."
);
create_exception!(
    e3d,
    SimulationError,
    PyRuntimeError,
    "A command whose simulation failed (for example a physics blow-up); the message names the scene and the command."
);

/// A failure inside code that runs without the GIL, made a Python
/// exception once the GIL is back.
pub(crate) enum Fail {
    Value(String),
    Scene(e3d::SceneError),
    Simulation(String),
    Runtime(String),
    Os(String),
}

impl From<Fail> for PyErr {
    fn from(f: Fail) -> PyErr {
        match f {
            Fail::Value(m) => PyValueError::new_err(m),
            Fail::Scene(e) => scene_err(e),
            Fail::Simulation(m) => SimulationError::new_err(m),
            Fail::Runtime(m) => PyRuntimeError::new_err(m),
            Fail::Os(m) => pyo3::exceptions::PyOSError::new_err(m),
        }
    }
}

impl From<WorldError> for Fail {
    fn from(e: WorldError) -> Fail {
        match e {
            WorldError::BadCommand { .. } => Fail::Value(e.to_string()),
            _ => Fail::Simulation(e.to_string()),
        }
    }
}

impl From<SweepError> for Fail {
    fn from(e: SweepError) -> Fail {
        match e {
            SweepError::Input(s) => Fail::Scene(s),
            SweepError::World(w) => w.into(),
            SweepError::Io { .. } | SweepError::Output(_) => Fail::Os(e.to_string()),
            _ => Fail::Runtime(e.to_string()),
        }
    }
}

/// The library's scene error as a `SceneError` whose attributes hold its
/// parts: `file`, `line`, `column`, `field`.
pub(crate) fn scene_err(e: e3d::SceneError) -> PyErr {
    let (line, column) = e.position().unzip();
    let field = e.field().map(str::to_string);
    scene_error(e.to_string(), Some(e.file()), line, column, field)
}

/// A `SceneError` with its attributes set (None where not known).
pub(crate) fn scene_error(
    message: String,
    file: Option<&str>,
    line: Option<usize>,
    column: Option<usize>,
    field: Option<String>,
) -> PyErr {
    Python::attach(|py| {
        let err = SceneError::new_err(message);
        let v = err.value(py);
        // setting attributes on a fresh exception object cannot fail but
        // for memory; the message alone is still right then
        let _ = v.setattr("file", file);
        let _ = v.setattr("line", line);
        let _ = v.setattr("column", column);
        let _ = v.setattr("field", field);
        err
    })
}

/// Sets the class attributes of `SceneError` (None), so that an error
/// raised by Python code has them too.
pub(crate) fn scene_error_defaults(py: Python<'_>) -> PyResult<()> {
    let t = py.get_type::<SceneError>();
    for name in ["file", "line", "column", "field"] {
        t.setattr(name, py.None())?;
    }
    Ok(())
}

/// The built-in learners' names, the library's list, joined for messages:
/// `"e3d", "uniform", ...`.
pub(crate) fn learner_names() -> String {
    LearnerKind::ALL
        .map(|k| format!("\"{}\"", k.as_str()))
        .join(", ")
}

/// An integer argument `name` of at least `min`: an int or numpy integer
/// in `[min, 2^64 - 1]` (`_args.integer`: `ValueError` naming the
/// argument out of range, `TypeError` for a float, str, bool or array).
pub(crate) fn int_arg(obj: &Bound<'_, PyAny>, name: &str, min: u64) -> PyResult<u64> {
    // the common case without a call into Python (`SessionRng.integers`)
    if obj.is_exact_instance_of::<pyo3::types::PyInt>() {
        if let Ok(v) = obj.extract::<u64>() {
            if v >= min {
                return Ok(v);
            }
        }
    }
    let args = obj.py().import("e3d._args")?;
    args.call_method1("integer", (name, obj, min))?.extract()
}

/// `int_arg` as `usize`.
pub(crate) fn usize_arg(obj: &Bound<'_, PyAny>, name: &str, min: u64) -> PyResult<usize> {
    let v = int_arg(obj, name, min)?;
    usize::try_from(v)
        .map_err(|_| PyValueError::new_err(format!("{name} = {v}: too large for this machine")))
}

/// The most trials (or episode commands) one call returns in its records,
/// all sessions together: 10^8 (about 2.5 GB of arrays).
pub(crate) const MAX_HELD_TRIALS: u64 = 100_000_000;

/// Refuses `sessions` sessions of `per_session` trials (or episode
/// commands) each when their records together would pass
/// [`MAX_HELD_TRIALS`]: `what` names the arguments.
pub(crate) fn check_held(what: &str, sessions: usize, per_session: usize) -> PyResult<()> {
    match (sessions as u64).checked_mul(per_session as u64) {
        Some(n) if n <= MAX_HELD_TRIALS => Ok(()),
        _ => Err(PyValueError::new_err(format!(
            "{what}: {sessions} sessions of {per_session} trials each: at most {MAX_HELD_TRIALS} trials in all (the records returned are held in memory; e3d run --sessions writes them as it goes)"
        ))),
    }
}

/// Raises `MemoryError` when `bytes` cannot be allocated, before any work:
/// the records of a session are allocated as it runs, and an allocation
/// that fails there aborts the interpreter (`run_session(trials=10**8)` on
/// a small machine). The memory is asked for (`try_reserve`) and given
/// back at once; `what` names the arguments.
pub(crate) fn reserve_records(what: &str, bytes: u64) -> PyResult<()> {
    let mut probe: Vec<u8> = Vec::new();
    let fits = usize::try_from(bytes)
        .ok()
        .is_some_and(|b| probe.try_reserve_exact(b).is_ok());
    if !fits {
        return Err(pyo3::exceptions::PyMemoryError::new_err(format!(
            "{what}: the records would take about {} MB, which cannot be allocated here; run fewer trials (or sessions), or use `e3d run --out`, which writes them as it goes",
            bytes >> 20
        )));
    }
    Ok(())
}

/// The name of `obj`'s type, for messages (`found str`).
pub(crate) fn type_name(obj: &Bound<'_, PyAny>) -> String {
    obj.get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_default()
}

/// `k` of `Learner`: an integer >= 1, for `from_py_with` (pyo3 names the
/// argument in a `TypeError`: `argument 'k': expected an integer, ...`).
pub(crate) fn k_arg(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    usize_arg(obj, "k", 1).map_err(|e| {
        let text = e.value(obj.py()).to_string();
        match text.strip_prefix("k: ") {
            Some(rest) if e.is_instance_of::<PyTypeError>(obj.py()) => {
                PyTypeError::new_err(rest.to_string())
            }
            _ => e,
        }
    })
}

/// A float argument (`from_py_with`): an int too large for a float
/// (`10**400`) is an infinity of its sign, which the argument's range check
/// refuses by name, not Python's bare `OverflowError`; anything but a
/// number is a `TypeError` (`argument 'alpha': expected a number, found str`).
pub(crate) fn float_arg(obj: &Bound<'_, PyAny>) -> PyResult<f64> {
    match obj.extract::<f64>() {
        Err(e) if e.is_instance_of::<PyOverflowError>(obj.py()) => Ok(if obj.lt(0)? {
            f64::NEG_INFINITY
        } else {
            f64::INFINITY
        }),
        Err(e) if e.get_type(obj.py()).is(obj.py().get_type::<PyTypeError>()) => Err(
            PyTypeError::new_err(format!("expected a number, found {}", type_name(obj))),
        ),
        r => r,
    }
}

/// A float argument `name` that must be finite (a reward): a `TypeError`
/// for a non-number, a `ValueError` naming it for NaN or an infinity.
pub(crate) fn finite_arg(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<f64> {
    let args = obj.py().import("e3d._args")?;
    let v: f64 = args.call_method1("number", (name, obj))?.extract()?;
    if !v.is_finite() {
        return Err(PyValueError::new_err(format!(
            "{name} = {v}: expected a finite number"
        )));
    }
    Ok(v)
}

/// The error text of work stopped on request (Ctrl-C, a failed callback).
pub(crate) const STOPPED: &str = "stopped";

/// The hyper-parameters by the library's names, as `e3d._args.hyper` gives
/// them (`k` an integer as a float), those not given the paper's task 1,
/// checked by the library.
pub(crate) fn params_of(named: std::collections::HashMap<String, f64>) -> PyResult<e3d::Params> {
    let mut p = e3d::Params::TASK1;
    for (name, v) in named {
        *match name.as_str() {
            "alpha" => &mut p.alpha,
            "beta" => &mut p.beta,
            "lambda" => &mut p.lambda,
            "eta" => &mut p.eta,
            "epsilon" => &mut p.epsilon,
            "sigma" => &mut p.sigma,
            "rarity" => &mut p.rarity,
            "goal_progress" => &mut p.goal_progress,
            "initial" => &mut p.initial,
            "k" => {
                p.k = v as usize;
                continue;
            }
            _ => return Err(PyTypeError::new_err(format!("no hyper-parameter `{name}`"))),
        } = v;
    }
    checked(p)
}

/// `p` if its values are in range, else the library's message naming
/// Python's `lambda_`.
pub(crate) fn checked(p: e3d::Params) -> PyResult<e3d::Params> {
    p.validate().map_err(|e| {
        let msg = e.to_string();
        PyValueError::new_err(match msg.strip_prefix("lambda ") {
            Some(rest) => format!("lambda_ {rest}"),
            None => msg,
        })
    })?;
    Ok(p)
}

/// Whose hyper-parameters a call's `alpha` ... `epsilon` would be (see
/// [`warn_unread`]).
pub(crate) enum Reader {
    /// A built-in learner made by the call: it reads its
    /// [`LearnerKind::params`].
    Kind(LearnerKind),
    /// An `e3d.Learner`: it keeps the parameters it was made with.
    State,
    /// A learner object: it holds its own.
    Object,
}

/// Warns (`UserWarning`, at the caller's line: `level` 1 for a call from
/// the user's code, 2 through a function of the package) for every
/// hyper-parameter given a value other than its default (`Params::TASK1`,
/// the signatures' defaults) that `reader` does not read. The call goes
/// on, as the CLI's note says and as a sweep spans only the parameters
/// its learner uses.
pub(crate) fn warn_unread(
    py: Python<'_>,
    reader: Reader,
    params: &e3d::Params,
    level: i32,
) -> PyResult<()> {
    let (reads, why): (&[&str], String) = match reader {
        Reader::Kind(kind) => {
            let reads = kind.params();
            let list = match reads {
                [] => "no hyper-parameter".to_string(),
                r => r
                    .iter()
                    .map(|n| python_name(n))
                    .collect::<Vec<_>>()
                    .join(", "),
            };
            (reads, format!("learner {kind} reads {list}"))
        }
        Reader::State => (
            &[],
            "an e3d.Learner keeps the parameters it was made with".into(),
        ),
        Reader::Object => (&[], "a learner object holds its own parameters".into()),
    };
    let given = params.named().into_iter().zip(e3d::Params::TASK1.named());
    for ((name, v), (_, default)) in given {
        if v != default && !reads.contains(&name) {
            let msg = format!("{} = {v} does nothing: {why}", python_name(name));
            warn(py, &msg, level)?;
        }
    }
    Ok(())
}

/// Warns when a `gamma` other than the default is given open loop, which
/// has no discount (checked all the same: see `check_gamma`).
pub(crate) fn warn_open_loop_gamma(
    py: Python<'_>,
    closed_loop: bool,
    gamma: f64,
    level: i32,
) -> PyResult<()> {
    if !closed_loop && gamma != e3d::learner::ClosedLoopE3d::GAMMA {
        warn(
            py,
            &format!(
                "gamma = {gamma} does nothing: the open loop has no discount (closed_loop=False)"
            ),
            level,
        )?;
    }
    Ok(())
}

/// A hyper-parameter's name as Python's arguments spell it (`lambda_`).
fn python_name(name: &str) -> &str {
    if name == "lambda" {
        "lambda_"
    } else {
        name
    }
}

/// Issues a `UserWarning` with `msg`, `level` frames up (1: the caller's).
pub(crate) fn warn(py: Python<'_>, msg: &str, level: i32) -> PyResult<()> {
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    let msg = std::ffi::CString::new(msg).unwrap_or_default();
    PyErr::warn(py, &category, &msg, level)
}
