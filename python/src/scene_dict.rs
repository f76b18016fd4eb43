//! Scenes as Python data: `Scene.to_dict` (the scene's fields, as in its
//! RON text, the library's serde form), `Scene.from_dict` (its JSON
//! lines written by python/e3d/_scene_dict.py, checked as a scene file is,
//! errors naming the path of the value at fault) and `Scene.with_` (the
//! library's `e3d::scene::path::set_path` on that form).

use crate::errors::{scene_err, scene_error};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The JSON lines of `obj` (python/e3d/_scene_dict.py), their paths
/// starting at `at`.
fn json_lines(obj: &Bound<'_, PyAny>, at: &str) -> PyResult<(String, Vec<String>)> {
    let f = obj.py().import("e3d._scene_dict")?.getattr("json_lines")?;
    f.call1((obj, at))?.extract()
}

/// `Scene.with_`: `scene` with each `{path: value}` of `overrides` set
/// (`set_path`), then read and checked as `from_dict` reads and checks.
pub(crate) fn with_(scene: &e3d::Scene, overrides: &Bound<'_, PyDict>) -> PyResult<e3d::Scene> {
    let mut data = serde_json::to_value(scene.spec()).expect("a scene is plain data");
    for (k, v) in overrides.iter() {
        let path: String = k
            .extract()
            .map_err(|_| PyTypeError::new_err("with_: keys must be paths (str)"))?;
        let (text, _) = json_lines(&v, &path)?;
        let value = serde_json::from_str(&text).expect("json_lines writes JSON");
        e3d::scene::path::set_path(&mut data, &path, value).map_err(|e| {
            let msg = format!("with_: {path}: {e}");
            scene_error(msg, Some("<with_>"), None, None, Some(path.clone()))
        })?;
    }
    let text = serde_json::to_string(&data).expect("JSON values serialise");
    let dict = overrides
        .py()
        .import("json")?
        .call_method1("loads", (text,))?;
    from_dict(&dict)
}

/// The scene's fields as Python data (see the module's doc).
pub(crate) fn to_dict<'py>(py: Python<'py>, scene: &e3d::Scene) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(scene).expect("a scene is plain data: it always serialises");
    py.import("json")?.call_method1("loads", (text,))
}

/// A scene from Python data, checked as `Scene.from_text` checks a scene.
pub(crate) fn from_dict(obj: &Bound<'_, PyAny>) -> PyResult<e3d::Scene> {
    const FILE: &str = "<dict>";
    if !obj.is_instance_of::<PyDict>() {
        return Err(PyTypeError::new_err(format!(
            "Scene.from_dict: expected a dict, found {}",
            obj.get_type().name()?
        )));
    }
    let (text, paths) = json_lines(obj, "")?;
    let spec: e3d::scene::SceneSpec = serde_json::from_str(&text).map_err(|e| {
        let line = e.line();
        let path = paths
            .get(line.saturating_sub(1))
            .cloned()
            .unwrap_or_default();
        // serde_json's message ends with " at line L column C": the line of
        // our text, which means nothing to the caller; the path does
        let msg = e.to_string();
        let msg = msg
            .rsplit_once(" at line ")
            .map_or(msg.as_str(), |(m, _)| m);
        let at = if path.is_empty() { "<scene>" } else { &path };
        scene_error(
            format!("{FILE}: {at}: {msg}"),
            Some(FILE),
            None,
            None,
            Some(path),
        )
    })?;
    spec.validate().map_err(scene_err)
}
