//! The `e3d._e3d` extension module: Python bindings of the e3d library.
//!
//! Everything is the Rust library's: scenes are parsed and checked by
//! [`e3d::Scene`], commands executed by its worlds (multi-copy Rapier worlds
//! in parallel, each command simulated once per [`World`] object through an
//! [`OutcomeMemo`]), sessions run by [`e3d::run_session_into`] on the world
//! an [`Executor`] chooses, sweeps by [`e3d::Sweep::run`]. This file only
//! converts: numpy arrays in and out, errors into Python exceptions with
//! the CLI's text.

use e3d::scene::WorldSpec;
use e3d::sweep::{DirOptions, Shard};
use e3d::world::{
    ExecOptions, Executor, Memoized, OutcomeMemo, Strategy, Workload, DEFAULT_MEMO_CAP,
    TABLE_COPIES,
};
use e3d::{
    Command, CommandSpace, Learner, LearnerKind, Metrics, Outcome, Params, PhysicsWorld,
    SessionConfig, SessionRecord, SessionRng, Sweep, SweepError, Target, World, WorldError,
};
use numpy::ndarray::{Array2, ArrayView2};
use numpy::{
    IntoPyArray, PyArray1, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString, PyTuple};
use rayon::prelude::*;

mod progress;
use progress::{watched, Throttle, Watch};
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

create_exception!(
    e3d,
    SceneError,
    PyValueError,
    "A scene or sweep file (or text) that cannot be used; the message names the file, line and column, as the CLI does."
);
create_exception!(
    e3d,
    SimulationError,
    PyRuntimeError,
    "A command whose simulation failed (for example a physics blow-up); the message names the scene and the command."
);

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

/// A failure inside code that runs without the GIL, made a Python
/// exception once the GIL is back.
enum Fail {
    Value(String),
    Scene(String),
    Simulation(String),
    Runtime(String),
    Os(String),
}

impl From<Fail> for PyErr {
    fn from(f: Fail) -> PyErr {
        match f {
            Fail::Value(m) => PyValueError::new_err(m),
            Fail::Scene(m) => SceneError::new_err(m),
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
            SweepError::Input(_) => Fail::Scene(e.to_string()),
            SweepError::World(w) => w.into(),
            SweepError::Io { .. } | SweepError::Output(_) => Fail::Os(e.to_string()),
            _ => Fail::Runtime(e.to_string()),
        }
    }
}

fn scene_err(e: e3d::SceneError) -> PyErr {
    SceneError::new_err(e.to_string())
}

// ---------------------------------------------------------------------------
// Commands in: strings, lists or numpy arrays
// ---------------------------------------------------------------------------

/// Checks one row of symbols against the space.
fn check_row(space: &CommandSpace, row: usize, symbols: &[i64]) -> PyResult<Command> {
    let mut out = Vec::with_capacity(symbols.len());
    for (slot, (&s, k)) in symbols.iter().zip(space.sizes()).enumerate() {
        if s < 0 || s as usize >= k {
            let alphabet: String = space.alphabet(slot).iter().collect();
            return Err(PyValueError::new_err(format!(
                "row {row}: symbol {s} at slot {slot} is out of range: slot {slot} has {k} symbols ({alphabet}), indices 0 to {}",
                k - 1
            )));
        }
        out.push(s as u8);
    }
    Ok(Command::new(out))
}

fn check_view(space: &CommandSpace, view: ArrayView2<'_, u8>) -> PyResult<Vec<Command>> {
    let sizes: Vec<usize> = space.sizes().collect();
    let mut out = Vec::with_capacity(view.nrows());
    for (i, row) in view.rows().into_iter().enumerate() {
        let symbols: Vec<u8> = row.iter().copied().collect();
        if symbols.iter().zip(&sizes).any(|(&s, &k)| s as usize >= k) {
            // the message names the first symbol out of range
            let wide: Vec<i64> = symbols.iter().map(|&s| s as i64).collect();
            check_row(space, i, &wide)?;
        }
        out.push(Command::new(symbols));
    }
    Ok(out)
}

/// Commands from a Python object: a command string, a list of command
/// strings, or an integer array (numpy, or anything `numpy.asarray` takes)
/// of shape `[slots]` (`ndim == 1`) or `[N, slots]` (`ndim == 2`).
fn commands_from(
    py: Python<'_>,
    space: &CommandSpace,
    obj: &Bound<'_, PyAny>,
    ndim: usize,
) -> PyResult<Vec<Command>> {
    let parse = |text: &str| {
        space
            .parse(text)
            .map_err(|e| PyValueError::new_err(e.to_string()))
    };
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(vec![parse(&s.to_cow()?)?]);
    }
    if ndim == 2 && (obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>()) {
        let items: Vec<Bound<'_, PyAny>> = obj.try_iter()?.collect::<PyResult<_>>()?;
        if !items.is_empty() && items.iter().all(|i| i.is_instance_of::<PyString>()) {
            return items
                .iter()
                .map(|i| parse(&i.cast::<PyString>()?.to_cow()?))
                .collect();
        }
    }
    let array: Bound<'_, PyUntypedArray> = match obj.cast::<PyUntypedArray>() {
        Ok(a) => a.clone(),
        Err(_) => {
            let np = py.import("numpy")?;
            let a = np.call_method1("asarray", (obj,)).map_err(|e| {
                PyValueError::new_err(format!(
                    "expected commands as an integer array, a command string or a list of them: {e}"
                ))
            })?;
            a.cast_into::<PyUntypedArray>()
                .map_err(|e| PyValueError::new_err(e.to_string()))?
        }
    };
    let shape = array.shape().to_vec();
    let what = if ndim == 1 {
        format!("one command, an array of shape [{}]", space.num_slots())
    } else {
        format!(
            "an array of shape [N, {}] (one command per row)",
            space.num_slots()
        )
    };
    if array.ndim() != ndim {
        return Err(PyValueError::new_err(format!(
            "expected {what}, found an array of {} dimension(s), shape {shape:?}",
            array.ndim()
        )));
    }
    if shape[ndim - 1] != space.num_slots() {
        return Err(PyValueError::new_err(format!(
            "expected {what}, found shape {shape:?}: the scene's commands have {} slots",
            space.num_slots()
        )));
    }
    let dtype = array.dtype();
    let kind = dtype.kind();
    if kind != b'u' && kind != b'i' {
        return Err(PyValueError::new_err(format!(
            "expected an integer array of symbol indices (dtype uint8, as Scene.parse returns), found dtype {}",
            dtype.str()?
        )));
    }
    let rows = if ndim == 1 { 1 } else { shape[0] };
    if dtype.is_equiv_to(&numpy::dtype::<u8>(py)) {
        let a = array.cast::<PyArrayDyn<u8>>()?.readonly();
        let view = a.as_array();
        if let Ok(v) = view.view().into_shape_with_order((rows, space.num_slots())) {
            return check_view(space, v);
        }
        // a layout that is not C-contiguous (a transposed or reversed
        // view): copied in logical order
        let flat: Vec<u8> = view.iter().copied().collect();
        let owned = Array2::from_shape_vec((rows, space.num_slots()), flat).expect("same size");
        return check_view(space, owned.view());
    }
    let wide = array.call_method1("astype", ("int64",))?;
    let a = wide.cast::<PyArrayDyn<i64>>()?.readonly();
    let flat: Vec<i64> = a.as_array().iter().copied().collect();
    flat.chunks(space.num_slots().max(1))
        .take(rows)
        .enumerate()
        .map(|(i, r)| check_row(space, i, r))
        .collect()
}

