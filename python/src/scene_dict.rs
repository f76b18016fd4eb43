//! Scenes as Python data: `Scene.to_dict` (the scene's fields, as in its
//! RON text), `Scene.from_dict` (checked as a scene file is, errors naming
//! the path of the value at fault) and `Scene.with_` (overrides by path).
//!
//! The dict form is the scene's serde form: a struct is a dict of its
//! fields, an enum variant with data a dict of one key, the variant's name
//! (`{"Physics": {...}}`, `{"Ball": {"radius": 0.1}}`), a variant without
//! data its name (`"Dynamic"`), a tuple a list.

use crate::errors::{scene_err, scene_error};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// JSON text of a Python value, one value per line, with the path of the
/// value each line holds (`world.Physics.bodies[2].mass`), so that a
/// parse error's line names a path.
struct Writer {
    text: String,
    paths: Vec<String>,
    /// The depth of the value being written.
    depth: usize,
}

/// The deepest nesting of dicts and lists a scene's data may have (a
/// scene's is under 15; a value that holds itself would recurse for ever).
const MAX_DEPTH: usize = 100;

impl Writer {
    fn line(&mut self, path: &str, s: &str) {
        self.text.push_str(s);
        self.text.push('\n');
        self.paths.push(path.to_string());
    }

    fn value(&mut self, path: &str, head: &str, v: &Bound<'_, PyAny>, tail: &str) -> PyResult<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let at = if path.is_empty() { "<scene>" } else { path };
            return Err(scene_error(
                format!(
                    "<dict>: {at}: nested more than {MAX_DEPTH} levels deep (a dict or list that holds itself?)"
                ),
                Some("<dict>"),
                None,
                None,
                Some(path.to_string()),
            ));
        }
        let r = self.nested(path, head, v, tail);
        self.depth -= 1;
        r
    }

    fn nested(&mut self, path: &str, head: &str, v: &Bound<'_, PyAny>, tail: &str) -> PyResult<()> {
        if let Ok(d) = v.cast::<PyDict>() {
            self.line(path, &format!("{head}{{"));
            let n = d.len();
            for (i, (k, x)) in d.iter().enumerate() {
                let key = k.cast::<PyString>().map_err(|_| {
                    PyTypeError::new_err(format!(
                        "{}: keys must be strings, found {}",
                        if path.is_empty() { "<scene>" } else { path },
                        k.repr().map(|r| r.to_string()).unwrap_or_default()
                    ))
                })?;
                let key = key.to_cow()?;
                let sub = if path.is_empty() {
                    key.to_string()
                } else {
                    format!("{path}.{key}")
                };
                let head = format!("{}: ", json_string(&key));
                self.value(&sub, &head, &x, if i + 1 < n { "," } else { "" })?;
            }
            self.line(path, &format!("}}{tail}"));
        } else if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
            let items: Vec<Bound<'_, PyAny>> = v.try_iter()?.collect::<PyResult<_>>()?;
            self.line(path, &format!("{head}["));
            let n = items.len();
            for (i, x) in items.iter().enumerate() {
                self.value(
                    &format!("{path}[{i}]"),
                    "",
                    x,
                    if i + 1 < n { "," } else { "" },
                )?;
            }
            self.line(path, &format!("]{tail}"));
        } else {
            let leaf = leaf_json(path, v)?;
            self.line(path, &format!("{head}{leaf}{tail}"));
        }
        Ok(())
    }
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).expect("a string serialises")
}

