//! Pictures of scenes: hand-written SVG of a scene's bodies, joints, effect
//! grid and reward cells, optionally with the path of the tracked point
//! under one command and its terminal cell.

use super::svg::{esc, tick_step, ticks};
use crate::scene::physics::{to_world, BodyKind, BodySpec, PhysicsSpec, ShapeSpec, GROUND};
use crate::scene::{Scene, Symmetry, WorldSpec};
use crate::world::{BodyPose, GridSpec};
use std::fmt::Write;

mod grid;
mod physics;
pub use physics::describe_effect;

pub(super) use grid::grid_picture;
pub(super) use physics::{body_svg, colours, physics_picture, Paint, END_FILL, END_STROKE};

/// Draws the moving parts of an animation over the picture (see
/// [`physics_picture`]).
pub(super) type Layer<'a> = &'a mut dyn FnMut(&mut String, &View);

/// A command's run, drawn over the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Overlay {
    /// The command, as symbols (for the caption).
    pub command: String,
    /// The tracked point from start to end (metres; on a grid, cell centres).
    pub points: Vec<[f64; 2]>,
    /// The terminal pose of every body, in the scene's order (physics only).
    pub poses: Option<Vec<BodyPose>>,
    /// The terminal effect.
    pub effect: usize,
    /// The terminal reward.
    pub reward: f64,
}

/// The largest side of the drawing, in pixels.
const SIDE: f64 = 760.0;
/// Left of the drawing: the y axis, its ticks and its label.
const LEFT: f64 = 66.0;
const RIGHT: f64 = 24.0;
/// Above the drawing: the title and the subtitle.
const TOP: f64 = 70.0;
/// The height of a line of a note under the header, px.
const NOTE_LINE: f64 = 14.0;
/// Below the drawing: the x axis, its ticks and its label.
const AXIS: f64 = 48.0;
/// One row of the legend.
const ROW: f64 = 20.0;
/// The x of the title, the subtitle and the legend.
const MARGIN: f64 = 30.0;

/// Maps world coordinates to SVG pixels (y up in the world, down in SVG).
pub(super) struct View {
    min: [f64; 2],
    /// The top right corner of the drawing, in world coordinates.
    pub(super) max: [f64; 2],
    scale: f64,
    /// Rows of the legend under the x axis.
    legend_rows: usize,
    /// Lines of a note under the header, past the first (they push the
    /// drawing down).
    note_lines: usize,
}

