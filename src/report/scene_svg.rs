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

/// The largest side of the picture, in pixels.
const SIDE: f64 = 760.0;
const MARGIN: f64 = 30.0;
const CAPTION: f64 = 46.0;

/// Maps world metres to SVG pixels (y up in the world, down in SVG).
struct View {
    min: [f64; 2],
    max: [f64; 2],
    scale: f64,
}

impl View {
    fn new(min: [f64; 2], max: [f64; 2]) -> View {
        let w = (max[0] - min[0]).max(1e-9);
        let h = (max[1] - min[1]).max(1e-9);
        View {
            min,
            max,
            scale: SIDE / w.max(h),
        }
    }
    fn x(&self, x: f64) -> f64 {
        MARGIN + (x - self.min[0]) * self.scale
    }
    fn y(&self, y: f64) -> f64 {
        CAPTION + MARGIN + (self.max[1] - y) * self.scale
    }
    fn len(&self, l: f64) -> f64 {
        l * self.scale
    }
    fn width(&self) -> f64 {
        2.0 * MARGIN + (self.max[0] - self.min[0]) * self.scale
    }
    fn height(&self) -> f64 {
        CAPTION + 2.0 * MARGIN + (self.max[1] - self.min[1]) * self.scale
    }
    fn pt(&self, p: (f64, f64)) -> String {
        format!("{:.2},{:.2}", self.x(p.0), self.y(p.1))
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
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
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="#7fd17f" fill-opacity="0.55"/>"##,
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
            r##"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="#ff9f1c" fill-opacity="0.25" stroke="#e07000" stroke-width="2.5"/>"##,
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

fn path_layer(out: &mut String, v: &View, overlay: Option<&Overlay>) {
    let Some(o) = overlay else { return };
    if o.points.is_empty() {
        return;
    }
    let pts: Vec<String> = o.points.iter().map(|p| v.pt((p[0], p[1]))).collect();
    let _ = writeln!(
        out,
        r##"<polyline points="{}" fill="none" stroke="#e07000" stroke-width="2.2" stroke-linejoin="round" stroke-linecap="round"/>"##,
        pts.join(" ")
    );
    let s = o.points[0];
    let e = o.points[o.points.len() - 1];
    let _ = writeln!(
        out,
        r##"<circle cx="{:.2}" cy="{:.2}" r="4" fill="#ffffff" stroke="#e07000" stroke-width="2"/>"##,
        v.x(s[0]),
        v.y(s[1])
    );
    let _ = writeln!(
        out,
        r##"<circle cx="{:.2}" cy="{:.2}" r="5" fill="#e07000"/>"##,
        v.x(e[0]),
        v.y(e[1])
    );
}

fn grid_svg(scene: &Scene, g: &GridSpec, overlay: Option<&Overlay>) -> String {
    let eg = g.effect_grid();
    let v = View::new(eg.min, eg.max);
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
    out.push_str("</svg>\n");
    out
}

/// A one-line key at the bottom right.
fn legend(out: &mut String, v: &View, with_path: bool) {
    let mut items = vec![
        ("#6fa8dc", "start pose"),
        ("#7fd17f", "reward cell"),
        ("#d62728", "tracked point"),
    ];
    if with_path {
        items.insert(1, ("#f4b183", "end pose"));
        items.push(("#e07000", "path, terminal cell"));
    }
    let mut x = v.width() - MARGIN;
    let y = v.height() - 10.0;
    for (colour, label) in items.iter().rev() {
        x -= 6.8 * label.len() as f64 + 22.0;
        let _ = writeln!(
            out,
            r##"<rect x="{:.1}" y="{:.1}" width="11" height="11" fill="{colour}" stroke="#555" stroke-width="0.5"/><text x="{:.1}" y="{:.1}" font-size="11" fill="#333">{label}</text>"##,
            x,
            y - 9.0,
            x + 15.0,
            y
        );
    }
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
struct Paint<'a>(&'a str, &'a str, f64);

fn body_svg(
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

fn colours(kind: BodyKind) -> (&'static str, &'static str) {
    match kind {
        BodyKind::Fixed => ("#5b6170", "#2e323b"),
        BodyKind::Kinematic => ("#9c7bd1", "#5a3d8f"),
        BodyKind::Dynamic => ("#6fa8dc", "#1f4e9c"),
    }
}

fn physics_svg(scene: &Scene, p: &PhysicsSpec, overlay: Option<&Overlay>) -> String {
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
    let v = View::new([min[0] - pad, min[1] - pad], [max[0] + pad, max[1] + pad]);
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
            r##"<g><title>mirror line ({sym:?}): one command of each mirror pair is simulated</title><line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="#7b68ee" stroke-width="1" stroke-dasharray="8,4,2,4"/></g>"##,
            v.x(a.0),
            v.y(a.1),
            v.x(b.0),
            v.y(b.1)
        );
    }
    // bodies at their start pose (faded when a terminal pose is drawn too)
    let start_opacity = if overlay.and_then(|o| o.poses.as_ref()).is_some() {
        0.35
    } else {
        0.9
    };
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
    if let Some(poses) = overlay.and_then(|o| o.poses.as_ref()) {
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
                Paint("#f4b183", "#a0522d", 0.9),
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
    // the tracked point at the start
    if let Some(b) = p.body(&p.effect.body) {
        let t = to_world(b.position, b.angle, p.effect.point);
        let _ = writeln!(
            out,
            r##"<circle cx="{:.2}" cy="{:.2}" r="3.5" fill="#d62728"><title>tracked point</title></circle>"##,
            v.x(t.0),
            v.y(t.1)
        );
    }
    path_layer(&mut out, &v, overlay);
    // a 1 m scale bar
    let y = v.height() - 10.0;
    let _ = writeln!(
        out,
        r##"<path d="M{:.2},{y:.2}h{:.2}" stroke="#333" stroke-width="2"/><text x="{:.2}" y="{:.2}" font-size="11" fill="#333">{}</text>"##,
        MARGIN,
        v.len(scale_bar(max[0] - min[0])),
        MARGIN + v.len(scale_bar(max[0] - min[0])) + 6.0,
        y + 4.0,
        format_args!("{} m", scale_bar(max[0] - min[0]))
    );
    legend(&mut out, &v, overlay.is_some());
    out.push_str("</svg>\n");
    out
}

fn scale_bar(width: f64) -> f64 {
    if width > 4.0 {
        1.0
    } else if width > 1.5 {
        0.5
    } else {
        0.1
    }
}
