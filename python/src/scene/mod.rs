//! `Scene`: a parsed and validated scene, its command schema and effects;
//! its Python methods are in `methods`.

mod methods;

use e3d::command::CommandSpace;
use e3d::command::ValueSpace;
use e3d::scene::WorldSpec;
use e3d::Target;
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::Arc;

/// A scene given as a `Scene` or as a path / built-in name.
pub(crate) fn scene_of(obj: &Bound<'_, PyAny>) -> PyResult<PyScene> {
    if let Ok(s) = obj.cast::<PyScene>() {
        return Ok(s.get().clone());
    }
    if let Ok(p) = obj.extract::<PathBuf>() {
        return PyScene::resolved(&p.to_string_lossy());
    }
    Err(PyTypeError::new_err(format!(
        "scene: expected a Scene, or a scene file's path or a built-in scene's name, found {}",
        obj.get_type().name()?
    )))
}

/// A parsed and validated scene: a world, a command schema (slots and
/// their alphabets), effects (cells of a grid) and a reward.
///
/// Make one with `Scene.load(path)`, `Scene.builtin(name)`,
/// `Scene.resolve(path_or_name)` or `Scene.from_text(text)`.
#[pyclass(module = "e3d", name = "Scene", frozen)]
#[derive(Clone)]
pub(crate) struct PyScene {
    pub(crate) inner: Arc<e3d::Scene>,
    pub(crate) space: CommandSpace,
    /// The value ranges of a continuous scene.
    pub(crate) values: Option<ValueSpace>,
    /// The scene's name.
    #[pyo3(get)]
    name: String,
    /// The scene's description.
    #[pyo3(get)]
    description: String,
    /// `"grid"` or `"physics"`.
    #[pyo3(get)]
    kind: &'static str,
    /// The number of slots of a command.
    #[pyo3(get)]
    num_slots: usize,
    /// Whether the scene's slots take continuous values (`value_ranges`)
    /// rather than symbols.
    #[pyo3(get)]
    is_continuous: bool,
    /// The `(low, high)` range of each slot of a continuous scene (empty
    /// for a scene of symbols).
    #[pyo3(get)]
    value_ranges: Vec<(f64, f64)>,
    /// The alphabet size of each slot (empty for a continuous scene).
    #[pyo3(get)]
    alphabet_sizes: Vec<usize>,
    /// The alphabet of each slot, as a string of its symbols.
    #[pyo3(get)]
    alphabets: Vec<String>,
    /// The number of effects (cells of the effect grid).
    #[pyo3(get)]
    num_effects: usize,
    /// The effect grid: `(rows, cols, (xmin, ymin), (xmax, ymax))`.
    #[pyo3(get)]
    effect_grid: (usize, usize, (f64, f64), (f64, f64)),
    /// The number of distinct commands, or `None` beyond 2^64 (and for a
    /// continuous scene).
    #[pyo3(get)]
    num_commands: Option<u64>,
}

impl PyScene {
    /// The scene, with its command space: symbols per slot, or values in
    /// ranges for a continuous scene (`values`; `space` is then a stand-in
    /// of one slot that no symbol path uses).
    fn new(scene: e3d::Scene) -> Result<PyScene, e3d::SceneError> {
        let values = scene.value_space();
        let symbols = match values {
            Some(_) => None,
            None => Some(scene.command_space()),
        };
        let spec = scene.spec();
        let g = scene.effect_grid();
        let space = symbols.as_ref();
        Ok(PyScene {
            name: spec.name.clone(),
            description: spec.description.clone(),
            kind: match spec.world {
                WorldSpec::Grid(_) => "grid",
                WorldSpec::Physics(_) => "physics",
            },
            num_slots: spec.num_slots(),
            is_continuous: values.is_some(),
            value_ranges: values
                .as_ref()
                .map_or_else(Vec::new, |v| v.ranges().to_vec()),
            alphabet_sizes: space.map_or_else(Vec::new, |s| s.sizes().collect()),
            alphabets: space.map_or_else(Vec::new, |s| {
                (0..s.num_slots())
                    .map(|i| s.alphabet(i).iter().collect())
                    .collect()
            }),
            num_effects: scene.num_effects(),
            effect_grid: (g.rows, g.cols, (g.min[0], g.min[1]), (g.max[0], g.max[1])),
            num_commands: space.and_then(CommandSpace::num_commands),
            space: symbols.unwrap_or_else(|| CommandSpace::repeat(1, &['0']).expect("one symbol")),
            values,
            inner: Arc::new(scene),
        })
    }

    /// A scene by path, or by the name of a built-in scene (`Scene.resolve`).
    fn resolved(path_or_name: &str) -> PyResult<PyScene> {
        e3d::Scene::resolve(path_or_name)
            .and_then(PyScene::new)
            .map_err(crate::errors::scene_err)
    }

    /// `Ok` for a scene of symbols; for a continuous one, `ValueError`
    /// saying that `what` takes symbols.
    pub(crate) fn require_symbols(&self, what: &str) -> PyResult<()> {
        if self.values.is_some() {
            return Err(PyValueError::new_err(format!(
                "{what}: scene `{}` takes continuous values (value_ranges), not symbols",
                self.inner.spec().name
            )));
        }
        Ok(())
    }
}

/// The built-in scenes.
pub(crate) fn builtin_names() -> Vec<&'static str> {
    e3d::scene::BUILTIN.iter().map(|(n, _)| *n).collect()
}

/// `target`: None (uniform), an array of one weight per effect, or a dict
/// `{effect: weight}` / `{(row, col): weight}` (the cells not named weigh
/// 0), collected by `e3d._args.target_weights` and checked as the library
/// checks a target.
pub(crate) fn target_arg(scene: &PyScene, target: Option<&Bound<'_, PyAny>>) -> PyResult<Target> {
    let Some(obj) = target.filter(|t| !t.is_none()) else {
        return Ok(Target::Uniform);
    };
    let args = obj.py().import("e3d._args")?;
    let weights = args.call_method1("target_weights", (scene.clone(), obj))?;
    let target = Target::Weights(weights.extract()?);
    target
        .log_probs(scene.inner.num_effects())
        .map_err(|e| PyValueError::new_err(format!("target: {e}")))?;
    Ok(target)
}

/// The bytes the records of `trials` trials of `scene` take, as held by
/// e3d and then by numpy (twice): each trial's command (a byte a symbol,
/// 8 bytes a value), effect and reward.
pub(crate) fn record_bytes(scene: &PyScene, trials: u64) -> u64 {
    let slots = scene.inner.spec().num_slots() as u64;
    let command = if scene.values.is_some() {
        8 * slots
    } else {
        slots
    };
    trials.saturating_mul(2 * (command + 16))
}
