//! `e3d scene render`: a scene as SVG, with one command's path or its
//! animated rollout.

use super::simulate::{say_cost, world_error};
use crate::cli::console::{errln, outln};
use crate::cli::output::write_file;
use crate::cli::{CliError, CliResult};
use e3d::report::scene_svg::{posed_svg, scene_svg, Overlay};
use e3d::scene::{Scene, WorldSpec};
use e3d::world::GridSpec;
use e3d::world::GridWorld;
use e3d::{Command, World};

pub(super) fn render(
    scene: &Scene,
    command: Option<&str>,
    context: Option<&str>,
    out: &std::path::Path,
) -> CliResult {
    let contexts = e3d::world::start_contexts(scene);
    if !contexts.is_empty() {
        return render_contexts(scene, &contexts, command, context, out);
    }
    if let Some(name) = context {
        return Err(no_contexts(scene, name));
    }
    let command = parse(scene, command)?;
    let overlay = command.map(|c| overlay_of(scene, &c)).transpose()?;
    let svg = scene_svg(scene, overlay.as_ref());
    write_file(out, svg.as_bytes())?;
    outln!("wrote {}", out.display());
    Ok(())
}

/// The index of the context `name` of `contexts`, or an error naming
/// them.
pub(super) fn context_index(
    scene: &Scene,
    contexts: &[e3d::world::StartContext],
    name: &str,
) -> Result<usize, CliError> {
    contexts.iter().position(|c| c.name == name).ok_or_else(|| {
        let names: Vec<&str> = contexts.iter().map(|c| c.name.as_str()).collect();
        let (scene, names) = (&scene.spec().name, names.join(", "));
        CliError::input(format!(
            "scene {scene}: no start context `{name}` (its contexts: {names})"
        ))
    })
}

/// `e3d scene render` on a scene with start contexts: one panel per
/// context (only `context`'s when given), stacked, each titled with the
/// context's name and drawn from its start (a drawn context: its seed-0
/// draw, said on stderr and in the title), with `command`'s path from
/// there if given.
fn render_contexts(
    scene: &Scene,
    contexts: &[e3d::world::StartContext],
    command: Option<&str>,
    context: Option<&str>,
    out: &std::path::Path,
) -> CliResult {
    let chosen: Vec<usize> = match context {
        Some(name) => vec![context_index(scene, contexts, name)?],
        None => (0..contexts.len()).collect(),
    };
    let command = parse(scene, command)?;
    let world = scene.build();
    let mut panels = Vec::new();
    for k in chosen {
        let ctx = &contexts[k];
        let from = e3d::world::seed0_start(&world, k).map_err(world_error)?;
        if ctx.drawn {
            let (scene, name) = (&scene.spec().name, &ctx.name);
            errln!("scene {scene}: context {name} is drawn from a range; the picture shows its seed-0 draw (as `e3d scene exec` runs it)");
        }
        let drawn = if ctx.drawn {
            " (drawn: its seed-0 start)"
        } else {
            ""
        };
        let label = format!("{}: context {}{drawn}", scene.spec().name, ctx.name);
        panels.push(context_panel(scene, &label, &from, command.as_ref())?);
    }
    let (count, s) = (panels.len(), crate::cli::plural(panels.len()));
    write_file(out, stack_svgs(&panels).as_bytes())?;
    outln!("wrote {} ({count} start context{s})", out.display());
    Ok(())
}

/// The picture of `scene` from the start `from`, titled `label`, with
/// `command`'s path from there if given.
fn context_panel(
    scene: &Scene,
    label: &str,
    from: &e3d::world::WorldState,
    command: Option<&Command>,
) -> Result<String, CliError> {
    let space = scene.command_space();
    match (from, &scene.spec().world) {
        (e3d::world::WorldState::Cell(cell), WorldSpec::Grid(_)) => {
            let titled = started_at(scene, *cell, Some(label))?;
            let overlay = command.map(|c| overlay_of(&titled, c)).transpose()?;
            Ok(scene_svg(&titled, overlay.as_ref()))
        }
        (e3d::world::WorldState::Physics(state), WorldSpec::Physics(_)) => {
            let mut spec = scene.to_spec();
            spec.name = label.to_string();
            let titled = spec.validate().map_err(CliError::input)?;
            let overlay = match command {
                Some(c) => {
                    let mut w = scene.physics_world().expect("a physics scene");
                    let t = w.from_start(from, |w| w.trace(c)).and_then(|t| t);
                    Some(traced(space.format(c), t.map_err(world_error)?))
                }
                None => None,
            };
            let start: Vec<e3d::world::BodyPose> = state
                .poses
                .iter()
                .map(|p| e3d::world::BodyPose {
                    position: [p[0], p[1]],
                    angle: p[2],
                })
                .collect();
            Ok(posed_svg(&titled, &start, overlay.as_ref()))
        }
        _ => Err(CliError::input(format!(
            "scene {}: a start this picture cannot draw",
            scene.spec().name
        ))),
    }
}

