//! Pictures of scenes: hand-written SVG of a scene's bodies, joints, effect
//! grid and reward cells, optionally with the path of the tracked point
//! under one command and its terminal cell.

use crate::scene::physics::{to_world, BodyKind, PhysicsSpec, ShapeSpec, GROUND};
use crate::scene::{Scene, Symmetry, WorldSpec};
use crate::world::{BodyPose, GridSpec};
use std::fmt::Write;

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
/// Below the drawing: the x axis, its ticks and its label.
const AXIS: f64 = 48.0;
/// One row of the legend.
const ROW: f64 = 20.0;
/// The x of the title, the subtitle and the legend.
const MARGIN: f64 = 30.0;

/// Maps world coordinates to SVG pixels (y up in the world, down in SVG).
pub(super) struct View {
    min: [f64; 2],
    max: [f64; 2],
    scale: f64,
    /// Rows of the legend under the x axis.
    legend_rows: usize,
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
        }
    }
    pub(super) fn x(&self, x: f64) -> f64 {
        LEFT + (x - self.min[0]) * self.scale
    }
    pub(super) fn y(&self, y: f64) -> f64 {
        TOP + (self.max[1] - y) * self.scale
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
    /// The top right corner of the drawing, in world coordinates.
    pub(super) fn max_world(&self) -> [f64; 2] {
        self.max
    }
    pub(super) fn pt(&self, p: (f64, f64)) -> String {
        format!("{:.2},{:.2}", self.x(p.0), self.y(p.1))
    }
}

pub(super) fn esc(s: &str) -> String {
    crate::text::xml_escape(s).into_owned()
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
    match &scene.world {
        WorldSpec::Grid(g) => grid_svg(scene, g, overlay),
        WorldSpec::Physics(p) => physics_svg(scene, p, overlay),
    }
}

fn header(out: &mut String, v: &View, scene: &Scene, overlay: Option<&Overlay>) {
    let (w, h) = (v.width(), v.height());
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="Helvetica, Arial, sans-serif">"#
    );
    let _ = writeln!(
        out,
        r##"<rect width="100%" height="100%" fill="#ffffff"/>"##
    );
    let _ = writeln!(
        out,
        r##"<text x="{MARGIN}" y="24" font-size="18" font-weight="bold" fill="#222">{}</text>"##,
        esc(&scene.name)
    );
    let sub = match overlay {
        Some(o) => format!(
            "command {}  →  effect {}  (point {:.3}, {:.3})  reward {}",
            o.command,
            o.effect,
            o.points.last().map_or(0.0, |p| p[0]),
            o.points.last().map_or(0.0, |p| p[1]),
            o.reward
        ),
        None => scene.description.clone(),
    };
    let _ = writeln!(
        out,
        r##"<text x="{MARGIN}" y="42" font-size="13" fill="#555">{}</text>"##,
        esc(&sub)
    );
}