/// A scene given as a `Scene` or as a path / built-in name.
fn scene_of(obj: &Bound<'_, PyAny>) -> PyResult<PyScene> {
    if let Ok(s) = obj.cast::<PyScene>() {
        return Ok(s.get().clone());
    }
    if let Ok(p) = obj.extract::<PathBuf>() {
        return PyScene::resolve(&p.to_string_lossy());
    }
    Err(PyTypeError::new_err(
        "expected a Scene, or a scene file's path or a built-in scene's name",
    ))
}

// ---------------------------------------------------------------------------
// Scene
// ---------------------------------------------------------------------------

/// A parsed and validated scene: a world, a command schema (slots and
/// their alphabets), effects (cells of a grid) and a reward.
///
/// Make one with `Scene.load(path)`, `Scene.builtin(name)`,
/// `Scene.resolve(path_or_name)` or `Scene.from_text(text)`.
#[pyclass(module = "e3d", name = "Scene", frozen)]
#[derive(Clone)]
struct PyScene {
    inner: Arc<e3d::Scene>,
    space: CommandSpace,
}

impl PyScene {
    /// The scene, if its slots take symbols: continuous scenes are not
    /// wrapped yet (they run from the CLI and the Rust library).
    fn new(scene: e3d::Scene) -> Result<PyScene, e3d::SceneError> {
        scene.require_symbols("the Python package (continuous commands run from the CLI and the Rust library)")?;
        Ok(PyScene {
            space: scene.command_space(),
            inner: Arc::new(scene),
        })
    }
}

#[pymethods]
impl PyScene {
    /// Loads and validates a scene file (`.ron`). Raises `SceneError` with
    /// `file:line:col: message`, the CLI's text.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<PyScene> {
        e3d::Scene::load(&path)
            .and_then(PyScene::new)
            .map_err(scene_err)
    }

    /// A scene shipped with e3d, by name (see `Scene.builtins()`).
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<PyScene> {
        let scene = e3d::Scene::builtin(name).ok_or_else(|| {
            SceneError::new_err(format!(
                "{name}: no built-in scene of that name; expected one of: {}",
                builtin_names().join(", ")
            ))
        })?;
        PyScene::new(scene).map_err(scene_err)
    }

    /// A scene by path, or by the name of a built-in scene when no such
    /// file exists (what the CLI's SCENE arguments accept).
    #[staticmethod]
    fn resolve(path_or_name: &str) -> PyResult<PyScene> {
        e3d::Scene::resolve(path_or_name)
            .and_then(PyScene::new)
            .map_err(scene_err)
    }

    /// Parses and validates scene text; `file` names it in errors.
    #[staticmethod]
    #[pyo3(signature = (text, file = "<string>"))]
    fn from_text(text: &str, file: &str) -> PyResult<PyScene> {
        e3d::Scene::parse(text, file)
            .and_then(PyScene::new)
            .map_err(scene_err)
    }

    /// The names of the built-in scenes.
    #[staticmethod]
    fn builtins() -> Vec<&'static str> {
        builtin_names()
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }

    /// The scene's description.
    #[getter]
    fn description(&self) -> &str {
        &self.inner.description
    }

    /// `"grid"` or `"physics"`.
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner.world {
            WorldSpec::Grid(_) => "grid",
            WorldSpec::Physics(_) => "physics",
        }
    }

    /// The number of slots of a command.
    #[getter]
    fn num_slots(&self) -> usize {
        self.space.num_slots()
    }

    /// The alphabet size of each slot.
    #[getter]
    fn alphabet_sizes(&self) -> Vec<usize> {
        self.space.sizes().collect()
    }

    /// The alphabet of each slot, as a string of its symbols.
    #[getter]
    fn alphabets(&self) -> Vec<String> {
        (0..self.space.num_slots())
            .map(|s| self.space.alphabet(s).iter().collect())
            .collect()
    }

    /// The number of effects (cells of the effect grid).
    #[getter]
    fn num_effects(&self) -> usize {
        self.inner.num_effects()
    }

    /// The effect grid: `(rows, cols, (xmin, ymin), (xmax, ymax))`.
    #[getter]
    fn effect_grid(&self) -> (usize, usize, (f64, f64), (f64, f64)) {
        let g = self.inner.effect_grid();
        (g.rows, g.cols, (g.min[0], g.min[1]), (g.max[0], g.max[1]))
    }

    /// The number of distinct commands, or `None` beyond 2^64.
    #[getter]
    fn num_commands(&self) -> Option<u64> {
        self.space.num_commands()
    }

    /// The effect of the start state: the cell of the tracked point (or of
    /// the agent) before any command.
    #[getter]
    fn start_effect(&self) -> usize {
        let g = self.inner.effect_grid();
        match &self.inner.world {
            WorldSpec::Grid(spec) => g.effect_of(g.center(spec.start.0, spec.start.1)),
            WorldSpec::Physics(p) => {
                let b = p.body(&p.effect.body).expect("validated: tracked body");
                let t = e3d::scene::physics::to_world_point(b.position, b.angle, p.effect.point);
                g.effect_of([t.0, t.1])
            }
        }
    }

    /// The reward of each effect, a float64 array of `num_effects`.
    fn reward_table<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.reward_table().into_pyarray(py)
    }

    /// Commands written as symbols (a string, or a list of strings) as a
    /// uint8 array of shape `[N, num_slots]` of symbol indices.
    fn parse<'py>(
        &self,
        py: Python<'py>,
        commands: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<u8>>> {
        let texts: Vec<String> = if let Ok(s) = commands.cast::<PyString>() {
            vec![s.to_cow()?.into_owned()]
        } else {
            commands.extract().map_err(|_| {
                PyTypeError::new_err("expected a command string or a list of command strings")
            })?
        };
        let n = self.space.num_slots();
        let mut flat = Vec::with_capacity(texts.len() * n);
        for t in &texts {
            let c = self
                .space
                .parse(t)
                .map_err(|e| PyValueError::new_err(e.to_string()))?;
            flat.extend_from_slice(&c.symbols);
        }
        let a = Array2::from_shape_vec((texts.len(), n), flat).expect("n symbols a row");
        Ok(a.into_pyarray(py))
    }

    /// Commands (an array `[N, slots]` or `[slots]` of symbol indices) as
    /// strings: a list for a 2-D array, one string for a 1-D one.
    fn format(&self, py: Python<'_>, commands: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let one = commands
            .cast::<PyUntypedArray>()
            .map(|a| a.ndim() == 1)
            .unwrap_or(false)
            || commands
                .extract::<Vec<i64>>()
                .map(|_| true)
                .unwrap_or(false);
        let cs = commands_from(py, &self.space, commands, if one { 1 } else { 2 })?;
        let texts: Vec<String> = cs.iter().map(|c| self.space.format(c)).collect();
        if one {
            Ok(texts[0].clone().into_pyobject(py)?.into_any().unbind())
        } else {
            Ok(texts.into_pyobject(py)?.into_any().unbind())
        }
    }

    /// A world that executes this scene's commands (see `World`).
    fn world(&self) -> PyWorld {
        PyWorld::new(self.clone())
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}: {}, {} slots, {} effects)",
            self.inner.name,
            self.kind(),
            self.space.num_slots(),
            self.inner.num_effects()
        )
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyScene>()
            .map(|o| *o.get().inner == *self.inner)
            .unwrap_or(false)
    }
}

