//! Pictures of scenes: `Scene.svg(command)` and `Scene._repr_svg_`, the
//! library's SVG (`e3d scene render`), with a command's path if given;
//! `Scene.render`, that SVG rasterised to an RGB array (`Scene.geometry`,
//! what the picture draws as plain data, is python/e3d/_scene_dict.py's).

use crate::commands::{commands_from, values_from};
use crate::errors::Fail;
use crate::scene::PyScene;
use e3d::report::scene_svg::{scene_svg, Overlay};
use e3d::scene::WorldSpec;
use e3d::world::GridWorld;
use e3d::World;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

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
        (Some(mut w), values) => {
            let (text, t) = match values {
                Some(space) => {
                    let v = values_from(py, space, command, 1)?.remove(0);
                    (space.format(&v), py.detach(|| w.trace_values(&v)))
                }
                None => {
                    let c = commands_from(py, &scene.space, command, 1)?.remove(0);
                    (scene.space.format(&c), py.detach(|| w.trace(&c)))
                }
            };
            let t = t.map_err(Fail::from)?;
            Overlay {
                command: text,
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
