//! `e3d scene render`: a scene as SVG, with one command's path or its
//! animated rollout.

use super::simulate::{say_cost, world_error};
use crate::cli::console::outln;
use crate::cli::output::write_file;
use crate::cli::{CliError, CliResult};
use e3d::report::scene_svg::{scene_svg, Overlay};
use e3d::scene::{Scene, WorldSpec};
use e3d::world::GridSpec;
use e3d::{Command, GridWorld, World};

pub(super) fn render(scene: &Scene, command: Option<&str>, out: &std::path::Path) -> CliResult {
    let overlay = match command {
        None => None,
        Some(text) => {
            let space = scene.command_space();
            let c = space.parse(text).map_err(CliError::input)?;
            Some(overlay_of(scene, &c, &space.format(&c))?)
        }
    };
    let svg = scene_svg(scene, overlay.as_ref());
    write_file(out, svg.as_bytes())?;
    outln!("wrote {}", out.display());
    Ok(())
}

/// `e3d scene render --animate`: the command's rollout, animated (SVG, or
/// an HTML page when `out` ends in `.html`).
pub(super) fn animate(scene: &Scene, text: &str, out: &std::path::Path) -> CliResult {
    use e3d::report::motion_svg::{grid_motion_svg, html_page, motion_svg, thin, MAX_FRAMES};
    let space = scene.command_space();
    let c = space.parse(text).map_err(CliError::input)?;
    let cmd = space.format(&c);
    say_cost(&format!("scene render {}", scene.spec().name), scene, 1, 1);
    let (svg, what) = match scene.physics_world() {
        None => {
            let svg = grid_motion_svg(scene, &c).map_err(|e| CliError::input(e.to_string()))?;
            let keyframes = space.num_slots() + 1;
            (
                svg,
                format!(
                    "{keyframes} keyframes: the start and a cell per slot, {:.1} s",
                    keyframes as f64 * e3d::report::motion_svg::GRID_KEYFRAME_SECONDS
                ),
            )
        }
        Some(mut w) => {
            // only the frames drawn are kept, as they are computed
            let total = scene.spec().steps_per_command().unwrap_or(0) + 1;
            let keep = thin(total, MAX_FRAMES);
            let mut frames = Vec::with_capacity(keep.len());
            let mut motion = w
                .motion_each(&c, &mut |k, f| {
                    if keep.binary_search(&k).is_ok() {
                        frames.push(f);
                    }
                })
                .map_err(world_error)?;
            motion.frames = frames;
            let svg =
                motion_svg(scene, &cmd, &motion).map_err(|e| CliError::input(e.to_string()))?;
            (
                svg,
                format!(
                    "{} of {total} frames, {:.3} s",
                    motion.frames.len(),
                    motion.frames.last().map_or(0.0, |f| f.time)
                ),
            )
        }
    };
    let html = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
    let text = if html {
        html_page(&format!("{}: command {cmd}", scene.spec().name), &svg)
    } else {
        svg
    };
    write_file(out, text.as_bytes())?;
    outln!("wrote {} ({what})", out.display());
    Ok(())
}

pub(super) fn overlay_of(scene: &Scene, c: &Command, text: &str) -> Result<Overlay, CliError> {
    match (
        &scene.spec().world,
        GridWorld::from_scene(scene),
        scene.physics_world(),
    ) {
        (WorldSpec::Grid(g), Some(mut w), _) => {
            let o = w.execute(c).map_err(world_error)?;
            Ok(Overlay {
                command: text.to_string(),
                points: grid_path(&w, g, c),
                poses: None,
                effect: o.effect,
                reward: o.reward,
            })
        }
        (_, _, Some(mut w)) => {
            let t = w.trace(c).map_err(world_error)?;
            Ok(Overlay {
                command: text.to_string(),
                points: t.points,
                poses: Some(t.poses),
                effect: t.outcome.effect,
                reward: t.outcome.reward,
            })
        }
        _ => Err(CliError::input(format!(
            "scene {}: neither a grid nor a physics world",
            scene.spec().name
        ))),
    }
}

pub(super) fn grid_path(w: &GridWorld, g: &GridSpec, c: &Command) -> Vec<[f64; 2]> {
    w.path(c)
        .into_iter()
        .map(|cell| w.grid().center(cell / g.cols, cell % g.cols))
        .collect()
}