/// The effect grid: light cell lines, reward cells, the terminal cell.
fn effect_layer(out: &mut String, v: &View, scene: &Scene, overlay: Option<&Overlay>) {
    let g = scene.effect_grid();
    let [cw, ch] = g.cell_size();
    let rewards = scene.reward_table();
    let rewarded = (0..g.num_cells())
        .filter(|&e| rewards[e] != 0.0)
        .map(|e| (e / g.cols, e % g.cols));
    for (r, c) in rewarded {
        let x0 = g.min[0] + c as f64 * cw;
        let y1 = g.max[1] - r as f64 * ch;
        let _ = writeln!(
            out,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{REWARD}" fill-opacity="{REWARD_OPACITY}"/>"##,
            v.x(x0),
            v.y(y1),
            v.len(cw),
            v.len(ch)
        );
    }
    if let Some(o) = overlay {
        let (r, c) = (o.effect / g.cols, o.effect % g.cols);
        let x0 = g.min[0] + c as f64 * cw;
        let y1 = g.max[1] - r as f64 * ch;
        let _ = writeln!(
            out,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="{PATH}" stroke-width="3" stroke-dasharray="7,3"/>"##,
            v.x(x0),
            v.y(y1),
            v.len(cw),
            v.len(ch)
        );
    }
    let mut d = String::new();
    for c in 0..=g.cols {
        let x = g.min[0] + c as f64 * cw;
        let _ = write!(
            d,
            "M{:.2},{:.2}V{:.2}",
            v.x(x),
            v.y(g.max[1]),
            v.y(g.min[1])
        );
    }
    for r in 0..=g.rows {
        let y = g.max[1] - r as f64 * ch;
        let _ = write!(
            d,
            "M{:.2},{:.2}H{:.2}",
            v.x(g.min[0]),
            v.y(y),
            v.x(g.max[0])
        );
    }
    let _ = writeln!(
        out,
        r##"<path d="{d}" stroke="#b8c4d6" stroke-width="0.8" fill="none"/>"##
    );
    for region in &scene.reward.regions {
        let _ = writeln!(
            out,
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="#2e8b57" stroke-width="1.5" stroke-dasharray="5,3"/><text x="{:.2}" y="{:.2}" font-size="11" fill="#2e8b57">{}</text>"##,
            v.x(region.min.0),
            v.y(region.max.1),
            v.len(region.max.0 - region.min.0),
            v.len(region.max.1 - region.min.1),
            v.x(region.min.0) + 3.0,
            v.y(region.max.1) + 12.0,
            esc(&region.name)
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
    let _ = writeln!(
        out,
        r##"<circle cx="{:.2}" cy="{:.2}" r="7" fill="none" stroke="{PATH}" stroke-width="2"><title>start of the path</title></circle>"##,
        v.x(s[0]),
        v.y(s[1])
    );
    let _ = writeln!(
        out,
        r##"<circle cx="{:.2}" cy="{:.2}" r="5" fill="{PATH}"><title>end of the path</title></circle>"##,
        v.x(e[0]),
        v.y(e[1])
    );
}

/// A step of 1, 2 or 5 times a power of ten giving about 5 to 10 ticks
/// over `span`.
fn tick_step(span: f64) -> f64 {
    let raw = span.max(1e-9) / 8.0;
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|k| k * mag)
        .find(|&s| s >= raw)
        .unwrap_or(10.0 * mag)
}

/// The ticks of `[lo, hi]` at multiples of `step`.
fn ticks(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step - 1e-9).ceil() as i64;
    let last = (hi / step + 1e-9).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
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
    let step = tick_step(span);
    let (x0, x1) = (v.x(v.min[0]), v.x(v.max[0]));
    let (y0, y1) = (v.bottom(), v.y(v.max[1]));
    let _ = writeln!(
        out,
        r##"<g class="axes" stroke="#333" stroke-width="1"><path d="M{x0:.2},{y0:.2}H{x1:.2}M{x0:.2},{y0:.2}V{y1:.2}" fill="none"/></g>"##
    );
    let mut d = String::new();
    let mut labels = String::new();
    for t in ticks(v.min[0], v.max[0], step) {
        let x = v.x(t);
        let _ = write!(d, "M{x:.2},{y0:.2}v5");
        let _ = write!(
            labels,
            r##"<text x="{x:.2}" y="{:.2}" text-anchor="middle">{}</text>"##,
            y0 + 18.0,
            tick_label(t, step)
        );
    }
    for t in ticks(v.min[1], v.max[1], step) {
        let y = v.y(t);
        let _ = write!(d, "M{x0:.2},{y:.2}h-5");
        let _ = write!(
            labels,
            r##"<text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"##,
            x0 - 8.0,
            y + 4.0,
            tick_label(t, step)
        );
    }
    let _ = writeln!(
        out,
        r##"<path class="ticks" d="{d}" stroke="#333" stroke-width="1"/><g class="tick-labels" font-size="12" fill="#333">{labels}</g>"##
    );
    let _ = writeln!(
        out,
        r##"<text x="{:.2}" y="{:.2}" font-size="13" fill="#333" text-anchor="middle">x ({unit})</text><text x="{:.2}" y="{:.2}" font-size="13" fill="#333" text-anchor="middle" transform="rotate(-90 {:.2} {:.2})">y ({unit})</text>"##,
        (x0 + x1) / 2.0,
        y0 + 36.0,
        LEFT - 48.0,
        (y0 + y1) / 2.0,
        LEFT - 48.0,
        (y0 + y1) / 2.0,
    );
}

