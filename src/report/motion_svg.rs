//! Motions you can watch: one command's rollout as a self-contained
//! animated SVG (SMIL `<animateTransform>`, no script), or an HTML page
//! holding it.
//!
//! The picture is [`scene_svg`](super::scene_svg)'s, with the bodies at
//! their start pose faint, the tracked point's whole path, and over them
//! every moving body (with the joints it carries), the tracked point and a
//! time readout, animated along the frames of
//! [`PhysicsWorld::motion`](crate::world::PhysicsWorld::motion), thinned
//! to at most [`MAX_FRAMES`] frames. The animation loops.
//!
//! A grid scene has no bodies: [`grid_motion_svg`] animates the agent's
//! cell path instead, one keyframe per cell (the start, then the cell after
//! each slot), over the still picture of the grid with its walls and the
//! whole path.

use super::scene_svg::{
    body_svg, colours, grid_picture, physics_picture, posed, Overlay, Paint, View,
};
use super::scene_svg::{END_FILL, END_STROKE, TRACKED};
use super::svg::esc;
use crate::scene::physics::{to_world, BodyKind, PhysicsSpec, GROUND};
use crate::scene::{Scene, WorldSpec};
use crate::world::{GridWorld, Motion};
use crate::{Command, World};
use std::fmt::Write;

/// The most frames an animation keeps (every k-th step, the last always).
pub const MAX_FRAMES: usize = 150;

/// The indices of the frames kept: every `k`-th of `n`, so that at most
/// `max` remain, the first and the last always.
///
/// ```
/// use e3d::report::motion_svg::thin;
/// assert_eq!(thin(10, 4), vec![0, 3, 6, 9]);
/// assert_eq!(thin(3, 150), vec![0, 1, 2]);
/// ```
pub fn thin(n: usize, max: usize) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
    let max = max.max(2);
    let k = (n - 1).div_ceil(max - 1).max(1);
    let mut idx: Vec<usize> = (0..n).step_by(k).collect();
    if idx.last() != Some(&(n - 1)) {
        idx.push(n - 1);
    }
    idx
}

/// Why a motion cannot be animated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum AnimateError {
    /// The scene is a grid: it has no bodies that move (animate its cell
    /// path with [`grid_motion_svg`]).
    #[error("scene `{0}` is a grid: it has no physics motion to animate (its cell path is animated by grid_motion_svg)")]
    Grid(String),
    /// The motion has no frame, or not the scene's bodies.
    #[error("the motion does not match scene `{0}` (its bodies or its frames)")]
    Mismatch(String),
    /// [`grid_motion_svg`] was given a physics scene (animate its motion
    /// with [`motion_svg`]).
    #[error(
        "scene `{0}` is a physics scene: its motion is animated by motion_svg, not as a cell path"
    )]
    NotGrid(String),
    /// The command is not one of the scene's (its message says why).
    #[error("{0}")]
    Command(String),
}

/// How long each keyframe of a grid animation shows, in seconds.
pub const GRID_KEYFRAME_SECONDS: f64 = 0.6;

