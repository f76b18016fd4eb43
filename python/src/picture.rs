//! Pictures of scenes: `Scene.svg(command)` and `Scene._repr_svg_`, the
//! library's SVG (`e3d scene render`), with a command's path if given;
//! `Scene.render`, that SVG rasterised to an RGB array; `Scene.geometry`,
//! what the picture draws as plain data.

use crate::commands::{commands_from, values_from};
use crate::errors::Fail;
use crate::scene::PyScene;
use e3d::report::scene_svg::{scene_svg, Overlay};
use e3d::scene::physics::{BodySpec, PhysicsSpec, ShapeSpec};
use e3d::scene::WorldSpec;
use e3d::world::GridWorld;
use e3d::World;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

/// The SVG of `scene`, with the path of `command` (symbols, or values on
/// a continuous scene) when given: what `e3d scene render SCENE
/// [--command C]` draws.
pub(crate) fn svg(
    py: Python<'_>,
    scene: &PyScene,
    command: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let inner = &scene.inner;
    let Some(command) = command.filter(|c| !c.is_none()) else {
        return Ok(scene_svg(inner, None));
    };
    let overlay = match (inner.physics_world(), &scene.values) {
        (Some(mut w), Some(space)) => {
            let v = values_from(py, space, command, 1)?.remove(0);
            let t = py.detach(|| w.trace_values(&v)).map_err(Fail::from)?;
            Overlay {
                command: space.format(&v),
                points: t.points,
                poses: Some(t.poses),
                effect: t.outcome.effect,
                reward: t.outcome.reward,
            }
        }
        (Some(mut w), None) => {
            let c = commands_from(py, &scene.space, command, 1)?.remove(0);
            let t = py.detach(|| w.trace(&c)).map_err(Fail::from)?;
            Overlay {
                command: scene.space.format(&c),
                points: t.points,
                poses: Some(t.poses),
                effect: t.outcome.effect,
                reward: t.outcome.reward,
            }
        }
        (None, _) => {
            scene.require_symbols("Scene.svg")?;
            let c = commands_from(py, &scene.space, command, 1)?.remove(0);
            // a scene is a grid when it is not physics
            let (Some(mut w), WorldSpec::Grid(g)) =
                (GridWorld::from_scene(inner), &inner.spec().world)
            else {
                return Ok(scene_svg(inner, None));
            };
            let o = w.execute(&c).map_err(Fail::from)?;
            let points = w
                .path(&c)
                .into_iter()
                .map(|cell| w.grid().center(cell / g.cols, cell % g.cols))
                .collect();
            Overlay {
                command: scene.space.format(&c),
                points,
                poses: None,
                effect: o.effect,
                reward: o.reward,
            }
        }
    };
    Ok(scene_svg(inner, Some(&overlay)))
}

/// `svg` rasterised (resvg, without text: the title, labels and legend
/// need fonts) at `scale` pixels per SVG pixel: `(height, width, rgb)`,
/// composited over white.
pub(crate) fn rasterise(svg: &str, scale: f64) -> PyResult<(usize, usize, Vec<u8>)> {
    use resvg::{tiny_skia, usvg};
    if !(scale.is_finite() && scale > 0.0 && scale <= 16.0) {
        return Err(PyValueError::new_err(format!(
            "scale = {scale}: expected a number in (0, 16]"
        )));
    }
    let scale = scale as f32;
    let tree = usvg::Tree::from_str(svg, &usvg::Options::default())
        .map_err(|e| PyValueError::new_err(format!("the scene's SVG does not parse: {e}")))?;
    let size = tree.size();
    let w = ((size.width() * scale).ceil() as u32).max(1);
    let h = ((size.height() * scale).ceil() as u32).max(1);
    let mut pix = tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| PyValueError::new_err(format!("a picture of {w}x{h} pixels")))?;
    pix.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(scale, scale),
        &mut pix.as_mut(),
    );
    // opaque over white: premultiplied RGBA is RGB plus (255 - a)
    let rgb = pix
        .data()
        .chunks_exact(4)
        .flat_map(|p| {
            let add = 255 - p[3];
            [p[0] + add, p[1] + add, p[2] + add]
        })
        .collect();
    Ok((h as usize, w as usize, rgb))
}