fn grid_svg(scene: &Scene, g: &GridSpec, overlay: Option<&Overlay>) -> String {
    grid_picture(scene, g, overlay, None)
}

/// The picture of a grid scene; with `animated`, what moves is drawn by
/// it after the path (the agent, see
/// [`grid_motion_svg`](super::motion_svg::grid_motion_svg)).
pub(super) fn grid_picture(
    scene: &Scene,
    g: &GridSpec,
    overlay: Option<&Overlay>,
    mut animated: Option<Layer>,
) -> String {
    let eg = g.effect_grid();
    let mut v = View::new(eg.min, eg.max);
    let mut keys = vec![Key(Swatch::Letter("#1f4e9c", 'S'), "start cell")];
    keys.extend(reward_keys(scene));
    keys.push(Key(Swatch::Line("#333", None), "wall"));
    if overlay.is_some() {
        path_keys(&mut keys, None);
    }
    if animated.is_some() {
        keys.push(Key(Swatch::Dot(TRACKED), "agent"));
    }
    v.legend_rows = legend_rows(&keys, v.width());
    let mut out = String::new();
    header(&mut out, &v, scene, overlay);
    effect_layer(&mut out, &v, scene, overlay);
    // the border and the walls
    let _ = writeln!(
        out,
        r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="#333" stroke-width="4"/>"##,
        v.x(eg.min[0]),
        v.y(eg.max[1]),
        v.len(eg.max[0] - eg.min[0]),
        v.len(eg.max[1] - eg.min[1])
    );
    let rows = g.rows as f64;
    for &((r1, c1), (r2, c2)) in &g.walls {
        let (x0, y0, x1, y1) = if r1 == r2 {
            let x = c1.max(c2) as f64;
            (x, rows - r1 as f64, x, rows - r1 as f64 - 1.0)
        } else {
            let y = rows - r1.max(r2) as f64;
            (c1 as f64, y, c1 as f64 + 1.0, y)
        };
        let _ = writeln!(
            out,
            r##"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#333" stroke-width="6" stroke-linecap="round"/>"##,
            v.x(x0),
            v.y(y0),
            v.x(x1),
            v.y(y1)
        );
    }
    let s = eg.center(g.start.0, g.start.1);
    let _ = writeln!(
        out,
        r##"<text x="{:.2}" y="{:.2}" font-size="{:.0}" text-anchor="middle" dominant-baseline="central" fill="#1f4e9c" font-weight="bold">S</text>"##,
        v.x(s[0] - 0.3),
        v.y(s[1] + 0.28),
        v.len(0.25)
    );
    path_layer(&mut out, &v, overlay);
    if let Some(draw) = animated.as_mut() {
        draw(&mut out, &v);
    }
    axes(&mut out, &v, "cells");
    legend(&mut out, &v, &keys);
    out.push_str("</svg>\n");
    out
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
        let swatch = match &k.0 {
            Swatch::Fill(fill, stroke, op) => format!(
                r#"<rect x="{x:.1}" y="{:.1}" width="14" height="11" fill="{fill}" fill-opacity="{op}" stroke="{stroke}" stroke-opacity="{op}" stroke-width="1"/>"#,
                y - 9.5
            ),
            Swatch::Outline(colour) => format!(
                r#"<rect x="{:.1}" y="{:.1}" width="12" height="10" fill="none" stroke="{colour}" stroke-width="2.5" stroke-dasharray="4,2"/>"#,
                x + 1.0,
                y - 9.0
            ),
            Swatch::Region => format!(
                r##"<rect x="{:.1}" y="{:.1}" width="12" height="10" fill="none" stroke="#2e8b57" stroke-width="1.5" stroke-dasharray="3,2"/>"##,
                x + 1.0,
                y - 9.0
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
        let _ = writeln!(
            out,
            r#"<g class="key">{swatch}<text x="{:.1}" y="{y:.1}">{}</text></g>"#,
            x + 20.0,
            esc(k.1)
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
    if !scene.reward.regions.is_empty() {
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

/// The outline points of a shape at a pose (for bounds).
fn shape_points(shape: &ShapeSpec, pos: (f64, f64), angle: f64) -> Vec<(f64, f64)> {
    let local: Vec<(f64, f64)> = match shape {
        ShapeSpec::Ball { radius } => {
            vec![
                (-radius, -radius),
                (*radius, *radius),
                (-radius, *radius),
                (*radius, -radius),
            ]
        }
        ShapeSpec::Cuboid { width, height } => {
            let (w, h) = (width / 2.0, height / 2.0);
            vec![(-w, -h), (w, -h), (w, h), (-w, h)]
        }
        ShapeSpec::Capsule { a, b, radius } => vec![
            (a.0 - radius, a.1 - radius),
            (a.0 + radius, a.1 + radius),
            (b.0 - radius, b.1 - radius),
            (b.0 + radius, b.1 + radius),
        ],
        ShapeSpec::Segment { a, b } => vec![*a, *b],
        ShapeSpec::Polyline { points } => points.clone(),
    };
    local.into_iter().map(|p| to_world(pos, angle, p)).collect()
}

/// Fill colour, stroke colour and opacity of a body.
pub(super) struct Paint<'a>(pub(super) &'a str, pub(super) &'a str, pub(super) f64);

pub(super) fn body_svg(
    out: &mut String,
    v: &View,
    shape: &ShapeSpec,
    pos: (f64, f64),
    angle: f64,
    paint: Paint,
) {
    let Paint(fill, stroke, opacity) = paint;
    let style = format!(
        r#"fill="{fill}" fill-opacity="{opacity}" stroke="{stroke}" stroke-opacity="{opacity}" stroke-width="1.5""#
    );
    match shape {
        ShapeSpec::Ball { radius } => {
            let _ = writeln!(
                out,
                r#"<circle cx="{:.2}" cy="{:.2}" r="{:.2}" {style}/>"#,
                v.x(pos.0),
                v.y(pos.1),
                v.len(*radius)
            );
            // a tick shows the rotation
            let t = to_world(pos, angle, (*radius, 0.0));
            let _ = writeln!(
                out,
                r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{stroke}" stroke-opacity="{opacity}" stroke-width="1.2"/>"#,
                v.x(pos.0),
                v.y(pos.1),
                v.x(t.0),
                v.y(t.1)
            );
        }
        ShapeSpec::Cuboid { .. } => {
            let pts: Vec<String> = shape_points(shape, pos, angle)
                .into_iter()
                .map(|p| v.pt(p))
                .collect();
            let _ = writeln!(out, r#"<polygon points="{}" {style}/>"#, pts.join(" "));
        }
        ShapeSpec::Capsule { a, b, radius } => {
            let (a, b) = (to_world(pos, angle, *a), to_world(pos, angle, *b));
            let w = v.len(2.0 * radius);
            // a round-capped line of the outline colour, then a narrower one
            // of the fill colour on it
            for (colour, width) in [(stroke, w + 3.0), (fill, w)] {
                let _ = writeln!(
                    out,
                    r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{colour}" stroke-opacity="{opacity}" stroke-width="{width:.2}" stroke-linecap="round"/>"#,
                    v.x(a.0),
                    v.y(a.1),
                    v.x(b.0),
                    v.y(b.1),
                );
            }
        }
        ShapeSpec::Segment { .. } | ShapeSpec::Polyline { .. } => {
            let pts: Vec<String> = shape_points(shape, pos, angle)
                .into_iter()
                .map(|p| v.pt(p))
                .collect();
            let _ = writeln!(
                out,
                r#"<polyline points="{}" fill="none" stroke="{stroke}" stroke-opacity="{opacity}" stroke-width="4" stroke-linecap="round" stroke-linejoin="round"/>"#,
                pts.join(" ")
            );
        }
    }
}

/// The fill and stroke of the bodies at their end pose.
pub(super) const END_FILL: &str = "#f4b183";
pub(super) const END_STROKE: &str = "#a0522d";

pub(super) fn colours(kind: BodyKind) -> (&'static str, &'static str) {
    match kind {
        BodyKind::Fixed => ("#5b6170", "#2e323b"),
        BodyKind::Kinematic => ("#9c7bd1", "#5a3d8f"),
        BodyKind::Dynamic => ("#6fa8dc", "#1f4e9c"),
    }
}

fn physics_svg(scene: &Scene, p: &PhysicsSpec, overlay: Option<&Overlay>) -> String {
    physics_picture(scene, p, overlay, None)
}

/// Draws the moving parts of an animation over the picture (see
/// [`physics_picture`]).
pub(super) type Layer<'a> = &'a mut dyn FnMut(&mut String, &View);

/// The picture of a physics scene; with `animated`, the bodies at their
/// start pose are faint and `animated` draws, after the path, what moves.
pub(super) fn physics_picture(
    scene: &Scene,
    p: &PhysicsSpec,
    overlay: Option<&Overlay>,
    mut animated: Option<Layer>,
) -> String {
    let g = scene.effect_grid();
    let (mut min, mut max) = (g.min, g.max);
    let mut grow = |q: (f64, f64)| {
        min = [min[0].min(q.0), min[1].min(q.1)];
        max = [max[0].max(q.0), max[1].max(q.1)];
    };
    for b in &p.bodies {
        for q in shape_points(&b.shape, b.position, b.angle) {
            grow(q);
        }
    }
    if let Some(o) = overlay {
        for q in &o.points {
            grow((q[0], q[1]));
        }
    }
    let pad = 0.02 * (max[0] - min[0]).max(max[1] - min[1]);
    let mut v = View::new([min[0] - pad, min[1] - pad], [max[0] + pad, max[1] + pad]);
    let end_pose = overlay.and_then(|o| o.poses.as_ref()).is_some();
    // bodies at their start pose, faded when a terminal pose is drawn too
    let start_opacity = if animated.is_some() {
        0.2
    } else if end_pose {
        0.35
    } else {
        0.9
    };
    let (dyn_fill, dyn_stroke) = colours(BodyKind::Dynamic);
    let mut keys = Vec::new();
    if p.bodies.iter().any(|b| b.kind == BodyKind::Fixed) {
        let (f, st) = colours(BodyKind::Fixed);
        keys.push(Key(Swatch::Fill(f, st, 0.95), "fixed body"));
    }
    if p.bodies.iter().any(|b| b.kind == BodyKind::Kinematic) {
        let (f, st) = colours(BodyKind::Kinematic);
        keys.push(Key(Swatch::Fill(f, st, start_opacity), "kinematic body"));
    }
    keys.push(Key(
        Swatch::Fill(dyn_fill, dyn_stroke, start_opacity),
        "start pose",
    ));
    if animated.is_some() {
        keys.push(Key(
            Swatch::Fill(END_FILL, END_STROKE, 0.9),
            "moving bodies",
        ));
    } else if end_pose {
        keys.push(Key(Swatch::Fill(END_FILL, END_STROKE, 0.9), "end pose"));
    }
    if p.joints.iter().any(|j| j.parent == GROUND) {
        keys.push(Key(Swatch::Hinge(true), "hinge on the ground"));
    }
    if p.joints.iter().any(|j| j.parent != GROUND) {
        keys.push(Key(Swatch::Hinge(false), "joint"));
    }
    keys.push(Key(Swatch::Dot(TRACKED), "tracked point"));
    keys.extend(reward_keys(scene));
    if overlay.is_some() {
        path_keys(&mut keys, Some(TRACKED));
    }
    if let Some(sym) = p.symmetry {
        keys.push(Key(
            Swatch::Line(MIRROR, Some(MIRROR_DASH)),
            match sym {
                Symmetry::FlipY => "mirror line (FlipY)",
                Symmetry::FlipX => "mirror line (FlipX)",
            },
        ));
    }
    v.legend_rows = legend_rows(&keys, v.width());
    let mut out = String::new();
    header(&mut out, &v, scene, overlay);
    effect_layer(&mut out, &v, scene, overlay);
    // the mirror line of a declared symmetry, across the whole picture
    if let Some(sym) = p.symmetry {
        let (a, b) = match sym {
            Symmetry::FlipY => ((v.min[0], 0.0), (v.max[0], 0.0)),
            Symmetry::FlipX => ((0.0, v.min[1]), (0.0, v.max[1])),
        };
        let _ = writeln!(
            out,
            r##"<g><title>mirror line ({sym:?}): one command of each mirror pair is simulated</title><line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{MIRROR}" stroke-width="1.2" stroke-dasharray="{MIRROR_DASH}"/></g>"##,
            v.x(a.0),
            v.y(a.1),
            v.x(b.0),
            v.y(b.1)
        );
    }
    for b in &p.bodies {
        let (fill, stroke) = colours(b.kind);
        let op = if b.kind == BodyKind::Fixed {
            0.95
        } else {
            start_opacity
        };
        let _ = writeln!(out, "<g><title>{}</title>", esc(&b.name));
        body_svg(
            &mut out,
            &v,
            &b.shape,
            b.position,
            b.angle,
            Paint(fill, stroke, op),
        );
        out.push_str("</g>\n");
    }
    if let Some(poses) = overlay
        .and_then(|o| o.poses.as_ref())
        .filter(|_| animated.is_none())
    {
        for (b, pose) in p.bodies.iter().zip(poses) {
            if b.kind == BodyKind::Fixed {
                continue;
            }
            let _ = writeln!(out, "<g><title>{} (end)</title>", esc(&b.name));
            body_svg(
                &mut out,
                &v,
                &b.shape,
                (pose.position[0], pose.position[1]),
                pose.angle,
                Paint(END_FILL, END_STROKE, 0.9),
            );
            out.push_str("</g>\n");
        }
    }
    // joints at their start pose: a ring at the hinge; ground hinges filled
    for j in &p.joints {
        let at = if j.parent == GROUND {
            j.parent_anchor
        } else if let Some(b) = p.body(&j.parent) {
            to_world(b.position, b.angle, j.parent_anchor)
        } else {
            continue;
        };
        let fill = if j.parent == GROUND {
            "#2e323b"
        } else {
            "#ffffff"
        };
        let _ = writeln!(
            out,
            r##"<circle cx="{:.2}" cy="{:.2}" r="4" fill="{fill}" stroke="#2e323b" stroke-width="1.5"><title>{}</title></circle>"##,
            v.x(at.0),
            v.y(at.1),
            esc(&j.name)
        );
    }
    path_layer(&mut out, &v, overlay);
    if let Some(draw) = animated.as_mut() {
        draw(&mut out, &v);
    }
    // the tracked point at the start, over the path (inside its start ring)
    if let Some(b) = p.body(&p.effect.body) {
        let t = to_world(b.position, b.angle, p.effect.point);
        let _ = writeln!(
            out,
            r##"<circle cx="{:.2}" cy="{:.2}" r="3.5" fill="{TRACKED}"><title>tracked point</title></circle>"##,
            v.x(t.0),
            v.y(t.1)
        );
    }
    axes(&mut out, &v, "m");
    legend(&mut out, &v, &keys);
    out.push_str("</svg>\n");
    out
}