/// SVG pictures stacked top to bottom in one SVG (each keeps its own
/// size; the whole is as wide as the widest).
pub(super) fn stack_svgs(panels: &[String]) -> String {
    if let [one] = panels {
        return one.clone();
    }
    let size = |svg: &str, what: &str| -> f64 {
        let key = format!(" {what}=\"");
        svg.find(&key)
            .and_then(|i| {
                let rest = &svg[i + key.len()..];
                rest[..rest.find('"')?].parse().ok()
            })
            .unwrap_or(0.0)
    };
    let width = panels.iter().map(|p| size(p, "width")).fold(0.0, f64::max);
    let height: f64 = panels.iter().map(|p| size(p, "height")).sum();
    let mut out = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\">\n"
    );
    let mut y = 0.0;
    for p in panels {
        out.push_str(&p.replacen("<svg ", &format!("<svg x=\"0\" y=\"{y:.0}\" "), 1));
        if !out.ends_with('\n') {
            out.push('\n');
        }
        y += size(p, "height");
    }
    out.push_str("</svg>\n");
    out
}

/// The error of `--context NAME` on a scene without start contexts.
fn no_contexts(scene: &Scene, name: &str) -> CliError {
    CliError::input(format!(
        "scene {} has no start contexts (`--context {name}`): it has one start, drawn without `--context`",
        scene.spec().name
    ))
}

/// The start of the context `name` (its seed-0 draw when drawn from a
/// range, said on stderr), for `scene render --animate --context`.
fn animation_start(scene: &Scene, name: &str) -> Result<e3d::world::WorldState, CliError> {
    let contexts = e3d::world::start_contexts(scene);
    if contexts.is_empty() {
        return Err(no_contexts(scene, name));
    }
    let k = context_index(scene, &contexts, name)?;
    if contexts[k].drawn {
        errln!(
            "scene {}: context {name} is drawn from a range; the animation starts from its seed-0 draw (as `e3d scene exec` runs it)",
            scene.spec().name
        );
    }
    e3d::world::seed0_start(&*scene.build(), k).map_err(world_error)
}

/// `e3d scene render --animate`: the command's rollout, animated (SVG, or
/// an HTML page when `out` ends in `.html`), from the start of the context
/// `context` if given, else from the scene's listed start.
pub(super) fn animate(
    scene: &Scene,
    text: &str,
    context: Option<&str>,
    out: &std::path::Path,
) -> CliResult {
    let space = scene.command_space();
    let c = space.parse(text).map_err(CliError::input)?;
    let cmd = space.format(&c);
    let from = context
        .map(|name| animation_start(scene, name))
        .transpose()?;
    let label = format!("scene render {}", scene.spec().name);
    say_cost(&label, scene, 1, 1, 1);
    let (svg, what) = match scene.physics_world() {
        None => animate_grid(scene, &c, from.as_ref())?,
        Some(w) => animate_physics(scene, w, &c, &cmd, from.as_ref())?,
    };
    write_file(out, animation_page(scene, &cmd, svg, out).as_bytes())?;
    outln!("wrote {} ({what})", out.display());
    Ok(())
}

/// A grid scene's animation of `c` from its start cell (the context's
/// `from`, if given), and what it holds.
fn animate_grid(
    scene: &Scene,
    c: &Command,
    from: Option<&e3d::world::WorldState>,
) -> Result<(String, String), CliError> {
    use e3d::report::motion_svg::{grid_motion_svg, GRID_KEYFRAME_SECONDS};
    // a grid's start is its `start` cell: the context's, if given
    let started = match from {
        Some(e3d::world::WorldState::Cell(cell)) => Some(started_at(scene, *cell, None)?),
        _ => None,
    };
    let svg = grid_motion_svg(started.as_ref().unwrap_or(scene), c)
        .map_err(|e| CliError::input(e.to_string()))?;
    let keyframes = scene.command_space().num_slots() + 1;
    let what = format!(
        "{keyframes} keyframes: the start and a cell per slot, {:.1} s",
        keyframes as f64 * GRID_KEYFRAME_SECONDS
    );
    Ok((svg, what))
}