impl View {
    fn new(min: [f64; 2], max: [f64; 2]) -> View {
        let w = (max[0] - min[0]).max(1e-9);
        let h = (max[1] - min[1]).max(1e-9);
        View {
            min,
            max,
            scale: SIDE / w.max(h),
            legend_rows: 1,
            note_lines: 0,
        }
    }
    pub(super) fn x(&self, x: f64) -> f64 {
        LEFT + (x - self.min[0]) * self.scale
    }
    pub(super) fn y(&self, y: f64) -> f64 {
        TOP + NOTE_LINE * self.note_lines as f64 + (self.max[1] - y) * self.scale
    }
    pub(super) fn len(&self, l: f64) -> f64 {
        l * self.scale
    }
    fn width(&self) -> f64 {
        LEFT + RIGHT + (self.max[0] - self.min[0]) * self.scale
    }
    /// The bottom of the drawing (the x axis).
    fn bottom(&self) -> f64 {
        self.y(self.min[1])
    }
    fn height(&self) -> f64 {
        self.bottom() + AXIS + ROW * self.legend_rows as f64 + 6.0
    }
    pub(super) fn pt(&self, p: (f64, f64)) -> String {
        format!("{:.2},{:.2}", self.x(p.0), self.y(p.1))
    }
    /// `x=".." y=".." width=".." height=".."` of the rectangle of top left
    /// corner `(x, y)` and size `w x h` (world units).
    pub(super) fn rect(&self, (x, y): (f64, f64), w: f64, h: f64) -> String {
        let (x, y, w, h) = (self.x(x), self.y(y), self.len(w), self.len(h));
        format!(r#"x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}""#)
    }
    /// `cx=".." cy=".."` of the point `p`.
    pub(super) fn centre(&self, p: (f64, f64)) -> String {
        format!(r#"cx="{:.2}" cy="{:.2}""#, self.x(p.0), self.y(p.1))
    }
    /// `x1=".." y1=".." x2=".." y2=".."` of the segment from `a` to `b`.
    pub(super) fn segment(&self, a: (f64, f64), b: (f64, f64)) -> String {
        let (x1, y1, x2, y2) = (self.x(a.0), self.y(a.1), self.x(b.0), self.y(b.1));
        format!(r#"x1="{x1:.2}" y1="{y1:.2}" x2="{x2:.2}" y2="{y2:.2}""#)
    }
}

/// Draws `scene` as SVG, with `overlay` (a command's path) if given.
///
/// ```
/// use e3d::report::scene_svg::scene_svg;
/// use e3d::Scene;
/// let svg = scene_svg(&Scene::builtin("arm7").unwrap(), None);
/// assert!(svg.starts_with("<svg") && svg.contains("link7"));
/// ```
pub fn scene_svg(scene: &Scene, overlay: Option<&Overlay>) -> String {
    match &scene.spec().world {
        WorldSpec::Grid(g) => grid_picture(scene, g, overlay, None),
        WorldSpec::Physics(p) => physics_picture(scene, p, overlay, None),
    }
}

/// Draws a physics scene as SVG with its bodies at `start` (one pose per
/// body, in the scene's order: a start context's start, as
/// [`PhysicsState::poses`](crate::world::PhysicsState) gives it) instead
/// of the poses the scene lists, and `overlay` (a command's path from that
/// start) if given; a grid scene is drawn as [`scene_svg`] draws it.
///
/// ```
/// use e3d::report::scene_svg::{posed_svg, scene_svg};
/// use e3d::world::BodyPose;
/// use e3d::Scene;
/// let scene = Scene::load("scenes/puck_contexts.ron").unwrap();
/// let moved = [BodyPose { position: [5.5, 0.5], angle: 0.0 }];
/// assert_ne!(posed_svg(&scene, &moved, None), scene_svg(&scene, None));
/// ```
pub fn posed_svg(scene: &Scene, start: &[BodyPose], overlay: Option<&Overlay>) -> String {
    match &scene.spec().world {
        WorldSpec::Grid(g) => grid_picture(scene, g, overlay, None),
        WorldSpec::Physics(p) => {
            physics_picture(scene, &posed(p.without_contexts(), start), overlay, None)
        }
    }
}

/// `p` with its bodies at `start` (one pose per body, in order).
pub(super) fn posed(mut p: PhysicsSpec, start: &[BodyPose]) -> PhysicsSpec {
    for (b, pose) in p.bodies.iter_mut().zip(start) {
        b.position = (pose.position[0], pose.position[1]);
        b.angle = pose.angle;
    }
    p
}

fn header(out: &mut String, v: &View, scene: &Scene, overlay: Option<&Overlay>) {
    let (w, h) = (v.width(), v.height());
    let sub = match overlay {
        Some(o) => {
            let [x, y] = o.points.last().copied().unwrap_or_default();
            let (command, effect, reward) = (&o.command, o.effect, o.reward);
            format!(
                "command {command}  →  effect {effect}  (point {x:.3}, {y:.3})  reward {reward}"
            )
        }
        None => scene.spec().description.clone(),
    };
    let (name, sub) = (esc(&scene.spec().name), esc(&sub));
    let _ = writeln!(
        out,
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="Helvetica, Arial, sans-serif">
<rect width="100%" height="100%" fill="#ffffff"/>
<text x="{MARGIN}" y="24" font-size="18" font-weight="bold" fill="#222">{name}</text>
<text x="{MARGIN}" y="42" font-size="13" fill="#555">{sub}</text>"##
    );
}

/// The effect grid: light cell lines, reward cells, the terminal cell.
fn effect_layer(out: &mut String, v: &View, scene: &Scene, overlay: Option<&Overlay>) {
    let g = scene.effect_grid();
    let [cw, ch] = g.cell_size();
    let rewards = scene.reward_table();
    // a cell's rectangle, then its look
    let cell = |out: &mut String, e: usize, look: &str| {
        let (r, c) = ((e / g.cols) as f64, (e % g.cols) as f64);
        let at = v.rect((g.min[0] + c * cw, g.max[1] - r * ch), cw, ch);
        let _ = writeln!(out, "<rect {at} {look}/>");
    };
    for e in (0..g.num_cells()).filter(|&e| rewards[e] != 0.0) {
        let look = format!(r#"fill="{REWARD}" fill-opacity="{REWARD_OPACITY}""#);
        cell(out, e, &look);
    }
    if let Some(o) = overlay {
        let look =
            format!(r#"fill="none" stroke="{PATH}" stroke-width="3" stroke-dasharray="7,3""#);
        cell(out, o.effect, &look);
    }
    let mut d = String::new();
    for c in 0..=g.cols {
        let (x, top, bottom) = (v.x(g.min[0] + c as f64 * cw), v.y(g.max[1]), v.y(g.min[1]));
        let _ = write!(d, "M{x:.2},{top:.2}V{bottom:.2}");
    }
    for r in 0..=g.rows {
        let (left, y, right) = (v.x(g.min[0]), v.y(g.max[1] - r as f64 * ch), v.x(g.max[0]));
        let _ = write!(d, "M{left:.2},{y:.2}H{right:.2}");
    }
    let _ = writeln!(
        out,
        r##"<path d="{d}" stroke="#b8c4d6" stroke-width="0.8" fill="none"/>"##
    );
    for region in &scene.spec().reward.regions {
        let (min, max) = (region.min, region.max);
        let at = v.rect((min.0, max.1), max.0 - min.0, max.1 - min.1);
        let (x, y, name) = (v.x(min.0) + 3.0, v.y(max.1) + 12.0, esc(&region.name));
        let _ = writeln!(
            out,
            r##"<rect {at} fill="none" stroke="#2e8b57" stroke-width="1.5" stroke-dasharray="5,3"/><text x="{x:.2}" y="{y:.2}" font-size="11" fill="#2e8b57">{name}</text>"##
        );
    }
}

/// The colour of a command's path, its ends and its terminal cell.
const PATH: &str = "#e07000";
/// The fill of a reward cell, and its opacity (the legend's swatch is the same).
const REWARD: &str = "#7fd17f";
const REWARD_OPACITY: f64 = 0.55;
/// The tracked point.
pub(super) const TRACKED: &str = "#d62728";
/// The mirror line of a symmetry.
const MIRROR: &str = "#7b68ee";
const MIRROR_DASH: &str = "8,4,2,4";

fn path_layer(out: &mut String, v: &View, overlay: Option<&Overlay>) {
    let Some(o) = overlay else { return };
    if o.points.is_empty() {
        return;
    }
    let pts: Vec<String> = o.points.iter().map(|p| v.pt((p[0], p[1]))).collect();
    let _ = writeln!(
        out,
        r##"<polyline points="{}" fill="none" stroke="{PATH}" stroke-width="2.2" stroke-linejoin="round" stroke-linecap="round"/>"##,
        pts.join(" ")
    );
    let s = o.points[0];
    let e = o.points[o.points.len() - 1];
    // the start: a ring around the tracked point, which stays visible in it
    let (s, e) = (v.centre((s[0], s[1])), v.centre((e[0], e[1])));
    let _ = writeln!(
        out,
        r##"<circle {s} r="7" fill="none" stroke="{PATH}" stroke-width="2"><title>start of the path</title></circle>
<circle {e} r="5" fill="{PATH}"><title>end of the path</title></circle>"##
    );
}

/// A tick's label with the decimals its step needs (never `-0`).
fn tick_label(t: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let t = if t.abs() < step * 1e-6 { 0.0 } else { t };
    format!("{t:.decimals$}")
}

/// The x axis under the drawing and the y axis left of it, with ticks in
/// world units (`unit`: "m", or "cells" on a grid).
fn axes(out: &mut String, v: &View, unit: &str) {
    let span = (v.max[0] - v.min[0]).max(v.max[1] - v.min[1]);
    let step = tick_step(span.max(1e-9));
    let ticks = |lo, hi| ticks(lo, hi, step).unwrap_or_default();
    let (x0, x1) = (v.x(v.min[0]), v.x(v.max[0]));
    let (y0, y1) = (v.bottom(), v.y(v.max[1]));
    let _ = writeln!(
        out,
        r##"<g class="axes" stroke="#333" stroke-width="1"><path d="M{x0:.2},{y0:.2}H{x1:.2}M{x0:.2},{y0:.2}V{y1:.2}" fill="none"/></g>"##
    );
    let mut d = String::new();
    let mut labels = String::new();
    for t in ticks(v.min[0], v.max[0]) {
        let x = v.x(t);
        let _ = write!(d, "M{x:.2},{y0:.2}v5");
        let (y, label) = (y0 + 18.0, tick_label(t, step));
        let _ = write!(
            labels,
            r##"<text x="{x:.2}" y="{y:.2}" text-anchor="middle">{label}</text>"##
        );
    }
    for t in ticks(v.min[1], v.max[1]) {
        let y = v.y(t);
        let _ = write!(d, "M{x0:.2},{y:.2}h-5");
        let (x, y, label) = (x0 - 8.0, y + 4.0, tick_label(t, step));
        let _ = write!(
            labels,
            r##"<text x="{x:.2}" y="{y:.2}" text-anchor="end">{label}</text>"##
        );
    }
    let _ = writeln!(
        out,
        r##"<path class="ticks" d="{d}" stroke="#333" stroke-width="1"/><g class="tick-labels" font-size="12" fill="#333">{labels}</g>"##
    );
    let (ax, ay) = (LEFT - 48.0, (y0 + y1) / 2.0);
    let _ = writeln!(
        out,
        r##"<text x="{:.2}" y="{:.2}" font-size="13" fill="#333" text-anchor="middle">x ({unit})</text><text x="{ax:.2}" y="{ay:.2}" font-size="13" fill="#333" text-anchor="middle" transform="rotate(-90 {ax:.2} {ay:.2})">y ({unit})</text>"##,
        (x0 + x1) / 2.0,
        y0 + 36.0,
    );
}

/// How a legend entry shows what it names: as it is drawn in the picture.
enum Swatch {
    /// A filled square: fill, stroke, opacity.
    Fill(&'static str, &'static str, f64),
    /// An outlined square (the terminal cell), dashed.
    Outline(&'static str),
    /// A dashed outline (a reward region).
    Region,
    /// A line, dashed with the given pattern or solid.
    Line(&'static str, Option<&'static str>),
    /// A dot of the given colour.
    Dot(&'static str),
    /// A ring (the start of the path) around a dot (the tracked point).
    Ring(Option<&'static str>),
    /// A letter (the start cell of a grid).
    Letter(&'static str, char),
    /// A joint's hinge: on the ground (filled) or between two bodies.
    Hinge(bool),
}

/// One entry of the legend.
struct Key(Swatch, &'static str);

/// The width in pixels of an entry (11 px text, a 14 px swatch).
fn key_width(k: &Key) -> f64 {
    14.0 + 6.0 + 6.3 * k.1.chars().count() as f64 + 18.0
}

/// How many rows `keys` take across the picture.
fn legend_rows(keys: &[Key], width: f64) -> usize {
    let mut rows = 1;
    let mut x = 0.0;
    for k in keys {
        let w = key_width(k);
        if x > 0.0 && x + w > width - 2.0 * MARGIN {
            rows += 1;
            x = 0.0;
        }
        x += w;
    }
    rows
}

/// The legend under the x axis, left to right, in as many rows as needed.
fn legend(out: &mut String, v: &View, keys: &[Key]) {
    let _ = writeln!(out, r##"<g class="legend" font-size="11" fill="#333">"##);
    let mut x = MARGIN;
    let mut y = v.bottom() + AXIS + 12.0;
    for k in keys {
        let w = key_width(k);
        if x > MARGIN && x + w > v.width() - MARGIN {
            x = MARGIN;
            y += ROW;
        }
        let (cx, cy) = (x + 7.0, y - 4.0);
        // the corner of a filled square, and of an outlined one
        let (fill_y, (out_x, out_y)) = (y - 9.5, (x + 1.0, y - 9.0));
        let swatch = match &k.0 {
            Swatch::Fill(fill, stroke, op) => format!(
                r#"<rect x="{x:.1}" y="{fill_y:.1}" width="14" height="11" fill="{fill}" fill-opacity="{op}" stroke="{stroke}" stroke-opacity="{op}" stroke-width="1"/>"#
            ),
            Swatch::Outline(colour) => format!(
                r#"<rect x="{out_x:.1}" y="{out_y:.1}" width="12" height="10" fill="none" stroke="{colour}" stroke-width="2.5" stroke-dasharray="4,2"/>"#
            ),
            Swatch::Region => format!(
                r##"<rect x="{out_x:.1}" y="{out_y:.1}" width="12" height="10" fill="none" stroke="#2e8b57" stroke-width="1.5" stroke-dasharray="3,2"/>"##
            ),
            Swatch::Line(colour, dash) => format!(
                r#"<path d="M{x:.1},{cy:.1}h14" stroke="{colour}" stroke-width="2"{}/>"#,
                dash.map_or(String::new(), |d| format!(r#" stroke-dasharray="{d}""#))
            ),
            Swatch::Dot(colour) => {
                format!(r#"<circle cx="{cx:.1}" cy="{cy:.1}" r="3.5" fill="{colour}"/>"#)
            }
            Swatch::Ring(inner) => format!(
                r#"<circle cx="{cx:.1}" cy="{cy:.1}" r="6" fill="none" stroke="{PATH}" stroke-width="2"/>{}"#,
                inner.map_or(String::new(), |c| format!(
                    r#"<circle cx="{cx:.1}" cy="{cy:.1}" r="3" fill="{c}"/>"#
                ))
            ),
            Swatch::Hinge(ground) => format!(
                r##"<circle cx="{cx:.1}" cy="{cy:.1}" r="4" fill="{}" stroke="#2e323b" stroke-width="1.5"/>"##,
                if *ground { "#2e323b" } else { "#ffffff" }
            ),
            Swatch::Letter(colour, c) => format!(
                r#"<text x="{cx:.1}" y="{:.1}" font-size="13" font-weight="bold" text-anchor="middle" fill="{colour}">{c}</text>"#,
                y + 0.5
            ),
        };
        let (text_x, name) = (x + 20.0, esc(k.1));
        let _ = writeln!(
            out,
            r#"<g class="key">{swatch}<text x="{text_x:.1}" y="{y:.1}">{name}</text></g>"#
        );
        x += w;
    }
    out.push_str("</g>\n");
}

/// The legend entries of what the picture of `scene` shows.
fn reward_keys(scene: &Scene) -> Vec<Key> {
    let mut keys = Vec::new();
    if scene.reward_table().iter().any(|&r| r != 0.0) {
        keys.push(Key(
            Swatch::Fill(REWARD, "none", REWARD_OPACITY),
            "reward cell",
        ));
    }
    if !scene.spec().reward.regions.is_empty() {
        keys.push(Key(Swatch::Region, "reward region"));
    }
    keys
}

fn path_keys(keys: &mut Vec<Key>, tracked: Option<&'static str>) {
    keys.push(Key(Swatch::Line(PATH, None), "path"));
    keys.push(Key(Swatch::Ring(tracked), "start of the path"));
    keys.push(Key(Swatch::Dot(PATH), "end of the path"));
    keys.push(Key(Swatch::Outline(PATH), "terminal cell"));
}
