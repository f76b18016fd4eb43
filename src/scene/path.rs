//! A scene's fields set by path, over its serde form: the overrides of a
//! sweep's scene axes and of Python's `Scene.with_`.
//!
//! The serde form is the scene's JSON: a struct is an object of its
//! fields, an enum variant with data an object of one key, the variant's
//! name (`{"Physics": {...}}`), a tuple an array. A path is dot-separated
//! keys: a field by name, a list's item by index (`bodies.2` or
//! `bodies[2]`) or by its `name` (`joints.j1`); an enum variant may be
//! stepped through without naming it (`world.bodies`, not
//! `world.Physics.bodies`); a path whose first key is not a field of the
//! scene starts in the world (`bodies.puck.mass`). A field the scene
//! leaves out (`noise`, `slots`) is created; the scene is then read and
//! checked as a scene file is, so a name that is no field is refused
//! there with the fields it could be.

use super::{Invalid, Scene, SceneError, SceneSpec};
use serde_json::{Map, Value};

/// The fields of a scene (docs/scenes.md), those it may leave out included.
const SCENE_FIELDS: [&str; 6] = ["name", "description", "world", "slots", "command", "reward"];

/// Sets `value` at `path` in `data`, a scene's serde form (see the
/// module's doc); the error says why the path leads nowhere and what
/// was there.
///
/// ```
/// use e3d::scene::path::set_path;
/// let mut data = serde_json::json!({"name": "s", "world": {"Physics": {"bodies": [{"name": "puck", "mass": 1.0}]}}});
/// set_path(&mut data, "bodies.puck.mass", 2.0.into()).unwrap();
/// set_path(&mut data, "world.bodies[0].mass", 3.0.into()).unwrap();
/// assert_eq!(data["world"]["Physics"]["bodies"][0]["mass"], 3.0);
/// let e = set_path(&mut data, "bodies.ball.mass", 2.0.into()).unwrap_err();
/// assert_eq!(e, "no item named `ball`; the names: puck");
/// ```
pub fn set_path(data: &mut Value, path: &str, value: Value) -> Result<(), String> {
    let keys = split(path)?;
    let Value::Object(top) = data else {
        return Err("the scene's data is not a dict of fields".into());
    };
    if SCENE_FIELDS.contains(&keys[0].as_str()) && !top.contains_key(&keys[0]) {
        // an optional field the scene leaves out (`slots`, the check of
        // the number of slots): set whole, then checked with the scene
        if keys.len() > 1 {
            let k = &keys[0];
            return Err(format!(
                "the scene has no `{k}` to step into: set `{k}` whole"
            ));
        }
        top.insert(keys[0].clone(), value);
        return Ok(());
    }
    let at = if top.contains_key(&keys[0]) {
        data
    } else {
        top.get_mut("world").ok_or("the scene has no world")?
    };
    set_in(at, &keys, value)
}

/// The keys of `path`: `a.b[2].c` is `a`, `b`, `2`, `c`.
fn split(path: &str) -> Result<Vec<String>, String> {
    let bad = || "expected dot-separated names, e.g. bodies.puck.linear_damping".to_string();
    let mut keys = Vec::new();
    for part in path.split('.') {
        let (name, mut rest) = part.split_once('[').map_or((part, ""), |(n, r)| (n, r));
        if name.is_empty() || part.ends_with('[') {
            return Err(bad());
        }
        keys.push(name.to_string());
        while !rest.is_empty() {
            let (index, after) = rest.split_once(']').ok_or_else(bad)?;
            if index.is_empty() || !index.bytes().all(|b| b.is_ascii_digit()) {
                return Err(bad());
            }
            keys.push(index.to_string());
            rest = after.strip_prefix('[').unwrap_or(after);
            if !after.is_empty() && !after.starts_with('[') {
                return Err(bad());
            }
        }
    }
    Ok(keys)
}

/// Whether `key` is an enum variant's name (it starts with a capital).
fn is_variant(key: &str) -> bool {
    key.starts_with(|c: char| c.is_ascii_uppercase())
}

/// `value` at `keys` in `at`: each key a field of an object (stepping
/// through one-key objects of enum variants, creating a field that is
/// missing), an index or a name in a list.
fn set_in(at: &mut Value, keys: &[String], value: Value) -> Result<(), String> {
    let Some((key, rest)) = keys.split_first() else {
        *at = value;
        return Ok(());
    };
    if at.is_null() {
        // an optional field left out: created, read back with the scene
        *at = Value::Object(Map::new());
    }
    match at {
        // an enum variant's one-key object without `key`: stepped through
        Value::Object(m)
            if !m.contains_key(key) && m.len() == 1 && m.keys().all(|k| is_variant(k)) =>
        {
            let inner = m.values_mut().next().expect("one key");
            set_in(inner, keys, value)
        }
        // a missing field is created: the scene's reading refuses one
        // that is not a field, naming those that are
        Value::Object(m) => set_in(m.entry(key.clone()).or_insert(Value::Null), rest, value),
        Value::Array(items) => {
            let idx = match key.parse::<usize>() {
                Ok(idx) if idx < items.len() => idx,
                Ok(idx) => return Err(format!("index {idx}: the list has {} items", items.len())),
                Err(_) => {
                    let names: Vec<&str> = items
                        .iter()
                        .filter_map(|x| x.get("name")?.as_str())
                        .collect();
                    let Some(idx) = names.iter().position(|n| n == key) else {
                        let names = names.join(", ");
                        return Err(format!("no item named `{key}`; the names: {names}"));
                    };
                    idx
                }
            };
            set_in(&mut items[idx], rest, value)
        }
        other => Err(format!("`{key}`: {other} has no fields")),
    }
}

impl Scene {
    /// A copy of the scene with `value` at each `(path, value)` of
    /// `overrides` in its serde form ([`set_path`]), read and checked as
    /// the loader reads and checks a scene file. The error names the path
    /// (its field) and what was expected.
    ///
    /// ```
    /// use e3d::Scene;
    /// let arm = Scene::builtin("arm7").unwrap();
    /// let stiff = arm.with_paths([("joints.j1.damping", 2.0.into())]).unwrap();
    /// assert_ne!(stiff, arm);
    /// let e = arm.with_paths([("joints.j1.dampin", 2.0.into())]).unwrap_err();
    /// assert!(e.to_string().contains("unknown field `dampin`, expected one of"));
    /// let e = arm.with_paths([("joints.j1.damping", (-1.0).into())]).unwrap_err();
    /// assert!(e.to_string().contains("found -1"));
    /// ```
    pub fn with_paths<'a>(
        &self,
        overrides: impl IntoIterator<Item = (&'a str, Value)>,
    ) -> Result<Scene, SceneError> {
        let spec = self.spec();
        let file = format!("<scene {}>", spec.name);
        let mut data = serde_json::to_value(spec).expect("a scene is plain data");
        let mut last = "";
        for (path, value) in overrides {
            set_path(&mut data, path, value)
                .map_err(|e| SceneError::invalid(&file, Invalid::new(path, e), None))?;
            last = path;
        }
        let spec: SceneSpec = serde_json::from_value(data)
            .map_err(|e| SceneError::invalid(&file, Invalid::new(last, e.to_string()), None))?;
        spec.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_split_at_dots_and_indices() {
        assert_eq!(split("a.b[2][0].c").unwrap(), ["a", "b", "2", "0", "c"]);
        for bad in ["", "a..b", "a[", "a[x]", "a[1]b", "[1]"] {
            assert!(split(bad).is_err(), "{bad}");
        }
    }
}