/// The grid scene `scene` started at `cell`, named `name` if given.
fn started_at(scene: &Scene, cell: usize, name: Option<&str>) -> Result<Scene, CliError> {
    let mut spec = scene.to_spec();
    if let Some(name) = name {
        spec.name = name.to_string();
    }
    if let WorldSpec::Grid(g) = &mut spec.world {
        g.start = (cell / g.cols, cell % g.cols);
    }
    spec.validate().map_err(CliError::input)
}

/// A physics scene's animation of `c` (written `cmd`) on the world `w`,
/// from the context's start `from` if given, and what it holds.
fn animate_physics(
    scene: &Scene,
    mut w: e3d::world::PhysicsWorld,
    c: &Command,
    cmd: &str,
    from: Option<&e3d::world::WorldState>,
) -> Result<(String, String), CliError> {
    use e3d::report::motion_svg::{motion_svg, motion_svg_from, thin, MAX_FRAMES};
    // only the frames drawn are kept, as they are computed
    let total = scene.spec().steps_per_command().unwrap_or(0) + 1;
    let keep = thin(total, MAX_FRAMES);
    let mut frames = Vec::with_capacity(keep.len());
    let mut each = |k: usize, f| {
        if keep.binary_search(&k).is_ok() {
            frames.push(f);
        }
    };
    let mut motion = match from {
        Some(from) => w
            .from_start(from, |w| w.motion_each(c, &mut each))
            .and_then(|m| m),
        None => w.motion_each(c, &mut each),
    }
    .map_err(world_error)?;
    motion.frames = frames;
    let svg = match from {
        Some(_) => motion_svg_from(scene, cmd, &motion),
        None => motion_svg(scene, cmd, &motion),
    }
    .map_err(|e| CliError::input(e.to_string()))?;
    let (k, time) = (
        motion.frames.len(),
        motion.frames.last().map_or(0.0, |f| f.time),
    );
    let what = format!("{k} of {total} frames, {time:.3} s");
    Ok((svg, what))
}

/// The overlay of a physics command's trace `t`, the command written `command`.
pub(super) fn traced(command: String, t: e3d::world::Trace) -> Overlay {
    Overlay {
        command,
        points: t.points,
        poses: Some(t.poses),
        effect: t.outcome.effect,
        reward: t.outcome.reward,
    }
}

/// An animation `svg` as written to `out`: an HTML page holding it when
/// `out` ends in `.html` or `.htm`, titled with the scene and `cmd`.
pub(super) fn animation_page(
    scene: &Scene,
    cmd: &str,
    svg: String,
    out: &std::path::Path,
) -> String {
    let html = out
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("html") || e.eq_ignore_ascii_case("htm"));
    if html {
        let title = format!("{}: command {cmd}", scene.spec().name);
        e3d::report::motion_svg::html_page(&title, &svg)
    } else {
        svg
    }
}

/// The command `text` of `scene`, if given, parsed.
fn parse(scene: &Scene, text: Option<&str>) -> Result<Option<Command>, CliError> {
    let space = scene.command_space();
    text.map(|t| space.parse(t))
        .transpose()
        .map_err(CliError::input)
}

/// The overlay of `c` on `scene`: its path and outcome.
fn overlay_of(scene: &Scene, c: &Command) -> Result<Overlay, CliError> {
    let text = scene.command_space().format(c);
    match (
        &scene.spec().world,
        GridWorld::from_scene(scene),
        scene.physics_world(),
    ) {
        (WorldSpec::Grid(g), Some(mut w), _) => {
            let o = w.execute(c).map_err(world_error)?;
            Ok(Overlay {
                command: text,
                points: grid_path(&w, g, c),
                poses: None,
                effect: o.effect,
                reward: o.reward,
            })
        }
        (_, _, Some(mut w)) => Ok(traced(text, w.trace(c).map_err(world_error)?)),
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