/// The built-in scenes of symbols (continuous ones are not wrapped yet).
fn builtin_names() -> Vec<&'static str> {
    e3d::scene::BUILTIN
        .iter()
        .map(|(n, _)| *n)
        .filter(|n| e3d::Scene::builtin(n).is_some_and(|s| !s.is_continuous()))
        .collect()
}

// ---------------------------------------------------------------------------
// World
// ---------------------------------------------------------------------------

/// The outcome of one command: `effect` (int), `reward` (float) and the
/// terminal point `x`, `y` (metres).
#[pyclass(module = "e3d", name = "Outcome", frozen, get_all)]
#[derive(Clone)]
struct PyOutcome {
    effect: usize,
    reward: f64,
    x: f64,
    y: f64,
}

#[pymethods]
impl PyOutcome {
    fn __repr__(&self) -> String {
        format!(
            "Outcome(effect={}, reward={:?}, x={:?}, y={:?})",
            self.effect, self.reward, self.x, self.y
        )
    }
    fn __eq__(&self, o: &Self) -> bool {
        (self.effect, self.reward, self.x, self.y) == (o.effect, o.reward, o.x, o.y)
    }
}

/// The outcomes of a batch of commands, one entry per row, as numpy
/// arrays: `effect` (int64), `reward`, `x`, `y` (float64).
#[pyclass(module = "e3d", name = "BatchOutcome", frozen, get_all)]
struct PyBatch {
    effect: Py<PyArray1<i64>>,
    reward: Py<PyArray1<f64>>,
    x: Py<PyArray1<f64>>,
    y: Py<PyArray1<f64>>,
}

#[pymethods]
impl PyBatch {
    fn __len__(&self, py: Python<'_>) -> usize {
        self.effect.bind(py).len()
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        format!("BatchOutcome({} commands)", self.effect.bind(py).len())
    }
}

/// The whole motion of one command (`World.trace`), one row a frame (the
/// start, then every step): `time` (float64 `[F]`, seconds), per body
/// (`bodies`, the scene's order, fixed ones included) `x`, `y`, `angle`,
/// `vx`, `vy`, `omega` (float64 `[F, bodies]`), per joint (`joints`)
/// `joint_angle` (the child's rotation relative to its parent, 0 at the
/// start pose, radians in (-pi, pi]) and `joint_velocity` (float64
/// `[F, joints]`), and the command's `outcome`. `columns()` gives the
/// same as a dict of the CSV columns of `e3d scene exec --trace`.
#[pyclass(module = "e3d", name = "Motion", frozen, get_all)]
struct PyMotion {
    command: String,
    bodies: Vec<String>,
    joints: Vec<String>,
    time: Py<PyArray1<f64>>,
    x: Py<numpy::PyArray2<f64>>,
    y: Py<numpy::PyArray2<f64>>,
    angle: Py<numpy::PyArray2<f64>>,
    vx: Py<numpy::PyArray2<f64>>,
    vy: Py<numpy::PyArray2<f64>>,
    omega: Py<numpy::PyArray2<f64>>,
    joint_angle: Py<numpy::PyArray2<f64>>,
    joint_velocity: Py<numpy::PyArray2<f64>>,
    outcome: PyOutcome,
}

#[pymethods]
impl PyMotion {
    /// The number of frames (the start and every step).
    fn __len__(&self, py: Python<'_>) -> usize {
        self.time.bind(py).len()
    }

    /// The columns of `e3d scene exec --trace FILE.csv`, in its order:
    /// `step` (int64), `time`, then per body `NAME.x`, `NAME.y`,
    /// `NAME.angle`, `NAME.vx`, `NAME.vy`, `NAME.omega`, then per joint
    /// `NAME.angle`, `NAME.velocity` (float64 arrays `[F]`).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let out = PyDict::new(py);
        let frames = self.time.bind(py).len();
        let steps: Vec<i64> = (0..frames as i64).collect();
        out.set_item("step", steps.into_pyarray(py))?;
        out.set_item("time", self.time.bind(py).call_method0("copy")?)?;
        let per_body = [
            ("x", &self.x),
            ("y", &self.y),
            ("angle", &self.angle),
            ("vx", &self.vx),
            ("vy", &self.vy),
            ("omega", &self.omega),
        ];
        for (b, name) in self.bodies.iter().enumerate() {
            for (field, a) in &per_body {
                let col = a.bind(py).readonly().as_array().column(b).to_owned();
                out.set_item(format!("{name}.{field}"), col.into_pyarray(py))?;
            }
        }
        for (j, name) in self.joints.iter().enumerate() {
            for (field, a) in [
                ("angle", &self.joint_angle),
                ("velocity", &self.joint_velocity),
            ] {
                let col = a.bind(py).readonly().as_array().column(j).to_owned();
                out.set_item(format!("{name}.{field}"), col.into_pyarray(py))?;
            }
        }
        Ok(out)
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "Motion(command={:?}, {} frames, {} bodies, {} joints)",
            self.command,
            self.time.bind(py).len(),
            self.bodies.len(),
            self.joints.len()
        )
    }
}