/// A scalar as JSON (numpy scalars through `float()` / `int()`).
fn leaf_json(path: &str, v: &Bound<'_, PyAny>) -> PyResult<String> {
    if v.is_none() {
        return Ok("null".into());
    }
    if let Ok(b) = v.cast::<PyBool>() {
        return Ok(b.is_true().to_string());
    }
    if let Ok(s) = v.cast::<PyString>() {
        return Ok(json_string(&s.to_cow()?));
    }
    if v.is_instance_of::<PyInt>() {
        if let Ok(i) = v.extract::<i64>() {
            return Ok(i.to_string());
        }
        if let Ok(u) = v.extract::<u64>() {
            return Ok(u.to_string());
        }
        return Err(scene_error(
            format!("<dict>: {path}: {} is out of range for any field", v.str()?),
            Some("<dict>"),
            None,
            None,
            Some(path.to_string()),
        ));
    }
    let is_float = v.is_instance_of::<PyFloat>() || v.hasattr("__float__")?;
    if is_float {
        if v.hasattr("__index__")? {
            if let Ok(i) = v.extract::<i64>() {
                return Ok(i.to_string());
            }
        }
        let x: f64 = v.extract()?;
        if !x.is_finite() {
            return Err(scene_error(
                format!("<dict>: {path}: {x} is not a finite number"),
                Some("<dict>"),
                None,
                None,
                Some(path.to_string()),
            ));
        }
        return Ok(serde_json::to_string(&x).expect("a finite float serialises"));
    }
    Err(PyTypeError::new_err(format!(
        "{path}: expected a dict, list, str, number, bool or None, found {}",
        v.get_type().name()?
    )))
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
    let mut w = Writer {
        text: String::new(),
        paths: Vec::new(),
        depth: 0,
    };
    w.value("", "", obj, "")?;
    let spec: e3d::scene::SceneSpec = serde_json::from_str(&w.text).map_err(|e| {
        let line = e.line();
        let path = w
            .paths
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

/// `data` (a scene's dict) with `value` at `path`: dot-separated keys;
/// a list's element by index or by its `name`; a one-key dict (an enum
/// variant such as `{"Physics": {...}}`) may be stepped through without
/// naming it; and a path whose first key is not a field of the scene
/// starts in the world (`bodies.puck.mass`).
pub(crate) fn set_path(
    data: &Bound<'_, PyAny>,
    path: &str,
    value: &Bound<'_, PyAny>,
) -> PyResult<()> {
    let bad = |msg: String| {
        scene_error(
            format!("with_: {path}: {msg}"),
            Some("<with_>"),
            None,
            None,
            Some(path.to_string()),
        )
    };
    let keys: Vec<&str> = path.split('.').collect();
    if keys.iter().any(|k| k.is_empty()) {
        return Err(bad(
            "expected dot-separated names, e.g. bodies.puck.linear_damping".into(),
        ));
    }
    let mut at = data.clone();
    let top = data.cast::<PyDict>()?;
    if !top.contains(keys[0])? {
        at = top
            .get_item("world")?
            .ok_or_else(|| bad("the scene has no world".into()))?;
    }
    for (i, key) in keys.iter().enumerate() {
        let last = i + 1 == keys.len();
        at = through_variants(at, key)?;
        if let Ok(d) = at.cast::<PyDict>() {
            if last {
                if !d.contains(*key)? {
                    return Err(bad(no_field(d, key)));
                }
                d.set_item(*key, value)?;
                return Ok(());
            }
            at = d.get_item(*key)?.ok_or_else(|| bad(no_field(d, key)))?;
        } else if let Ok(l) = at.cast::<PyList>() {
            let idx = list_index(l, key).map_err(bad)?;
            if last {
                l.set_item(idx, value)?;
                return Ok(());
            }
            at = l.get_item(idx)?;
        } else {
            return Err(bad(format!("`{key}`: {} has no fields", at.repr()?)));
        }
    }
    Ok(())
}

/// `at` stepped through the one-key dicts of enum variants (such as
/// `{"Physics": {...}}`) down to the first dict that holds `key`, or that
/// is not a variant's.
fn through_variants<'py>(mut at: Bound<'py, PyAny>, key: &str) -> PyResult<Bound<'py, PyAny>> {
    loop {
        let Ok(d) = at.cast::<PyDict>() else { break };
        if d.contains(key)? || d.len() != 1 {
            break;
        }
        let (k, v) = d.iter().next().expect("one item");
        let variant = k.extract::<String>().unwrap_or_default();
        if !variant.starts_with(|c: char| c.is_ascii_uppercase()) {
            break;
        }
        at = v;
    }
    Ok(at)
}

/// The message for a dict without the field `key`: the fields it has.
fn no_field(d: &Bound<'_, PyDict>, key: &str) -> String {
    let keys: Vec<String> = d.keys().iter().map(|k| k.to_string()).collect();
    format!("no field `{key}` here; its fields: {}", keys.join(", "))
}

/// The index `key` names in a list: a number below its length, or the
/// `name` of one of its dicts; else the message saying why not.
fn list_index(l: &Bound<'_, PyList>, key: &str) -> Result<usize, String> {
    match key.parse::<usize>() {
        Ok(n) if n < l.len() => Ok(n),
        Ok(n) => Err(format!("index {n}: the list has {} items", l.len())),
        Err(_) => {
            let names: Vec<String> = l
                .iter()
                .filter_map(|x| {
                    x.cast::<PyDict>()
                        .ok()?
                        .get_item("name")
                        .ok()??
                        .extract::<String>()
                        .ok()
                })
                .collect();
            names
                .iter()
                .position(|n| n == key)
                .ok_or_else(|| format!("no item named `{key}`; the names: {}", names.join(", ")))
        }
    }
}
