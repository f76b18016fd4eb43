//! Scenes as Python data: `Scene.to_dict` (the scene's fields, as in its
//! RON text, the library's serde form) and `Scene.from_dict` (its JSON
//! lines written by python/e3d/_scene_dict.py, checked as a scene file is,
//! errors naming the path of the value at fault).

use crate::errors::{scene_err, scene_error};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

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
    let (text, paths): (String, Vec<String>) = obj
        .py()
        .import("e3d._scene_dict")?
        .call_method1("json_lines", (obj,))?
        .extract()?;
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