fn motion_to_py(py: Python<'_>, command: String, m: e3d::world::Motion) -> PyResult<PyMotion> {
    let (f, b, j) = (m.frames.len(), m.bodies.len(), m.joints.len());
    let table = |cols: usize, value: &dyn Fn(&e3d::world::Frame, usize) -> f64| {
        let mut a = Array2::<f64>::zeros((f, cols));
        for (r, frame) in m.frames.iter().enumerate() {
            for c in 0..cols {
                a[[r, c]] = value(frame, c);
            }
        }
        a.into_pyarray(py).unbind()
    };
    let time: Vec<f64> = m.frames.iter().map(|fr| fr.time).collect();
    let o = m.outcome;
    Ok(PyMotion {
        command,
        time: time.into_pyarray(py).unbind(),
        x: table(b, &|fr, c| fr.poses[c].position[0]),
        y: table(b, &|fr, c| fr.poses[c].position[1]),
        angle: table(b, &|fr, c| fr.poses[c].angle),
        vx: table(b, &|fr, c| fr.velocities[c][0]),
        vy: table(b, &|fr, c| fr.velocities[c][1]),
        omega: table(b, &|fr, c| fr.velocities[c][2]),
        joint_angle: table(j, &|fr, c| fr.joint_angles[c]),
        joint_velocity: table(j, &|fr, c| fr.joint_velocities[c]),
        bodies: m.bodies,
        joints: m.joints,
        outcome: PyOutcome {
            effect: o.effect,
            reward: o.reward,
            x: o.point[0],
            y: o.point[1],
        },
    })
}

/// Executes a scene's commands open loop from its start state; made by
/// `Scene.world()`.
///
/// Each world object keeps the outcome of every command it executed (an
/// outcome memo), so no command is simulated twice; `execute_batch` runs
/// the new commands of a batch in parallel on every core, many at once
/// per Rapier world where that is exact, without the GIL. The outcomes
/// are those of `e3d scene exec`, bit for bit.
#[pyclass(module = "e3d", name = "World", frozen)]
struct PyWorld {
    scene: PyScene,
    memo: OutcomeMemo,
    copies: usize,
    idle: Mutex<Vec<Box<dyn World + Send>>>,
    /// A single-copy Rapier world for `trace`, built on its first use.
    tracer: Mutex<Option<PhysicsWorld>>,
}

impl PyWorld {
    fn new(scene: PyScene) -> PyWorld {
        let copies = match &scene.inner.world {
            WorldSpec::Physics(p) if p.copies_are_exact() => TABLE_COPIES,
            _ => 1,
        };
        // a space of more than 2^64 commands cannot be indexed: its memo
        // is refused, and such a world keeps nothing (cap 0 never fills)
        let memo = OutcomeMemo::new(&scene.space, scene.inner.num_effects(), DEFAULT_MEMO_CAP)
            .unwrap_or_else(|_| {
                let tiny = CommandSpace::repeat(1, &['0']).expect("valid");
                OutcomeMemo::new(&tiny, 1, 0).expect("small")
            });
        PyWorld {
            scene,
            memo,
            copies,
            idle: Mutex::new(Vec::new()),
            tracer: Mutex::new(None),
        }
    }

    fn take(&self) -> Box<dyn World + Send> {
        let kept = self.idle.lock().unwrap_or_else(|e| e.into_inner()).pop();
        kept.unwrap_or_else(|| match &self.scene.inner.world {
            WorldSpec::Physics(p) if self.copies > 1 => {
                Box::new(PhysicsWorld::with_copies(&self.scene.inner, p, self.copies))
            }
            _ => self.scene.inner.build(),
        })
    }

    fn give(&self, w: Box<dyn World + Send>) {
        self.idle.lock().unwrap_or_else(|e| e.into_inner()).push(w);
    }

    fn memoised(&self) -> bool {
        self.scene.space.num_commands().is_some()
    }

    /// The outcome of each command, in order (the first failure, in input
    /// order, instead): each distinct command (a mirror-image pair counts
    /// once) looked up or simulated once, the new ones in parallel.
    ///
    /// With a `watch`, each piece adds its commands to `watch.done` (a
    /// repeated command counts as done at once), and once the watch is
    /// cancelled the pieces not yet started are skipped (the call fails).
    fn run(&self, commands: &[Command], watch: Option<&Watch>) -> Result<Vec<Outcome>, WorldError> {
        let space = &self.scene.space;
        let keyer = self.take();
        // (index of the distinct command, whether it is the mirror image)
        let mut slot: Vec<(usize, bool)> = Vec::with_capacity(commands.len());
        let mut unique: Vec<Command> = Vec::new();
        if self.memoised() {
            let mut first: HashMap<u64, usize> = HashMap::new();
            for c in commands {
                let own = space.index_of(c);
                let key = keyer.mirror_of(c).map_or(own, |m| space.index_of(&m));
                let k = *first.entry(key).or_insert_with(|| {
                    unique.push(c.clone());
                    unique.len() - 1
                });
                slot.push((k, space.index_of(&unique[k]) != own));
            }
        } else {
            unique = commands.to_vec();
            slot.extend((0..commands.len()).map(|k| (k, false)));
        }
        if let Some(w) = watch {
            w.base
                .store((commands.len() - unique.len()) as u64, Ordering::Relaxed);
        }
        let piece = unique
            .len()
            .div_ceil(rayon::current_num_threads())
            .clamp(1, self.copies);
        let parts: Vec<Vec<Result<Outcome, WorldError>>> = unique
            .par_chunks(piece)
            .map(|part| {
                if watch.is_some_and(Watch::cancelled) {
                    return vec![Err(WorldError::Other(STOPPED.into())); part.len()];
                }
                let mut out = Vec::with_capacity(part.len());
                if self.memoised() {
                    let mut w = Memoized::new(self.take(), &self.memo);
                    w.execute_batch(part, &mut out);
                    self.give(w.into_inner());
                } else {
                    let mut w = self.take();
                    w.execute_batch(part, &mut out);
                    self.give(w);
                }
                if let Some(w) = watch {
                    w.add(part.len() as u64);
                }
                out
            })
            .collect();
        let results: Vec<Result<Outcome, WorldError>> = parts.into_iter().flatten().collect();
        let mut out = Vec::with_capacity(commands.len());
        for (c, &(k, mirrored)) in commands.iter().zip(&slot) {
            match &results[k] {
                Ok(o) if mirrored => out.push(keyer.mirror_outcome(*o)),
                Ok(o) => out.push(*o),
                // the error as the world words it for this very command
                Err(e) if mirrored => {
                    let mut w = self.take();
                    let r = w.execute(c);
                    self.give(w);
                    return Err(r.err().unwrap_or_else(|| e.clone()));
                }
                Err(e) => return Err(e.clone()),
            }
        }
        self.give(keyer);
        Ok(out)
    }
}