/// The scene's geometry as plain data (see `Scene.geometry`).
pub(crate) fn geometry<'py>(py: Python<'py>, scene: &e3d::Scene) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let g = scene.effect_grid();
    let grid = PyDict::new(py);
    grid.set_item("rows", g.rows)?;
    grid.set_item("cols", g.cols)?;
    grid.set_item("min", (g.min[0], g.min[1]))?;
    grid.set_item("max", (g.max[0], g.max[1]))?;
    d.set_item("effect_grid", grid)?;
    let rewarded: Vec<(usize, usize)> = scene
        .reward_table()
        .iter()
        .enumerate()
        .filter(|(_, &r)| r != 0.0)
        .map(|(e, _)| (e / g.cols, e % g.cols))
        .collect();
    d.set_item("reward_cells", rewarded)?;
    match &scene.spec().world {
        WorldSpec::Grid(spec) => {
            d.set_item("kind", "grid")?;
            d.set_item("start", spec.start)?;
            d.set_item("walls", spec.walls.clone())?;
        }
        WorldSpec::Physics(p) => physics_geometry(py, &d, p)?,
    }
    Ok(d)
}

/// A physics world's geometry, into `d`: its bodies (outlines in world
/// coordinates), its joints (where they hold the child) and the tracked
/// point.
fn physics_geometry(py: Python<'_>, d: &Bound<'_, PyDict>, p: &PhysicsSpec) -> PyResult<()> {
    d.set_item("kind", "physics")?;
    let bodies = PyList::empty(py);
    for b in &p.bodies {
        bodies.append(body_geometry(py, b)?)?;
    }
    d.set_item("bodies", bodies)?;
    let joints = PyList::empty(py);
    for j in &p.joints {
        let e = PyDict::new(py);
        e.set_item("name", &j.name)?;
        e.set_item("parent", &j.parent)?;
        e.set_item("child", &j.child)?;
        let at = p
            .body(&j.child)
            .map(|c| world_point(c, j.child_anchor))
            .unwrap_or((f64::NAN, f64::NAN));
        e.set_item("position", at)?;
        joints.append(e)?;
    }
    d.set_item("joints", joints)?;
    let t = p.body(&p.effect.body).expect("validated: tracked body");
    d.set_item("tracked_point", world_point(t, p.effect.point))?;
    d.set_item("tracked_body", &p.effect.body)?;
    Ok(())
}

/// A point of body `b` (in its own frame) in world coordinates.
fn world_point(b: &BodySpec, q: (f64, f64)) -> (f64, f64) {
    e3d::scene::physics::to_world_point(b.position, b.angle, q)
}

/// A body's geometry: its name, kind, pose, shape, radius and outline
/// (points in world coordinates).
fn body_geometry<'py>(py: Python<'py>, b: &BodySpec) -> PyResult<Bound<'py, PyDict>> {
    let w = world_point;
    let e = PyDict::new(py);
    e.set_item("name", &b.name)?;
    e.set_item("kind", format!("{:?}", b.kind).to_lowercase())?;
    e.set_item("position", b.position)?;
    e.set_item("angle", b.angle)?;
    match &b.shape {
        ShapeSpec::Ball { radius } => {
            e.set_item("shape", "ball")?;
            e.set_item("radius", radius)?;
            e.set_item("points", vec![b.position])?;
        }
        ShapeSpec::Cuboid { width, height } => {
            let (x, y) = (width / 2.0, height / 2.0);
            e.set_item("shape", "cuboid")?;
            e.set_item("radius", 0.0)?;
            let corners = [(-x, -y), (x, -y), (x, y), (-x, y), (-x, -y)];
            e.set_item("points", corners.map(|c| w(b, c)).to_vec())?;
        }
        ShapeSpec::Capsule { a, b: end, radius } => {
            e.set_item("shape", "capsule")?;
            e.set_item("radius", radius)?;
            e.set_item("points", vec![w(b, *a), w(b, *end)])?;
        }
        ShapeSpec::Segment { a, b: end } => {
            e.set_item("shape", "segment")?;
            e.set_item("radius", 0.0)?;
            e.set_item("points", vec![w(b, *a), w(b, *end)])?;
        }
        ShapeSpec::Polyline { points } => {
            e.set_item("shape", "polyline")?;
            e.set_item("radius", 0.0)?;
            let pts: Vec<(f64, f64)> = points.iter().map(|&q| w(b, q)).collect();
            e.set_item("points", pts)?;
        }
    }
    Ok(e)
}
