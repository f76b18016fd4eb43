//! `Scene`: a parsed and validated scene, its command schema and effects;
//! its Python methods are in `methods`.

mod methods;

use e3d::command::CommandSpace;
use e3d::command::ValueSpace;
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
}

impl PyScene {
    /// The scene, with its command space: symbols per slot, or values in
    /// ranges for a continuous scene (`values`; `space` is then a stand-in
    /// of one slot that no symbol path uses).
    fn new(scene: e3d::Scene) -> Result<PyScene, e3d::SceneError> {
        let values = scene.value_space();
        let space = match values {
            Some(_) => CommandSpace::repeat(1, &['0']).expect("one symbol"),
            None => scene.command_space(),
        };
        Ok(PyScene {
            space,
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
/// 0); checked as the library checks a target.
pub(crate) fn target_arg(scene: &PyScene, target: Option<&Bound<'_, PyAny>>) -> PyResult<Target> {
    let Some(obj) = target.filter(|t| !t.is_none()) else {
        return Ok(Target::Uniform);
    };
    let n = scene.inner.num_effects();
    let weights: Vec<f64> = if let Ok(d) = obj.cast::<pyo3::types::PyDict>() {
        let g = scene.inner.effect_grid();
        let mut w = vec![0.0; n];
        let mut named: Vec<Option<Bound<'_, PyAny>>> = vec![None; n];
        for (k, v) in d.iter() {
            let cell = if k.is_instance_of::<pyo3::types::PyBool>() {
                None
            } else if let Ok((r, c)) = k.extract::<(usize, usize)>() {
                (r < g.rows && c < g.cols).then_some(r * g.cols + c)
            } else {
                k.extract::<usize>().ok().filter(|&e| e < n)
            };
            let Some(e) = cell else {
                return Err(PyValueError::new_err(format!(
                    "target: key {} is not an effect: expected an int in [0, {n}) or a (row, col) cell of the {}x{} grid",
                    k.repr()?,
                    g.rows,
                    g.cols
                )));
            };
            if let Some(first) = &named[e] {
                return Err(PyValueError::new_err(format!(
                    "target: keys {} and {} are the same effect {e}: give each effect once",
                    first.repr()?,
                    k.repr()?
                )));
            }
            named[e] = Some(k.clone());
            w[e] = crate::errors::float_arg(&v).map_err(|_| {
                PyValueError::new_err(format!(
                    "target[{}]: expected a number",
                    k.repr().map(|r| r.to_string()).unwrap_or_default()
                ))
            })?;
        }
        w
    } else {
        let np = obj.py().import("numpy")?;
        let a = np.call_method1("asarray", (obj, "float64")).map_err(|e| {
            PyValueError::new_err(format!(
                "target: expected None, {n} weights (one per effect) or a dict {{effect: weight}}: {e}"
            ))
        })?;
        let flat = a.call_method0("ravel")?;
        if a.getattr("ndim")?.extract::<usize>()? != 1 {
            return Err(PyValueError::new_err(format!(
                "target: expected a 1-D array of {n} weights (one per effect), found shape {}",
                a.getattr("shape")?.repr()?
            )));
        }
        flat.extract()?
    };
    let target = Target::Weights(weights);
    target
        .log_probs(n)
        .map_err(|e| PyValueError::new_err(format!("target: {e}")))?;
    Ok(target)
}