#[pymethods]
impl PyWorld {
    /// The scene.
    #[getter]
    fn scene(&self) -> PyScene {
        self.scene.clone()
    }

    /// Executes one command (a string of symbols, or an array of `slots`
    /// symbol indices) and returns its `Outcome`.
    fn execute(&self, py: Python<'_>, command: &Bound<'_, PyAny>) -> PyResult<PyOutcome> {
        let cs = commands_from(py, &self.scene.space, command, 1)?;
        let out = py.detach(|| self.run(&cs, None)).map_err(Fail::from)?;
        let o = out[0];
        Ok(PyOutcome {
            effect: o.effect,
            reward: o.reward,
            x: o.point[0],
            y: o.point[1],
        })
    }

    /// Executes a batch of commands, an integer array `[N, slots]` of
    /// symbol indices (uint8, as `Scene.parse` returns; other integer
    /// dtypes are converted) or a list of command strings, and returns a
    /// `BatchOutcome` of numpy arrays, one entry per row. Releases the GIL.
    /// `progress`: a callable, called as `progress(commands_done, N)` at
    /// most ten times a second and once at the end. Ctrl-C stops the batch
    /// and raises `KeyboardInterrupt` (the outcomes simulated so far are
    /// kept).
    #[pyo3(signature = (commands, progress = None))]
    fn execute_batch(
        &self,
        py: Python<'_>,
        commands: &Bound<'_, PyAny>,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<PyBatch> {
        let cs = commands_from(py, &self.scene.space, commands, 2)?;
        // a small batch is not worth a thread of its own (a memo hit costs
        // less than starting one)
        let out = if progress.is_none() && cs.len() <= 256 {
            py.detach(|| self.run(&cs, None))
        } else {
            let watch = Watch::new();
            watched(py, progress, cs.len() as u64, &watch, |w| {
                self.run(&cs, Some(w))
            })?
        }
        .map_err(Fail::from)?;
        let effect: Vec<i64> = out.iter().map(|o| o.effect as i64).collect();
        let reward: Vec<f64> = out.iter().map(|o| o.reward).collect();
        let x: Vec<f64> = out.iter().map(|o| o.point[0]).collect();
        let y: Vec<f64> = out.iter().map(|o| o.point[1]).collect();
        Ok(PyBatch {
            effect: effect.into_pyarray(py).unbind(),
            reward: reward.into_pyarray(py).unbind(),
            x: x.into_pyarray(py).unbind(),
            y: y.into_pyarray(py).unbind(),
        })
    }

    /// The whole motion of one command (a string, or an array of `slots`
    /// symbol indices) on a physics scene, as a `Motion`: the time, every
    /// body's pose and velocity, every joint's angle and angular velocity,
    /// at the start and after every step. The numbers of
    /// `e3d scene exec SCENE COMMAND --trace FILE.csv`. A grid scene raises
    /// `ValueError` (it has no motion).
    fn trace(&self, py: Python<'_>, command: &Bound<'_, PyAny>) -> PyResult<PyMotion> {
        let inner = &self.scene.inner;
        if matches!(inner.world, WorldSpec::Grid(_)) {
            return Err(PyValueError::new_err(format!(
                "scene `{}` is a grid: it has no motion to trace (`e3d scene render --command` draws a command's path)",
                inner.name
            )));
        }
        let cs = commands_from(py, &self.scene.space, command, 1)?;
        let text = self.scene.space.format(&cs[0]);
        let motion = py
            .detach(|| {
                let mut slot = self.tracer.lock().unwrap_or_else(|e| e.into_inner());
                let world =
                    slot.get_or_insert_with(|| inner.physics_world().expect("a physics scene"));
                world.motion(&cs[0])
            })
            .map_err(Fail::from)?;
        motion_to_py(py, text, motion)
    }

    /// How many commands' outcomes this world keeps (each simulated once).
    #[getter]
    fn memo_len(&self) -> usize {
        self.memo.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "World({:?}, {} outcomes kept)",
            self.scene.inner.name,
            self.memo.len()
        )
    }
}

// ---------------------------------------------------------------------------
// Sessions
// ---------------------------------------------------------------------------

/// The session's random generator, handed to a Python learner's
/// `propose(rng)`: the very generator the session was seeded with (PCG
/// 64-bit MCG), valid only during that call.
#[pyclass(module = "e3d", name = "SessionRng", unsendable)]
struct PyRng {
    inner: SessionRng,
}

#[pymethods]
impl PyRng {
    /// A float uniform in [0, 1).
    fn random(&mut self) -> f64 {
        use rand::RngExt;
        self.inner.random::<f64>()
    }

    /// An integer uniform in [0, n): the draw of the library's uniform
    /// policy for a slot of `n` symbols (rand's `random_range(0..n)` on
    /// `usize`).
    fn integers(&mut self, n: usize) -> PyResult<usize> {
        use rand::RngExt;
        if n == 0 {
            return Err(PyValueError::new_err("integers(n): n must be at least 1"));
        }
        Ok(self.inner.random_range(0..n))
    }

