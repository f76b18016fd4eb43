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
use e3d::world::{
    ExecOptions, Executor, Memoized, OutcomeMemo, Strategy, Workload, DEFAULT_MEMO_CAP,
    TABLE_COPIES,
};
use e3d::{
    Command, CommandSpace, Learner, LearnerKind, Outcome, Params, PhysicsWorld, SessionConfig,
    SessionRecord, SessionRng, Sweep, SweepError, Target, World, WorldError,
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
use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
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
}

impl From<Fail> for PyErr {
    fn from(f: Fail) -> PyErr {
        match f {
            Fail::Value(m) => PyValueError::new_err(m),
            Fail::Scene(m) => SceneError::new_err(m),
            Fail::Simulation(m) => SimulationError::new_err(m),
            Fail::Runtime(m) => PyRuntimeError::new_err(m),
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
    fn new(scene: e3d::Scene) -> PyScene {
        PyScene {
            space: scene.command_space(),
            inner: Arc::new(scene),
        }
    }
}

#[pymethods]
impl PyScene {
    /// Loads and validates a scene file (`.ron`). Raises `SceneError` with
    /// `file:line:col: message`, the CLI's text.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<PyScene> {
        e3d::Scene::load(&path).map(PyScene::new).map_err(scene_err)
    }

    /// A scene shipped with e3d, by name (see `Scene.builtins()`).
    #[staticmethod]
    fn builtin(name: &str) -> PyResult<PyScene> {
        e3d::Scene::builtin(name).map(PyScene::new).ok_or_else(|| {
            SceneError::new_err(format!(
                "{name}: no built-in scene of that name; expected one of: {}",
                builtin_names().join(", ")
            ))
        })
    }

    /// A scene by path, or by the name of a built-in scene when no such
    /// file exists (what the CLI's SCENE arguments accept).
    #[staticmethod]
    fn resolve(path_or_name: &str) -> PyResult<PyScene> {
        e3d::Scene::resolve(path_or_name)
            .map(PyScene::new)
            .map_err(scene_err)
    }

    /// Parses and validates scene text; `file` names it in errors.
    #[staticmethod]
    #[pyo3(signature = (text, file = "<string>"))]
    fn from_text(text: &str, file: &str) -> PyResult<PyScene> {
        e3d::Scene::parse(text, file)
            .map(PyScene::new)
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

fn builtin_names() -> Vec<&'static str> {
    e3d::scene::BUILTIN.iter().map(|(n, _)| *n).collect()
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
    fn run(&self, commands: &[Command]) -> Result<Vec<Outcome>, WorldError> {
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
        let piece = unique
            .len()
            .div_ceil(rayon::current_num_threads())
            .clamp(1, self.copies);
        let parts: Vec<Vec<Result<Outcome, WorldError>>> = unique
            .par_chunks(piece)
            .map(|part| {
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
        let out = py.detach(|| self.run(&cs)).map_err(Fail::from)?;
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
    fn execute_batch(&self, py: Python<'_>, commands: &Bound<'_, PyAny>) -> PyResult<PyBatch> {
        let cs = commands_from(py, &self.scene.space, commands, 2)?;
        let out = py.detach(|| self.run(&cs)).map_err(Fail::from)?;
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

/// A world that stops the session once the Python learner has raised.
struct Guarded<'a, W: ?Sized> {
    world: &'a mut W,
    error: &'a RefCell<Option<PyErr>>,
}

impl<W: World + ?Sized> World for Guarded<'_, W> {
    fn command_space(&self) -> &CommandSpace {
        self.world.command_space()
    }
    fn num_effects(&self) -> usize {
        self.world.num_effects()
    }
    fn execute(&mut self, command: &Command) -> Result<Outcome, WorldError> {
        if self.error.borrow().is_some() {
            return Err(WorldError::Other("the Python learner raised".into()));
        }
        self.world.execute(command)
    }
    fn is_deterministic(&self) -> bool {
        self.world.is_deterministic()
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

fn record_to_py(
    py: Python<'_>,
    scene: &PyScene,
    learner: &str,
    cfg: &SessionConfig,
    rec: SessionRecord,
    execution: String,
) -> PyResult<PyRecord> {
    let m = rec.metrics(&Target::Uniform);
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
#[pyfunction]
#[pyo3(signature = (scene, learner = None, trials = 5000, seed = 0, use_reward = true,
    alpha = Params::TASK1.alpha, beta = Params::TASK1.beta, lambda_ = Params::TASK1.lambda,
    eta = Params::TASK1.eta, epsilon = Params::TASK1.epsilon, outcomes = None, table_cache = None))]
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
) -> PyResult<PyRecord> {
    let scene = scene_of(scene)?;
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
    let options = ExecOptions {
        cache: table_cache,
        memo_cap: DEFAULT_MEMO_CAP,
        force,
    };
    let work = Workload {
        trials: trials as u64,
        sessions: 1,
        threads: rayon::current_num_threads(),
    };
    let cfg = SessionConfig {
        trials,
        seed,
        use_reward,
    };
    let space = scene.space.clone();
    let n_eff = scene.inner.num_effects();
    let kind = match learner {
        None => Some(LearnerKind::E3d),
        Some(l) if l.is_instance_of::<PyString>() => Some(
            l.extract::<String>()?
                .parse::<LearnerKind>()
                .map_err(PyValueError::new_err)?,
        ),
        Some(_) => None,
    };
    if let Some(kind) = kind {
        let mut made = kind
            .make(&params, &space, n_eff, &Target::Uniform)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let inner = scene.inner.clone();
        let (rec, execution) = py.detach(|| -> Result<_, Fail> {
            let exec = Executor::new(&inner, &work, &options)?;
            let mut world = exec.world(1);
            let mut rec = SessionRecord::new(&*world, trials);
            e3d::run_session_into(&mut *world, &mut made, &cfg, &mut rec, |_| {})?;
            drop(world);
            let mut execution = exec.plan().to_string();
            if let Some(line) = exec.finish() {
                execution.push('\n');
                execution.push_str(&line);
            }
            Ok((rec, execution))
        })?;
        return record_to_py(py, &scene, kind.as_str(), &cfg, rec, execution);
    }
    let obj = learner.expect("an object").clone();
    for m in ["propose", "learn"] {
        if !obj.hasattr(m)? {
            return Err(PyTypeError::new_err(format!(
                "learner: expected \"e3d\", \"uniform\", \"egreedy\" or an object with propose(rng) and learn(command, effect, reward); this one has no `{m}`"
            )));
        }
    }
    let name: String = obj
        .getattr("name")
        .and_then(|n| n.extract())
        .unwrap_or_else(|_| "python".to_string());
    let error = RefCell::new(None);
    let rng = Bound::new(
        py,
        PyRng {
            inner: rand::SeedableRng::seed_from_u64(0),
        },
    )?;
    let mut pl = PyLearner {
        py,
        obj,
        rng,
        space: space.clone(),
        error: &error,
    };
    let exec = Executor::new(&scene.inner, &work, &options).map_err(Fail::from)?;
    let mut world = exec.world(1);
    let mut guarded = Guarded {
        world: &mut *world,
        error: &error,
    };
    let mut rec = SessionRecord::new(&guarded, trials);
    let status = e3d::run_session_into(&mut guarded, &mut pl, &cfg, &mut rec, |_| {});
    drop(world);
    if let Some(e) = error.into_inner() {
        return Err(e);
    }
    status.map_err(Fail::from)?;
    let mut execution = exec.plan().to_string();
    if let Some(line) = exec.finish() {
        execution.push('\n');
        execution.push_str(&line);
    }
    record_to_py(py, &scene, &name, &cfg, rec, execution)
}

// ---------------------------------------------------------------------------
// Sweeps
// ---------------------------------------------------------------------------

/// Runs a sweep and returns its `results.csv` as a dict of columns, in
/// the file's order: `scene`, `learner`, `failure` (lists of str),
/// `use_reward` (bool array), `session` (int64), `seed` (uint64), and
/// float64 arrays for the parameters and the metrics (NaN where the CSV
/// cell is empty: a parameter the learner does not use, no first reward,
/// a failed session). The same values as `e3d sweep FILE --out DIR`.
///
/// `sweep`: a path to a sweep file (scene paths relative to its folder),
/// or the text of one (scene paths relative to the current folder).
/// `threads`: default every core.
#[pyfunction]
#[pyo3(signature = (sweep, threads = None, table_cache = None))]
fn run_sweep<'py>(
    py: Python<'py>,
    sweep: &Bound<'py, PyAny>,
    threads: Option<usize>,
    table_cache: Option<PathBuf>,
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
    let threads = threads.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let results = py
        .detach(|| sw.run(threads))
        .map_err(|e| PyErr::from(Fail::from(e)))?;
    let header: Vec<String> = sw.results_header().split(',').map(String::from).collect();
    let rows: Vec<Vec<String>> = results
        .iter()
        .map(|r| sw.result_row(r).split(',').map(String::from).collect())
        .collect();
    let out = PyDict::new(py);
    for (j, name) in header.iter().enumerate() {
        let col = rows
            .iter()
            .map(|r| r.get(j).map(String::as_str).unwrap_or(""));
        match name.as_str() {
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
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add_function(wrap_pyfunction!(run_session, m)?)?;
    m.add_function(wrap_pyfunction!(run_sweep, m)?)?;
    Ok(())
}
