//! `Scene`'s Python methods: loading, the command schema, parsing and
//! formatting commands, its world, pictures and dict / RON forms.

use super::{builtin_names, PyScene};
use crate::commands::{commands_from, values_from};
use crate::errors::{scene_err, scene_error, usize_arg};
use crate::world::PyWorld;
use e3d::scene::WorldSpec;
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyString;
use std::path::PathBuf;

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
            scene_error(
                format!(
                    "{name}: no built-in scene of that name{}; expected one of: {}",
                    e3d::scene::did_you_mean(name, &builtin_names()),
                    builtin_names().join(", ")
                ),
                Some(name),
                None,
                None,
                None,
            )
        })?;
        PyScene::new(scene).map_err(scene_err)
    }

    /// A scene by path, or by the name of a built-in scene when no such
    /// file exists (what the CLI's SCENE arguments accept).
    #[staticmethod]
    fn resolve(path_or_name: &str) -> PyResult<PyScene> {
        PyScene::resolved(path_or_name)
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

    /// The effect of the start state: the cell of the tracked point (or of
    /// the agent) before any command.
    #[getter]
    fn start_effect(&self) -> usize {
        let g = self.inner.effect_grid();
        match &self.inner.spec().world {
            WorldSpec::Grid(spec) => g.effect_of(g.center(spec.start.0, spec.start.1)),
            WorldSpec::Physics(p) => match p.effect.world_point() {
                Some((body, point, _)) => {
                    let b = p.body(body).expect("validated: tracked body");
                    let t = e3d::scene::physics::to_world_point(b.position, b.angle, point);
                    g.effect_of([t.0, t.1])
                }
                // the features' start state, binned
                None => self.inner.physics_world().map(|w| w.start().1).unwrap_or(0),
            },
        }
    }

    /// The reward of each effect, a float64 array of `num_effects`.
    fn reward_table<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.reward_table().into_pyarray(py)
    }

    /// The effort of each command (docs/algorithms.md, "Effort"): the sum
    /// over its slots of the size of the slot's action (`|torque|`, the
    /// norm of an impulse or a force, `|angle|` of a set point, the length
    /// of a grid move, 0 for `Idle`); `commands` as `World.execute_batch`
    /// takes them (symbol indices `[N, num_slots]` or strings; values on a
    /// continuous scene). A float64 array `[N]`.
    fn effort<'py>(
        &self,
        py: Python<'py>,
        commands: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let effort = e3d::learner::Effort::of_scene(&self.inner);
        let of = |e: Option<f64>| e.expect("a command of the scene's slots");
        let out: Vec<f64> = match &self.values {
            Some(space) => (values_from(py, space, commands, 2)?.iter())
                .map(|v| of(effort.of(&v[..])))
                .collect(),
            None => (commands_from(py, &self.space, commands, 2)?.iter())
                .map(|c| of(effort.of(c)))
                .collect(),
        };
        Ok(out.into_pyarray(py))
    }

    /// The largest effort of a command: the sum over slots of the largest
    /// size of the slot's actions.
    #[getter]
    fn max_effort(&self) -> f64 {
        e3d::learner::Effort::of_scene(&self.inner).max()
    }

    /// Whether commands differ in effort (else every command's effort
    /// quality is the same, and sessions report no `qd_score`).
    #[getter]
    fn effort_varies(&self) -> bool {
        e3d::learner::Effort::of_scene(&self.inner).varies()
    }

    /// Commands written as symbols (a string, or a list of strings) as a
    /// uint8 array of shape `[N, num_slots]` of symbol indices.
    fn parse<'py>(
        &self,
        py: Python<'py>,
        commands: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<u8>>> {
        self.require_symbols("Scene.parse")?;
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
        self.require_symbols("Scene.format")?;
        let one = commands
            .cast::<PyUntypedArray>()
            .is_ok_and(|a| a.ndim() == 1)
            || commands.extract::<Vec<i64>>().is_ok();
        let cs = commands_from(py, &self.space, commands, if one { 1 } else { 2 })?;
        let mut texts: Vec<String> = cs.iter().map(|c| self.space.format(c)).collect();
        Ok(match one {
            true => texts.remove(0).into_pyobject(py)?.into_any().unbind(),
            false => texts.into_pyobject(py)?.into_any().unbind(),
        })
    }

    /// A world that executes this scene's commands (see `World`).
    /// `prefix_states`: the most phase-end states `execute` keeps for the
    /// commands that share a prefix (default 2048; 0: every step of every
    /// command simulated).
    #[pyo3(signature = (prefix_states = None))]
    fn world(&self, prefix_states: Option<&Bound<'_, PyAny>>) -> PyResult<PyWorld> {
        let cap = match prefix_states {
            Some(n) if !n.is_none() => usize_arg(n, "prefix_states", 0)?,
            _ => e3d::world::PREFIX_STATES,
        };
        Ok(PyWorld::new(self.clone(), cap))
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene({:?}: {}, {} {}slots, {} effects)",
            self.name,
            self.kind,
            self.num_slots,
            if self.values.is_some() {
                "continuous "
            } else {
                ""
            },
            self.inner.num_effects()
        )
    }

    /// The scene drawn as SVG (bodies, joints, walls, the effect grid and
    /// the reward cells), with the path of `command` and its terminal cell
    /// when given (symbols, or values on a continuous scene): what
    /// `e3d scene render SCENE [--command C]` writes.
    #[pyo3(signature = (command = None))]
    fn svg(&self, py: Python<'_>, command: Option<&Bound<'_, PyAny>>) -> PyResult<String> {
        crate::picture::svg(py, self, command)
    }

    /// The SVG picture, for notebooks (Jupyter shows it).
    fn _repr_svg_(&self, py: Python<'_>) -> PyResult<String> {
        crate::picture::svg(py, self, None)
    }

    /// The SVG picture rasterised: a uint8 array `(height, width, 3)`
    /// (RGB), `scale` pixels per pixel of `svg()` (whose largest side
    /// is about 850), with the path of `command` when given. Text (the
    /// title, axis labels and legend) is left out: it would need fonts.
    #[pyo3(signature = (command = None, scale = 1.0))]
    fn render<'py>(
        &self,
        py: Python<'py>,
        command: Option<&Bound<'py, PyAny>>,
        #[pyo3(from_py_with = crate::errors::float_arg)] scale: f64,
    ) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
        let svg = crate::picture::svg(py, self, command)?;
        let (h, w, rgb) = py.detach(|| crate::picture::rasterise(&svg, scale))?;
        let a = numpy::ndarray::Array3::from_shape_vec((h, w, 3), rgb).expect("h x w x 3");
        Ok(a.into_pyarray(py))
    }

    /// What the picture draws, as plain data for matplotlib and the like
    /// (metres, world frame, y up): `kind`; `effect_grid` (`rows`, `cols`,
    /// `min`, `max`); `reward_cells` (`(row, col)` of every rewarded
    /// cell); on a grid `start` and `walls` (pairs of cells); on a physics
    /// scene `bodies` (each `name`, `kind`, `shape`, `position`, `angle`,
    /// `radius` and `points`: a ball's centre, a cuboid's closed outline,
    /// a capsule's or segment's two ends, a polyline's points), `joints`
    /// (`name`, `parent`, `child`, `position`), `tracked_body` and
    /// `tracked_point` (None for an effect of features).
    fn geometry<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let f = py.import("e3d._scene_dict")?.getattr("geometry")?;
        f.call1((self.clone(),))
    }

    /// The scene's fields as Python data: the RON text's structure (a
    /// struct a dict, an enum variant with data a one-key dict such as
    /// `{"Physics": {...}}`, a variant without data its name, a tuple a
    /// list), which `Scene.from_dict` reads back as an equal scene.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        crate::scene_dict::to_dict(py, &self.inner)
    }

    /// A scene from Python data of `to_dict`'s form, checked as a scene
    /// file is: `SceneError` naming the path of the value at fault
    /// (`<dict>: world.Physics.bodies[0].shape: unknown variant ...`,
    /// `.field` the path), or the validation's message and field.
    #[staticmethod]
    fn from_dict(data: &Bound<'_, PyAny>) -> PyResult<PyScene> {
        let scene = crate::scene_dict::from_dict(data)?;
        PyScene::new(scene).map_err(scene_err)
    }

    /// A copy of the scene with overrides: `{path: value}`, paths of
    /// dot-separated fields of `to_dict()`'s form, a list's item by index
    /// (`bodies.2` or `bodies[2]`) or by name, enum variants stepped
    /// through, fields the scene leaves out (`noise`) created, and paths
    /// that do not start with a field of the scene (`name`, `description`,
    /// `world`, `command`, `reward`, ...) starting in the world:
    /// `scene.with_({"bodies.puck.linear_damping": 2.0})` (the library's
    /// `Scene::with_paths`, as sweep axes). The result is checked as
    /// `from_dict` checks.
    fn with_(&self, overrides: &Bound<'_, pyo3::types::PyDict>) -> PyResult<PyScene> {
        let scene = crate::scene_dict::with_(&self.inner, overrides)?;
        PyScene::new(scene).map_err(scene_err)
    }

    /// The scene as RON text that `Scene.from_text` reads back as an equal
    /// scene (the library's `Scene::to_ron`).
    fn to_ron(&self) -> String {
        self.inner.spec().to_ron()
    }

    /// The scene as a MuJoCo model, MJCF text (`e3d scene export --mjcf`):
    /// bodies, joints, motors and actuators in the x-y plane, with the table
    /// that replays a command (docs/mjcf.md). Raises `ValueError` for a grid
    /// scene.
    fn to_mjcf(&self) -> PyResult<String> {
        e3d::scene::mjcf::to_mjcf(&self.inner).ok_or_else(|| {
            PyValueError::new_err(format!(
                "scene `{}` is a grid: only physics scenes export to MJCF",
                self.inner.spec().name
            ))
        })
    }

    /// The effect (cell) of the effect's feature values, in the effect's
    /// order: 2 per point (x, y), 1 per joint or angle; binned as the
    /// scene bins its terminal state.
    fn effect_of(&self, values: Vec<f64>) -> PyResult<usize> {
        let b = self.inner.binning();
        if values.len() != b.arity() {
            return Err(PyValueError::new_err(format!(
                "scene `{}`: expected {} feature values, found {}",
                self.inner.spec().name,
                b.arity(),
                values.len()
            )));
        }
        Ok(b.locate(&values).1)
    }

    /// Pickling: the scene's RON text, read back by `Scene.from_text`.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, (String, String))> {
        let from_text = py.get_type::<PyScene>().getattr("from_text")?;
        Ok((
            from_text,
            (
                self.inner.spec().to_ron(),
                format!("<scene {}>", self.inner.spec().name),
            ),
        ))
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<PyScene>()
            .map(|o| *o.get().inner == *self.inner)
            .unwrap_or(false)
    }
}