    /// An index drawn with probability proportional to `weights` (>= 0,
    /// not all 0), by one `random()` and a cumulative sum.
    fn choice(&mut self, weights: Vec<f64>) -> PyResult<usize> {
        use rand::RngExt;
        let total: f64 = weights.iter().sum();
        if weights.is_empty()
            || !total.is_finite()
            || total <= 0.0
            || weights.iter().any(|w| *w < 0.0)
        {
            return Err(PyValueError::new_err(
                "choice(weights): expected finite weights >= 0, not all 0",
            ));
        }
        let u = self.inner.random::<f64>() * total;
        let mut acc = 0.0;
        for (i, w) in weights.iter().enumerate() {
            acc += w;
            if u < acc {
                return Ok(i);
            }
        }
        Ok(weights.iter().rposition(|w| *w > 0.0).unwrap_or(0))
    }
}

/// A learner written in Python: an object with `propose(rng)` and
/// `learn(command, effect, reward)`. Its first exception stops the session
/// and is raised by `run_session`.
struct PyLearner<'py, 'a> {
    py: Python<'py>,
    obj: Bound<'py, PyAny>,
    rng: Bound<'py, PyRng>,
    space: CommandSpace,
    error: &'a RefCell<Option<PyErr>>,
}

impl<'py, 'a> PyLearner<'py, 'a> {
    fn new(
        py: Python<'py>,
        obj: Bound<'py, PyAny>,
        space: &CommandSpace,
        error: &'a RefCell<Option<PyErr>>,
    ) -> PyResult<Self> {
        let rng = Bound::new(
            py,
            PyRng {
                inner: rand::SeedableRng::seed_from_u64(0),
            },
        )?;
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
        std::mem::swap(&mut self.rng.borrow_mut().inner, rng);
        let r = self.obj.call_method1("propose", (self.rng.clone(),));
        std::mem::swap(&mut self.rng.borrow_mut().inner, rng);
        let r = r.and_then(|v| commands_from(self.py, &self.space, &v, 1));
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
struct Guarded<'a, W: ?Sized, S: Fn() -> bool> {
    world: &'a mut W,
    stop: S,
}

const STOPPED: &str = "stopped";

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

/// What a session recorded: `commands` (uint8 `[T, slots]`), `effects`
/// (int64 `[T]`), `rewards` (float64 `[T]`, 0 when the reward is not
/// used), `metrics` (a dict), and how outcomes were obtained (`execution`).
#[pyclass(module = "e3d", name = "SessionRecord", frozen, get_all)]
struct PyRecord {
    scene: String,
    learner: String,
    seed: u64,
    trials: usize,
    commands: Py<numpy::PyArray2<u8>>,
    effects: Py<PyArray1<i64>>,
    rewards: Py<PyArray1<f64>>,
    metrics: Py<PyDict>,
    execution: String,
}

#[pymethods]
impl PyRecord {
    fn __repr__(&self) -> String {
        format!(
            "SessionRecord(scene={:?}, learner={:?}, seed={}, trials={})",
            self.scene, self.learner, self.seed, self.trials
        )
    }
}

/// A session's metrics as a dict (`summary.json`'s names).
fn metrics_dict<'py>(py: Python<'py>, m: &Metrics) -> PyResult<Bound<'py, PyDict>> {
    let metrics = PyDict::new(py);
    metrics.set_item("normalized_entropy", m.normalized_entropy)?;
    metrics.set_item(
        "normalized_entropy_last_1000",
        m.normalized_entropy_last_1000,
    )?;
    metrics.set_item("kl_to_target", m.kl_to_target)?;
    metrics.set_item("distinct_effects", m.distinct_effects)?;
    metrics.set_item("cumulative_reward", m.cumulative_reward)?;
    metrics.set_item("first_reward_trial", m.first_reward_trial)?;
    metrics.set_item("trials", m.trials)?;
    Ok(metrics)
}

fn record_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    cfg: &SessionConfig,
    rec: SessionRecord,
    execution: String,
) -> PyResult<PyRecord> {
    let metrics = metrics_dict(py, &rec.metrics(&Target::Uniform))?;
    let t = rec.trials();
    let commands = Array2::from_shape_vec((t, rec.num_slots), rec.commands).expect("T x slots");
    let effects: Vec<i64> = rec.effects.iter().map(|&e| e as i64).collect();
    Ok(PyRecord {
        scene: scene.inner.name.clone(),
        learner: learner.to_string(),
        seed: cfg.seed,
        trials: t,
        commands: commands.into_pyarray(py).unbind(),
        effects: effects.into_pyarray(py).unbind(),
        rewards: rec.rewards.into_pyarray(py).unbind(),
        metrics: metrics.unbind(),
        execution,
    })
}

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
struct SessionArgs {
    params: Params,
    options: ExecOptions,
    use_reward: bool,
}