/// The animated SVG of `command` on a grid scene: the still picture of the
/// grid ([`scene_svg`](super::scene_svg::scene_svg) with the command's
/// path: walls, start, reward cells, terminal cell) and over it the agent
/// moving from cell to cell, one keyframe per cell visited (the start, then
/// the cell after each slot: slots + 1 keyframes, each shown
/// [`GRID_KEYFRAME_SECONDS`]), with a readout of the slot, its symbol and
/// the cell. The animation loops.
///
/// ```
/// use e3d::report::motion_svg::grid_motion_svg;
/// use e3d::Scene;
/// let scene = Scene::builtin("two_rooms").unwrap();
/// let c = scene.command_space().parse("EEESSEE").unwrap();
/// let svg = grid_motion_svg(&scene, &c).unwrap();
/// assert!(svg.contains(r#"class="agent""#) && svg.contains("slot 7/7: E"));
/// ```
pub fn grid_motion_svg(scene: &Scene, command: &Command) -> Result<String, AnimateError> {
    let WorldSpec::Grid(g) = &scene.spec().world else {
        return Err(AnimateError::NotGrid(scene.spec().name.clone()));
    };
    let mut world = GridWorld::of(scene, g);
    let outcome = world
        .execute(command)
        .map_err(|e| AnimateError::Command(e.to_string()))?;
    let text = scene.command_space().format(command);
    let cells = world.path(command);
    let grid = world.grid().clone();
    let centres: Vec<[f64; 2]> = cells
        .iter()
        .map(|&cell| grid.center(cell / g.cols, cell % g.cols))
        .collect();
    let overlay = Overlay {
        command: text.clone(),
        points: centres.clone(),
        poses: None,
        effect: outcome.effect,
        reward: outcome.reward,
    };
    // one keyframe per cell, each shown GRID_KEYFRAME_SECONDS
    let n = cells.len();
    let tl = Timeline {
        key_times: (0..n).map(|k| k as f64 / n as f64).collect(),
        dur: GRID_KEYFRAME_SECONDS * n as f64,
        calc: r#" calcMode="discrete""#,
    };
    let symbols: Vec<char> = text.chars().collect();
    // the readout: the start cell, then each slot, its symbol and the cell
    // it led to
    let labels: Vec<(String, f64, f64)> = cells
        .iter()
        .enumerate()
        .map(|(k, &cell)| {
            let (r, c) = (cell / g.cols, cell % g.cols);
            let label = if k == 0 {
                format!("start: cell ({r}, {c})")
            } else {
                let symbol = symbols.get(k - 1).map_or(String::new(), |s| s.to_string());
                format!("slot {k}/{}: {} → cell ({r}, {c})", n - 1, esc(&symbol))
            };
            (label, k as f64 / n as f64, (k + 1) as f64 / n as f64)
        })
        .collect();
    let mut draw = |out: &mut String, v: &View| {
        let _ = writeln!(out, r#"<g class="motion">"#);
        let radius = format!("{:.2}", v.len(0.12).clamp(4.0, 14.0));
        let at: Vec<(f64, f64)> = centres.iter().map(|p| (p[0], p[1])).collect();
        moving_dot(out, v, &tl, ["agent", &radius, "1.5", "agent"], &at);
        let corner = (v.x(grid.max[0]) - 4.0, v.y(grid.max[1]) - 8.0);
        readout(out, ["step", "keyframe"], corner, &labels, tl.dur);
        out.push_str("</g>\n");
    };
    Ok(grid_picture(scene, g, Some(&overlay), Some(&mut draw)))
}

/// The readout at `at` (pixels; `classes`: of its group and of each
/// text): one text per keyframe, `(label, on, off)` shown from `on` to
/// `off` (fractions of the loop of `dur` seconds), the first from the start,
/// the last to the end.
fn readout(
    out: &mut String,
    [group, class]: [&str; 2],
    at: (f64, f64),
    labels: &[(String, f64, f64)],
    dur: f64,
) {
    let _ = writeln!(
        out,
        r##"<g class="{group}" font-size="14" fill="#222" font-family="monospace">"##
    );
    let n = labels.len();
    for (k, (label, on, off)) in labels.iter().enumerate() {
        let (values, times, opacity) = match k {
            0 => ("1;0", format!("0;{off:.4}"), 1),
            _ if k + 1 == n => ("0;1", format!("0;{on:.4}"), 0),
            _ => ("0;1;0", format!("0;{on:.4};{off:.4}"), 0),
        };
        let (x, y) = at;
        let _ = writeln!(
            out,
            r#"<text class="{class}" x="{x:.1}" y="{y:.1}" text-anchor="end" opacity="{opacity}">{label}<animate attributeName="opacity" calcMode="discrete" values="{values}" keyTimes="{times}" dur="{dur:.3}s" repeatCount="indefinite"/></text>"#
        );
    }
    out.push_str("</g>\n");
}

/// A dot moving through `at` (world coordinates, one per keyframe of
/// `tl`); `[class, radius, stroke width, title]`.
fn moving_dot(out: &mut String, v: &View, tl: &Timeline, look: [&str; 4], at: &[(f64, f64)]) {
    let [class, r, stroke, title] = look;
    let xs: Vec<String> = at.iter().map(|p| format!("{:.2}", v.x(p.0))).collect();
    let ys: Vec<String> = at.iter().map(|p| format!("{:.2}", v.y(p.1))).collect();
    let (x, y) = (&xs[0], &ys[0]);
    let ax = tl.anim("cx", None, xs.join(";"));
    let ay = tl.anim("cy", None, ys.join(";"));
    let _ = writeln!(
        out,
        r##"<circle class="{class}" cx="{x}" cy="{y}" r="{r}" fill="{TRACKED}" stroke="#ffffff" stroke-width="{stroke}"><title>{title}</title>{ax}{ay}</circle>"##
    );
}

/// The animated SVG of `motion`, the rollout of `command` on `scene`.
///
/// ```
/// use e3d::report::motion_svg::motion_svg;
/// use e3d::Scene;
/// let scene = Scene::builtin("arm7").unwrap();
/// let mut w = scene.physics_world().unwrap();
/// let c = scene.command_space().parse("+0-+0-+").unwrap();
/// let m = w.motion(&c).unwrap();
/// let svg = motion_svg(&scene, "+0-+0-+", &m).unwrap();
/// assert!(svg.contains("<animateTransform") && svg.contains("t = "));
/// ```
pub fn motion_svg(scene: &Scene, command: &str, motion: &Motion) -> Result<String, AnimateError> {
    draw_motion(scene, physics(scene)?, command, motion)
}

/// [`motion_svg`] of a motion that starts elsewhere than the poses the
/// scene lists (a start context's start): the faint start pose drawn
/// under the animation is the motion's first frame.
pub fn motion_svg_from(
    scene: &Scene,
    command: &str,
    motion: &Motion,
) -> Result<String, AnimateError> {
    let first = motion.frames.first().map_or(&[][..], |f| &f.poses[..]);
    let posed = posed(physics(scene)?.clone(), first);
    draw_motion(scene, &posed, command, motion)
}

/// The physics of `scene`; a grid has no motion to animate.
fn physics(scene: &Scene) -> Result<&PhysicsSpec, AnimateError> {
    match &scene.spec().world {
        WorldSpec::Physics(p) => Ok(p),
        WorldSpec::Grid(_) => Err(AnimateError::Grid(scene.spec().name.clone())),
    }
}

/// The animated picture of `motion` over `p` (the scene's physics, its
/// bodies at the faint start pose drawn).
fn draw_motion(
    scene: &Scene,
    p: &PhysicsSpec,
    command: &str,
    motion: &Motion,
) -> Result<String, AnimateError> {
    let (tracked, drawn_point) = tracked_of(scene, p, motion)?;
    let point_at = |f: usize| {
        let pose = &motion.frames[f].poses[tracked];
        let at = (pose.position[0], pose.position[1]);
        to_world(at, pose.angle, drawn_point)
    };
    let overlay = Overlay {
        command: command.to_string(),
        points: (0..motion.frames.len())
            .map(|f| {
                let q = point_at(f);
                [q.0, q.1]
            })
            .collect(),
        poses: None,
        effect: motion.outcome.effect,
        reward: motion.outcome.reward,
    };
    let keep = thin(motion.frames.len(), MAX_FRAMES);
    let end = motion.frames.last().map_or(0.0, |f| f.time);
    // a motion shorter than a second plays over a second
    let dur = end.max(1.0);
    let at = |f: usize| (motion.frames[f].time / dur).min(1.0);
    let tl = Timeline {
        key_times: keep.iter().map(|&f| at(f)).collect(),
        dur,
        calc: "",
    };
    // the time readout: one text per kept frame, shown in its turn
    let labels: Vec<(String, f64, f64)> = keep
        .iter()
        .enumerate()
        .map(|(k, &f)| {
            let t = motion.frames[f].time;
            let off = keep.get(k + 1).map_or(1.0, |&g| at(g));
            (format!("t = {t:.3} s / {end:.3} s"), at(f), off)
        })
        .collect();
    let mut draw = |out: &mut String, v: &View| {
        let _ = writeln!(out, r#"<g class="motion">"#);
        moving_bodies_svg(out, v, p, motion, &keep, &tl);
        // ground hinges do not move: drawn once, over the bodies
        for j in p.joints.iter().filter(|j| j.parent == GROUND) {
            let (c, name) = (v.centre(j.parent_anchor), esc(&j.name));
            let _ = writeln!(
                out,
                r##"<circle {c} r="4" fill="#2e323b"><title>{name}</title></circle>"##
            );
        }
        let path: Vec<(f64, f64)> = keep.iter().map(|&f| point_at(f)).collect();
        moving_dot(out, v, &tl, ["tracked", "4.5", "1", "tracked point"], &path);
        let corner = (v.x(v.max[0]) - 4.0, v.y(v.max[1]) + 16.0);
        readout(out, ["time", "frame"], corner, &labels, dur);
        out.push_str("</g>\n");
    };
    Ok(physics_picture(scene, p, Some(&overlay), Some(&mut draw)))
}

/// The index of the body whose point is drawn, and that point in the
/// body's frame; refused when `motion` is not a motion of `p`'s bodies.
fn tracked_of(
    scene: &Scene,
    p: &PhysicsSpec,
    motion: &Motion,
) -> Result<(usize, (f64, f64)), AnimateError> {
    if motion.frames.is_empty()
        || motion.bodies.len() != p.bodies.len()
        || motion
            .frames
            .iter()
            .any(|f| f.poses.len() != p.bodies.len())
    {
        return Err(AnimateError::Mismatch(scene.spec().name.clone()));
    }
    let (drawn, drawn_point) = p
        .effect
        .drawn_point(|j| p.child_of(j))
        .ok_or_else(|| AnimateError::Mismatch(scene.spec().name.clone()))?;
    let tracked = p
        .bodies
        .iter()
        .position(|b| b.name == drawn)
        .ok_or_else(|| AnimateError::Mismatch(scene.spec().name.clone()))?;
    Ok((tracked, drawn_point))
}

/// Every moving body, with the joints it carries as a parent, at its start
/// pose and animated by the rigid motion from it.
fn moving_bodies_svg(
    out: &mut String,
    v: &View,
    p: &PhysicsSpec,
    motion: &Motion,
    keep: &[usize],
    tl: &Timeline,
) {
    for (i, b) in p.bodies.iter().enumerate() {
        if b.kind == BodyKind::Fixed {
            continue;
        }
        let start = &motion.frames[0].poses[i];
        let (at, angle) = ((start.position[0], start.position[1]), start.angle);
        let c0 = (v.x(at.0), v.y(at.1));
        // the rigid motion from the start pose: rotate about the start
        // position, then translate to the current one
        let (mut moves, mut turns) = (Vec::new(), Vec::new());
        for q in keep.iter().map(|&f| &motion.frames[f].poses[i]) {
            let (dx, dy) = (v.x(q.position[0]) - c0.0, v.y(q.position[1]) - c0.1);
            moves.push(format!("{dx:.2},{dy:.2}"));
            let turn = -(q.angle - start.angle).to_degrees();
            turns.push(format!("{turn:.2} {:.2} {:.2}", c0.0, c0.1));
        }
        let (fill, stroke) = if b.kind == BodyKind::Kinematic {
            colours(b.kind)
        } else {
            (END_FILL, END_STROKE)
        };
        let name = esc(&b.name);
        let translate = tl.anim("transform", Some("translate"), moves.join(";"));
        let rotate = tl.anim("transform", Some("rotate"), turns.join(";"));
        let _ = writeln!(
            out,
            r#"<g class="body" data-body="{name}"><title>{name}</title>
{translate}
{rotate}"#
        );
        body_svg(out, v, &b.shape, at, angle, Paint(fill, stroke, 0.9));
        // the joints this body carries as a parent ride with it
        for j in p.joints.iter().filter(|j| j.parent == b.name) {
            let c = v.centre(to_world(at, angle, j.parent_anchor));
            let name = esc(&j.name);
            let _ = writeln!(
                out,
                r##"<circle {c} r="3.5" fill="#ffffff" stroke="#2e323b" stroke-width="1.3"><title>{name}</title></circle>"##
            );
        }
        out.push_str("</g>\n");
    }
}

/// The timing every animation of a picture shares: the keyframes' times
/// as fractions of `dur` seconds, looping; `calc`, the calcMode of a
/// plain `<animate>` (empty: linear).
struct Timeline {
    key_times: Vec<f64>,
    dur: f64,
    calc: &'static str,
}

impl Timeline {
    /// An `<animateTransform>` of `kind` (or, without one, an `<animate>`)
    /// of `attr` through `values`, one per keyframe.
    fn anim(&self, attr: &str, kind: Option<&str>, values: String) -> String {
        let times: Vec<String> = self.key_times.iter().map(|t| format!("{t:.4}")).collect();
        let (key_times, dur, calc) = (times.join(";"), self.dur, self.calc);
        match kind {
            Some(t) => format!(
                r#"<animateTransform attributeName="{attr}" type="{t}" values="{values}" keyTimes="{key_times}" dur="{dur:.3}s" repeatCount="indefinite" additive="sum"/>"#
            ),
            None => format!(
                r#"<animate attributeName="{attr}"{calc} values="{values}" keyTimes="{key_times}" dur="{dur:.3}s" repeatCount="indefinite"/>"#
            ),
        }
    }
}

/// `svg` in a self-contained HTML page (no script, no network).
pub fn html_page(title: &str, svg: &str) -> String {
    let style = "svg{max-width:100%;height:auto;background:#fff}";
    super::svg::page(title, style, svg)
}
