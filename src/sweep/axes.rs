//! The scene axes of a sweep: each scene once per combination of the
//! values of fields set by path ([`SweepSpec::axes`]).

use super::factory::SweepScene;
use super::spec::SweepSpec;
use super::summary::format_number;
use super::SweepError;
use std::sync::Arc;

/// Derived scenes, and the scene axes' values of each.
pub(super) type Derived = (Vec<Arc<SweepScene>>, Vec<Vec<f64>>);

/// Each of `scenes` once per combination of the scene axes' values `axes`
/// (the last axis fastest), the fields at their paths set, and the axes'
/// values of each; the scenes themselves without axes. A scene made by
/// code as worlds (a [`LiveScene`](super::LiveScene)) has no fields to
/// set; a path a scene lacks, or a value its checks refuse, is an error
/// at the path.
pub(super) fn derive_scenes(
    spec: &SweepSpec,
    scenes: Vec<Arc<SweepScene>>,
    axes: &[Vec<f64>],
    bad: &dyn Fn(&str, Option<&str>, &str) -> SweepError,
) -> Result<Derived, SweepError> {
    if axes.is_empty() {
        let n = scenes.len();
        return Ok((scenes, vec![Vec::new(); n]));
    }
    let count: usize = axes.iter().map(Vec::len).product();
    let combos: Vec<Vec<f64>> = (0..count)
        .map(|mut k| {
            let mut v = vec![0.0; axes.len()];
            for i in (0..axes.len()).rev() {
                v[i] = axes[i][k % axes[i].len()];
                k /= axes[i].len();
            }
            v
        })
        .collect();
    let (mut derived, mut values) = (Vec::new(), Vec::new());
    for s in &scenes {
        let Some(scene) = s.scene() else {
            let name = s.name();
            let expected = format!(
                "scenes with fields to set by the axes, found `{name}`, worlds made by code"
            );
            return Err(bad("scenes", Some(&format!("\"{name}\"")), &expected));
        };
        let refused = |path: &str, v: f64, e: crate::scene::SceneError| {
            let why = match e.kind() {
                crate::scene::SceneErrorKind::Invalid { expected, .. } => expected.clone(),
                _ => e.to_string(),
            };
            let name = &scene.spec().name;
            let v = format_number(v);
            let expected = format!("a path to a field of scene `{name}` and values it takes, found `{path}` = {v}: {why}");
            bad("axes", Some(&format!("{path:?}")), &expected)
        };
        // each path and value alone first, so that an error names the
        // path and the value at fault
        for ((path, _), values) in spec.axes.iter().zip(axes) {
            for &v in values {
                let one = [(path.as_str(), axis_value(v))];
                scene.with_paths(one).map_err(|e| refused(path, v, e))?;
            }
        }
        for combo in &combos {
            let paths = spec.axes.iter().map(|(p, _)| p.as_str());
            let overrides = paths.zip(combo.iter().map(|&v| axis_value(v)));
            let one = scene.with_paths(overrides).map_err(|e| {
                let at = spec
                    .axes
                    .iter()
                    .position(|(p, _)| e.field() == Some(p.as_str()));
                let i = at.unwrap_or(0);
                refused(&spec.axes[i].0, combo[i], e)
            })?;
            derived.push(Arc::new(SweepScene::Scene(one)));
            values.push(combo.clone());
        }
    }
    Ok((derived, values))
}

/// A scene axis's value in a scene's serde form: a whole number as an
/// integer (which a count such as `command.slots` needs, and a float
/// field reads too), any other as a float.
fn axis_value(v: f64) -> serde_json::Value {
    if v.fract() == 0.0 && v.abs() < 9.0e15 {
        serde_json::Value::from(v as i64)
    } else {
        serde_json::Value::from(v)
    }
}