#[allow(clippy::too_many_arguments)]
fn session_args(
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
        ..Params::TASK1
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

/// A built-in learner's kind from `learner` (None: e3d), or `None` for a
/// Python object.
fn builtin_kind(learner: Option<&Bound<'_, PyAny>>) -> PyResult<Option<LearnerKind>> {
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
fn python_learner_name(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    for m in ["propose", "learn"] {
        if !obj.hasattr(m)? {
            return Err(PyTypeError::new_err(format!(
                "learner: expected \"e3d\", \"uniform\", \"egreedy\" or an object with propose(rng) and learn(command, effect, reward); this one has no `{m}`"
            )));
        }
    }
    Ok(obj
        .getattr("name")
        .and_then(|n| n.extract())
        .unwrap_or_else(|_| "python".to_string()))
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
fn run_session(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    learner: Option<&Bound<'_, PyAny>>,
    trials: usize,
    seed: u64,
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

/// Sessions of one scene run together, in lockstep (`run_sessions`):
/// per-session arrays stacked along a first axis of one entry a session.
/// `seeds` (uint64 `[S]`), `commands` (uint8 `[S, T, slots]`), `effects`
/// (int64 `[S, T]`), `rewards` (float64 `[S, T]`), `metrics` (a dict of
/// arrays `[S]`: float64, `distinct_effects` and `trials` int64,
/// `first_reward_trial` float64 with NaN for none, as in `run_sweep`).
/// `batch[i]` is session `i`'s `SessionRecord`.
#[pyclass(module = "e3d", name = "SessionBatch", frozen)]
struct PyBatchRecord {
    #[pyo3(get)]
    scene: String,
    #[pyo3(get)]
    learner: String,
    #[pyo3(get)]
    seeds: Py<PyArray1<u64>>,
    #[pyo3(get)]
    trials: usize,
    #[pyo3(get)]
    commands: Py<numpy::PyArray3<u8>>,
    #[pyo3(get)]
    effects: Py<numpy::PyArray2<i64>>,
    #[pyo3(get)]
    rewards: Py<numpy::PyArray2<f64>>,
    #[pyo3(get)]
    metrics: Py<PyDict>,
    #[pyo3(get)]
    execution: String,
    /// Each session's metrics, as `SessionRecord.metrics`.
    per_session: Vec<Py<PyDict>>,
}

#[pymethods]
impl PyBatchRecord {
    fn __len__(&self) -> usize {
        self.per_session.len()
    }

    /// Session `i`'s record, as `run_session(seed=seeds[i])` returns it
    /// (its arrays are views of this batch's).
    fn __getitem__(&self, py: Python<'_>, i: isize) -> PyResult<PyRecord> {
        let n = self.per_session.len() as isize;
        let k = if i < 0 { i + n } else { i };
        if k < 0 || k >= n {
            return Err(pyo3::exceptions::PyIndexError::new_err(format!(
                "session {i} out of range: {n} sessions"
            )));
        }
        let k = k as usize;
        let seed = self.seeds.bind(py).readonly().as_slice()?[k];
        Ok(PyRecord {
            scene: self.scene.clone(),
            learner: self.learner.clone(),
            seed,
            trials: self.trials,
            commands: self.commands.bind(py).get_item(k)?.cast_into()?.unbind(),
            effects: self.effects.bind(py).get_item(k)?.cast_into()?.unbind(),
            rewards: self.rewards.bind(py).get_item(k)?.cast_into()?.unbind(),
            metrics: self.per_session[k].bind(py).copy()?.unbind(),
            execution: self.execution.clone(),
        })
    }

    fn __repr__(&self, py: Python<'_>) -> String {
        let seeds = self.seeds.bind(py).readonly();
        let seeds = seeds.as_slice().unwrap_or(&[]);
        format!(
            "SessionBatch(scene={:?}, learner={:?}, {} sessions, seeds {:?}, trials={})",
            self.scene,
            self.learner,
            seeds.len(),
            seeds,
            self.trials
        )
    }
}

fn batch_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    seeds: &[u64],
    trials: usize,
    records: Vec<SessionRecord>,
    execution: String,
) -> PyResult<PyBatchRecord> {
    let s = records.len();
    let slots = scene.space.num_slots();
    let mut commands = Vec::with_capacity(s * trials * slots);
    let mut effects = Vec::with_capacity(s * trials);
    let mut rewards = Vec::with_capacity(s * trials);
    let mut per_session = Vec::with_capacity(s);
    let cols: [&str; 7] = [
        "normalized_entropy",
        "normalized_entropy_last_1000",
        "kl_to_target",
        "distinct_effects",
        "cumulative_reward",
        "first_reward_trial",
        "trials",
    ];
    let mut floats: Vec<Vec<f64>> = vec![Vec::with_capacity(s); cols.len()];
    for rec in &records {
        let m = rec.metrics(&Target::Uniform);
        per_session.push(metrics_dict(py, &m)?.unbind());
        let row = [
            m.normalized_entropy,
            m.normalized_entropy_last_1000,
            m.kl_to_target,
            m.distinct_effects as f64,
            m.cumulative_reward,
            m.first_reward_trial.map_or(f64::NAN, |t| t as f64),
            m.trials as f64,
        ];
        for (c, v) in floats.iter_mut().zip(row) {
            c.push(v);
        }
        commands.extend_from_slice(&rec.commands);
        effects.extend(rec.effects.iter().map(|&e| e as i64));
        rewards.extend_from_slice(&rec.rewards);
    }
    let metrics = PyDict::new(py);
    for (name, v) in cols.iter().zip(floats) {
        if *name == "distinct_effects" || *name == "trials" {
            let ints: Vec<i64> = v.iter().map(|&x| x as i64).collect();
            metrics.set_item(name, ints.into_pyarray(py))?;
        } else {
            metrics.set_item(name, v.into_pyarray(py))?;
        }
    }
    let commands = numpy::ndarray::Array3::from_shape_vec((s, trials, slots), commands)
        .expect("S x T x slots");
    let effects = Array2::from_shape_vec((s, trials), effects).expect("S x T");
    let rewards = Array2::from_shape_vec((s, trials), rewards).expect("S x T");
    Ok(PyBatchRecord {
        scene: scene.inner.name.clone(),
        learner: learner.to_string(),
        seeds: seeds.to_vec().into_pyarray(py).unbind(),
        trials,
        commands: commands.into_pyarray(py).unbind(),
        effects: effects.into_pyarray(py).unbind(),
        rewards: rewards.into_pyarray(py).unbind(),
        metrics: metrics.unbind(),
        execution,
        per_session,
    })
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
fn run_sessions(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    learner: Option<&Bound<'_, PyAny>>,
    trials: usize,
    seeds: Option<Vec<u64>>,
    sessions: Option<usize>,
    seed: u64,
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
                "learner: expected \"e3d\", \"uniform\", \"egreedy\" or a sequence of Python learners, one per seed",
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

// ---------------------------------------------------------------------------
// Sweeps
// ---------------------------------------------------------------------------

/// `results.csv`'s rows (`header` and one line a session) as a dict of
/// columns (see `run_sweep`).
fn columns_of<'py>(py: Python<'py>, header: &str, rows: &[&str]) -> PyResult<Bound<'py, PyDict>> {
    let header: Vec<&str> = header.split(',').collect();
    let rows: Vec<Vec<&str>> = rows.iter().map(|r| r.split(',').collect()).collect();
    let out = PyDict::new(py);
    for (j, name) in header.iter().enumerate() {
        let col = rows.iter().map(|r| r.get(j).copied().unwrap_or(""));
        match *name {
            "scene" | "learner" | "failure" => {
                let v: Vec<&str> = col.collect();
                out.set_item(name, v)?;
            }
            "use_reward" => {
                let v: Vec<bool> = col.map(|s| s == "true").collect();
                out.set_item(name, v.into_pyarray(py))?;
            }
            "session" => {
                let v: Vec<i64> = col.map(|s| s.parse().unwrap_or(-1)).collect();
                out.set_item(name, v.into_pyarray(py))?;
            }
            "seed" => {
                let v: Vec<u64> = col.map(|s| s.parse().unwrap_or(0)).collect();
                out.set_item(name, v.into_pyarray(py))?;
            }
            _ => {
                let v: Vec<f64> = col.map(|s| s.parse().unwrap_or(f64::NAN)).collect();
                out.set_item(name, v.into_pyarray(py))?;
            }
        }
    }
    Ok(out)
}

/// The marker a cancelled `run_to_dir` unwinds with (its progress callback
/// cannot return an error). The journal is written to survive a kill at
/// any moment, so an unwind leaves a folder that `resume=True` completes.
struct Interrupted;

/// Takes the lock of the output folder as `e3d sweep` does (creating the
/// folder), or refuses with the CLI's text.
fn lock_out(dir: &Path) -> PyResult<Option<e3d::io::DirLock>> {
    if (dir.exists() && !dir.is_dir()) || std::fs::create_dir_all(dir).is_err() {
        return Ok(None);
    }
    match e3d::io::DirLock::acquire(dir) {
        Ok(lock) => Ok(Some(lock)),
        Err(e) if e.kind() == std::io::ErrorKind::WouldBlock => Err(pyo3::exceptions::PyOSError::new_err(format!(
            "{}: in use by {e}, which is running a sweep into it; wait for it to end or choose another --out",
            dir.display()
        ))),
        Err(e) => Err(pyo3::exceptions::PyOSError::new_err(format!(
            "{}: cannot take the lock {}: {e}",
            dir.display(),
            dir.join(e3d::io::LOCK_FILE).display()
        ))),
    }
}

/// Runs a sweep (the native part of `e3d.run_sweep`, which also takes a
/// dict) and returns its `results.csv` as a dict of columns, in the
/// file's order: `scene`, `learner`, `failure` (lists of str),
/// `use_reward` (bool array), `session` (int64), `seed` (uint64), and
/// float64 arrays for the parameters and the metrics (NaN where the CSV
/// cell is empty: a parameter the learner does not use, no first reward,
/// a failed session). The same values as `e3d sweep FILE --out DIR`.
///
/// `sweep`: a path to a sweep file (scene paths relative to its folder),
/// or the text of one (scene paths relative to the current folder).
/// `threads`: default every core. `out`: a folder to write what
/// `e3d sweep --out DIR` writes, byte for byte (`results.csv`,
/// `summary.csv`, `sweep.ron`, `version.txt`, `journal.txt`); `resume`:
/// complete the sweep that `out` holds (`--resume`). `progress`: called
/// as `progress(trials_done, trials_of_all_sessions)`. Ctrl-C raises
/// `KeyboardInterrupt` once the sessions running have finished (with
/// `out`, `resume=True` completes the folder later).
#[pyfunction]
#[pyo3(signature = (sweep, threads = None, table_cache = None, out = None, resume = false,
    progress = None))]
