//! Pictures of scenes: `Scene.svg(command)` and `Scene._repr_svg_`, the
//! library's SVG (`e3d scene render`), with a command's path if given.

use crate::commands::{commands_from, values_from};
use crate::errors::Fail;
use crate::scene::PyScene;
use e3d::report::scene_svg::{scene_svg, Overlay};
use e3d::scene::WorldSpec;
use e3d::world::GridWorld;
use e3d::World;
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
            let (Some(mut w), WorldSpec::Grid(g)) = (GridWorld::from_scene(inner), &inner.world)
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