fn run_sweep<'py>(
    py: Python<'py>,
    sweep: &Bound<'py, PyAny>,
    threads: Option<usize>,
    table_cache: Option<PathBuf>,
    out: Option<PathBuf>,
    resume: bool,
    progress: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let text_or_path: PathBuf = sweep.extract()?;
    let s = text_or_path.to_string_lossy().to_string();
    let is_text = !Path::new(&s).exists() && s.contains('(');
    let mut sw = if is_text {
        Sweep::parse(&s, "<string>", None)
    } else {
        Sweep::load(&text_or_path)
    }
    .map_err(|e| PyErr::from(Fail::from(e)))?;
    if let Some(dir) = table_cache {
        sw = sw.with_table_cache(dir);
    }
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads = 0: expected at least 1"));
    }
    let threads = threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let watch = Watch::new();
    let sw = sw.with_trial_counter(watch.done.clone());
    let per_session = sw.spec.trials as u64;
    let total = sw.num_sessions() as u64 * per_session;
    let header = sw.results_header();
    let Some(dir) = out else {
        let rows: Vec<String> = watched(py, progress, total, &watch, |watch| {
            let sessions = sw.sessions();
            let mut rows: Vec<Option<String>> = vec![None; sessions.len()];
            sw.run_with(&sessions, threads, |r| {
                if watch.cancelled() {
                    return Err(SweepError::Other(STOPPED.into()));
                }
                rows[r.session.index] = Some(sw.result_row(&r));
                Ok(())
            })?;
            Ok::<_, Fail>(rows.into_iter().flatten().collect())
        })??;
        let rows: Vec<&str> = rows.iter().map(String::as_str).collect();
        return columns_of(py, &header, &rows);
    };
    let _lock = lock_out(&dir)?;
    let options = DirOptions {
        threads,
        resume,
        shard: Shard::ALL,
    };
    watched(py, progress, total, &watch, |watch| {
        let mut first = true;
        let run = std::panic::AssertUnwindSafe(|| {
            sw.run_to_dir(&dir, &options, |done, _| {
                if first {
                    // the sessions of an earlier run count as done
                    watch
                        .base
                        .store(done as u64 * per_session, Ordering::Relaxed);
                    first = false;
                }
                if watch.cancelled() {
                    std::panic::resume_unwind(Box::new(Interrupted));
                }
            })
        });
        match std::panic::catch_unwind(run) {
            Ok(r) => r.map(|_| ()).map_err(Fail::from),
            Err(p) if p.is::<Interrupted>() => Err(Fail::Runtime(STOPPED.into())),
            Err(p) => std::panic::resume_unwind(p),
        }
    })??;
    let path = dir.join(e3d::sweep::RESULTS);
    let text = std::fs::read_to_string(&path).map_err(|e| {
        pyo3::exceptions::PyOSError::new_err(format!("{}: cannot read: {e}", path.display()))
    })?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let rows: Vec<&str> = lines.collect();
    columns_of(py, header, &rows)
}

// ---------------------------------------------------------------------------
// The module
// ---------------------------------------------------------------------------

/// e3d's native module (import `e3d`, which re-exports it).
#[pymodule]
fn _e3d(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("E3D_VERSION", e3d::sweep::VERSION)?;
    m.add_class::<PyScene>()?;
    m.add_class::<PyWorld>()?;
    m.add_class::<PyOutcome>()?;
    m.add_class::<PyBatch>()?;
    m.add_class::<PyRecord>()?;
    m.add_class::<PyRng>()?;
    m.add_class::<PyBatchRecord>()?;
    m.add_class::<PyMotion>()?;
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add_function(wrap_pyfunction!(run_session, m)?)?;
    m.add_function(wrap_pyfunction!(run_sessions, m)?)?;
    m.add_function(wrap_pyfunction!(run_sweep, m)?)?;
    Ok(())
}
