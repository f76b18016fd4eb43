//! The picture of a physics scene: its bodies, joints, effect grid and
//! reward.

use super::*;
use crate::effect::Feature;
use crate::scene::physics::{JointKind, JointSpec};

/// The outline points of a shape at a pose (for bounds).
pub(super) fn shape_points(shape: &ShapeSpec, pos: (f64, f64), angle: f64) -> Vec<(f64, f64)> {
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
pub(in crate::report) struct Paint<'a>(
    pub(in crate::report) &'a str,
    pub(in crate::report) &'a str,
    pub(in crate::report) f64,
);

pub(in crate::report) fn body_svg(
    out: &mut String,
    v: &View,
    shape: &ShapeSpec,
    pos: (f64, f64),
    angle: f64,
    paint: Paint,
) {
    let Paint(fill, stroke, opacity) = paint;
    let points = || -> Vec<String> {
        let pts = shape_points(shape, pos, angle).into_iter();
        pts.map(|p| v.pt(p)).collect()
    };
    let style = format!(
        r#"fill="{fill}" fill-opacity="{opacity}" stroke="{stroke}" stroke-opacity="{opacity}" stroke-width="1.5""#
    );
    match shape {
        ShapeSpec::Ball { radius } => {
            let (c, r) = (v.centre(pos), v.len(*radius));
            // a tick shows the rotation
            let tick = v.segment(pos, to_world(pos, angle, (*radius, 0.0)));
            let _ = writeln!(
                out,
                r#"<circle {c} r="{r:.2}" {style}/>
<line {tick} stroke="{stroke}" stroke-opacity="{opacity}" stroke-width="1.2"/>"#
            );
        }
        ShapeSpec::Cuboid { .. } => {
            let _ = writeln!(out, r#"<polygon points="{}" {style}/>"#, points().join(" "));
        }
        ShapeSpec::Capsule { a, b, radius } => {
            let (a, b) = (to_world(pos, angle, *a), to_world(pos, angle, *b));
            let w = v.len(2.0 * radius);
            // a round-capped line of the outline colour, then a narrower one
            // of the fill colour on it
            for (colour, width) in [(stroke, w + 3.0), (fill, w)] {
                let _ = writeln!(
                    out,
                    r#"<line {} stroke="{colour}" stroke-opacity="{opacity}" stroke-width="{width:.2}" stroke-linecap="round"/>"#,
                    v.segment(a, b)
                );
            }
        }
        ShapeSpec::Segment { .. } | ShapeSpec::Polyline { .. } => {
            let _ = writeln!(
                out,
                r#"<polyline points="{}" fill="none" stroke="{stroke}" stroke-opacity="{opacity}" stroke-width="4" stroke-linecap="round" stroke-linejoin="round"/>"#,
                points().join(" ")
            );
        }
    }
}

/// The fill and stroke of the bodies at their end pose.
pub(in crate::report) const END_FILL: &str = "#f4b183";
pub(in crate::report) const END_STROKE: &str = "#a0522d";

pub(in crate::report) fn colours(kind: BodyKind) -> (&'static str, &'static str) {
    match kind {
        BodyKind::Fixed => ("#5b6170", "#2e323b"),
        BodyKind::Kinematic => ("#9c7bd1", "#5a3d8f"),
        BodyKind::Dynamic => ("#6fa8dc", "#1f4e9c"),
    }
}

/// The picture of a physics scene; with `animated`, the bodies at their
/// start pose are faint and `animated` draws, after the path, what moves.
pub(in crate::report) fn physics_picture(
    scene: &Scene,
    p: &PhysicsSpec,
    overlay: Option<&Overlay>,
    mut animated: Option<Layer>,
) -> String {
    // an effect that is not one point's world cell (a joint's
    // coordinate, an angle, a product) has no cells over the world: the
    // picture says so instead of drawing them
    let world_cells = p.effect.world_point().is_some()
        || matches!(p.effect.features.as_slice(), [Feature::Centre { .. }]);
    let mut v = picture_view(scene, p, overlay, world_cells);
    let note = (!world_cells).then(|| effect_note(scene, p, v.width()));
    v.note_lines = note.as_ref().map_or(0, |n| n.len().saturating_sub(1));
    let end_pose = overlay.and_then(|o| o.poses.as_ref()).is_some();
    // bodies at their start pose, faded when a terminal pose is drawn too
    let start_opacity = if animated.is_some() {
        0.2
    } else if end_pose {
        0.35
    } else {
        0.9
    };
    let keys = picture_keys(scene, p, overlay, animated.is_some(), start_opacity);
    v.legend_rows = legend_rows(&keys, v.width());
    let mut out = String::new();
    header(&mut out, &v, scene, overlay);
    if world_cells {
        effect_layer(&mut out, &v, scene, overlay);
    } else {
        for (k, line) in note.iter().flatten().enumerate() {
            let y = 60.0 + NOTE_LINE * k as f64;
            let _ = writeln!(
                out,
                r##"<text x="{MARGIN}" y="{y}" font-size="12" fill="#555">{}</text>"##,
                esc(line)
            );
        }
    }
    if let Some(sym) = p.symmetry {
        mirror_line(&mut out, &v, sym);
    }
    // every body at its start pose (fixed bodies opaque)
    let start = p.bodies.iter().map(|b| {
        let ((fill, stroke), fixed) = (colours(b.kind), b.kind == BodyKind::Fixed);
        let op = if fixed { 0.95 } else { start_opacity };
        (b, b.position, b.angle, Paint(fill, stroke, op))
    });
    bodies_layer(&mut out, &v, start, "");
    if let Some(poses) = overlay
        .and_then(|o| o.poses.as_ref())
        .filter(|_| animated.is_none())
    {
        // the bodies that move, at their terminal poses
        let moved = (p.bodies.iter().zip(poses)).filter(|(b, _)| b.kind != BodyKind::Fixed);
        let end = moved.map(|(b, q)| {
            let position = (q.position[0], q.position[1]);
            (b, position, q.angle, Paint(END_FILL, END_STROKE, 0.9))
        });
        bodies_layer(&mut out, &v, end, " (end)");
    }
    joints_layer(&mut out, &v, p);
    path_layer(&mut out, &v, overlay);
    if let Some(draw) = animated.as_mut() {
        draw(&mut out, &v);
    }
    tracked_start(&mut out, &v, p);
    axes(&mut out, &v, "m");
    legend(&mut out, &v, &keys);
    out.push_str("</svg>\n");
    out
}

/// The picture's extent: the effect grid (when its cells are over the
/// world), every body at its start pose and the overlay's points, padded.
fn picture_view(
    scene: &Scene,
    p: &PhysicsSpec,
    overlay: Option<&Overlay>,
    world_cells: bool,
) -> View {
    let (mut min, mut max) = if world_cells {
        let g = scene.effect_grid();
        (g.min, g.max)
    } else {
        ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2])
    };
    let mut grow = |q: (f64, f64)| {
        min = [min[0].min(q.0), min[1].min(q.1)];
        max = [max[0].max(q.0), max[1].max(q.1)];
    };
    for b in &p.bodies {
        for q in shape_points(&b.shape, b.position, b.angle) {
            grow(q);
        }
    }
    for (_, a, b, _) in p.joints.iter().filter_map(|j| rail(p, j)) {
        grow(a);
        grow(b);
    }
    if let Some(o) = overlay {
        for q in &o.points {
            grow((q[0], q[1]));
        }
    }
    let pad = 0.02 * (max[0] - min[0]).max(max[1] - min[1]);
    View::new([min[0] - pad, min[1] - pad], [max[0] + pad, max[1] + pad])
}

/// The legend's entries, in the order they are drawn.
fn picture_keys(
    scene: &Scene,
    p: &PhysicsSpec,
    overlay: Option<&Overlay>,
    animated: bool,
    start_opacity: f64,
) -> Vec<Key> {
    let end_pose = overlay.and_then(|o| o.poses.as_ref()).is_some();
    use BodyKind::{Dynamic, Fixed, Kinematic};
    let has = |k: BodyKind| p.bodies.iter().any(|b| b.kind == k);
    let fill = |k: BodyKind, opacity: f64| {
        let (f, st) = colours(k);
        Swatch::Fill(f, st, opacity)
    };
    let end = || Swatch::Fill(END_FILL, END_STROKE, 0.9);
    let ground = p.joints.iter().filter(|j| j.parent == GROUND).count();
    let mut keys: Vec<Key> = [
        (has(Fixed), fill(Fixed, 0.95), "fixed body"),
        (
            has(Kinematic),
            fill(Kinematic, start_opacity),
            "kinematic body",
        ),
        (true, fill(Dynamic, start_opacity), "start pose"),
        (animated, end(), "moving bodies"),
        (!animated && end_pose, end(), "end pose"),
        (ground > 0, Swatch::Hinge(true), "hinge on the ground"),
        (ground < p.joints.len(), Swatch::Hinge(false), "joint"),
        (true, Swatch::Dot(TRACKED), "tracked point"),
    ]
    .into_iter()
    .filter_map(|(shown, swatch, name)| shown.then_some(Key(swatch, name)))
    .collect();
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
    keys
}

/// An effect whose cells are not over the world, said in words.
fn effect_note(scene: &Scene, p: &PhysicsSpec, width: f64) -> Vec<String> {
    let g = scene.effect_grid();
    let text = format!(
        "effect: {} ({} x {} cells, not drawn over the world; the dot and path are the first feature's body)",
        describe_effect(p),
        g.rows,
        g.cols
    );
    // about 6.5 px a character at 12 px: the lines fit the picture
    let fits = ((width - 2.0 * MARGIN) / 6.5).max(20.0) as usize;
    let mut lines = vec![String::new()];
    for word in text.split(' ') {
        let last = lines.last_mut().expect("a line");
        if !last.is_empty() && last.chars().count() + 1 + word.chars().count() > fits {
            lines.push(word.to_string());
        } else {
            if !last.is_empty() {
                last.push(' ');
            }
            last.push_str(word);
        }
    }
    lines
}

/// The mirror line of a declared symmetry, across the whole picture.
fn mirror_line(out: &mut String, v: &View, sym: Symmetry) {
    let (a, b) = match sym {
        Symmetry::FlipY => ((v.min[0], 0.0), (v.max[0], 0.0)),
        Symmetry::FlipX => ((0.0, v.min[1]), (0.0, v.max[1])),
    };
    let _ = writeln!(
        out,
        r##"<g><title>mirror line ({sym:?}): one command of each mirror pair is simulated</title><line {} stroke="{MIRROR}" stroke-width="1.2" stroke-dasharray="{MIRROR_DASH}"/></g>"##,
        v.segment(a, b)
    );
}

/// Each body at a pose, in its paint, in a group titled with its name and
/// `suffix`.
fn bodies_layer<'a>(
    out: &mut String,
    v: &View,
    bodies: impl Iterator<Item = (&'a BodySpec, (f64, f64), f64, Paint<'a>)>,
    suffix: &str,
) {
    for (b, position, angle, paint) in bodies {
        let _ = writeln!(out, "<g><title>{}{suffix}</title>", esc(&b.name));
        body_svg(out, v, &b.shape, position, angle, paint);
        out.push_str("</g>\n");
    }
}

/// A slider's anchor, the ends of its rail and the unit normal to it.
type Rail = ((f64, f64), (f64, f64), (f64, f64), (f64, f64));

/// A slider's rail at the start pose: its anchor, the ends at its
/// limits (0.5 m each way without limits), the unit normal to its axis
/// (`None` for a hinge).
fn rail(p: &PhysicsSpec, j: &JointSpec) -> Option<Rail> {
    let JointKind::Prismatic { axis } = j.kind else {
        return None;
    };
    let (at, angle) = match p.body(&j.parent) {
        Some(b) => (to_world(b.position, b.angle, j.parent_anchor), b.angle),
        None => (j.parent_anchor, 0.0),
    };
    let n = axis.0.hypot(axis.1);
    let (s, c) = angle.sin_cos();
    let u = ((c * axis.0 - s * axis.1) / n, (s * axis.0 + c * axis.1) / n);
    let (lo, hi) = j.limits.unwrap_or((-0.5, 0.5));
    let along = |d: f64| (at.0 + d * u.0, at.1 + d * u.1);
    Some((at, along(lo), along(hi), (-u.1, u.0)))
}

/// Joints at their start pose: a ring at a hinge (ground hinges filled);
/// a slider's rail along its axis between its limits, with end stops
/// (none without limits), its anchor a dot.
fn joints_layer(out: &mut String, v: &View, p: &PhysicsSpec) {
    for j in &p.joints {
        let name = esc(&j.name);
        if let Some((at, a, b, n)) = rail(p, j) {
            let limits = match j.limits {
                Some((lo, hi)) => format!("limits [{lo}, {hi}] m"),
                None => "no limits".into(),
            };
            let line = |a, b| {
                format!(
                    r##"<line {} stroke="#2e323b" stroke-width="2"/>"##,
                    v.segment(a, b)
                )
            };
            let mut g = format!("<g><title>{name}: slider, {limits}</title>{}", line(a, b));
            if j.limits.is_some() {
                // the end stops: 6 px each side of the rail
                let t = 6.0 / v.len(1.0);
                for e in [a, b] {
                    g += &line(
                        (e.0 - t * n.0, e.1 - t * n.1),
                        (e.0 + t * n.0, e.1 + t * n.1),
                    );
                }
            }
            let _ = writeln!(
                out,
                r##"{g}<circle {} r="2.5" fill="#2e323b"/></g>"##,
                v.centre(at)
            );
            continue;
        }
        let at = if j.parent == GROUND {
            j.parent_anchor
        } else if let Some(b) = p.body(&j.parent) {
            to_world(b.position, b.angle, j.parent_anchor)
        } else {
            continue;
        };
        let fill = ["#ffffff", "#2e323b"][usize::from(j.parent == GROUND)];
        let c = v.centre(at);
        let _ = writeln!(
            out,
            r##"<circle {c} r="4" fill="{fill}" stroke="#2e323b" stroke-width="1.5"><title>{name}</title></circle>"##
        );
    }
}

/// The tracked point at the start, over the path (inside its start ring).
fn tracked_start(out: &mut String, v: &View, p: &PhysicsSpec) {
    let drawn = p.effect.drawn_point(|j| p.child_of(j));
    if let Some((b, point)) = drawn.and_then(|(b, q)| Some((p.body(b)?, q))) {
        let t = to_world(b.position, b.angle, point);
        let _ = writeln!(
            out,
            r##"<circle {} r="3.5" fill="{TRACKED}"><title>tracked point</title></circle>"##,
            v.centre(t)
        );
    }
}

/// The effect's features in words: `joint \`pivot\` (9 bins over [-0.9, 0.9]) x ...`.
pub fn describe_effect(p: &PhysicsSpec) -> String {
    let parts: Vec<String> = p
        .effect
        .features()
        .iter()
        .map(|f| match f {
            Feature::Point {
                body,
                point,
                frame,
                grid,
            } => {
                let frame = frame.as_ref().map(|f| format!(" in the frame of `{f}`"));
                let ([x0, y0], [x1, y1], (x, y)) = (grid.min, grid.max, point);
                format!(
                    "point ({x}, {y}) of `{body}`{} ({} x {} cells over [{x0}, {x1}] x [{y0}, {y1}] m)",
                    frame.unwrap_or_default(),
                    grid.rows,
                    grid.cols,
                )
            }
            Feature::Joint { joint, bins, range } => {
                let unit = p.joint(joint).map_or("", |j| j.kind.unit());
                format!(
                    "joint `{joint}` ({bins} bins over [{}, {}] {unit})",
                    range.0, range.1
                )
            }
            Feature::Centre { bodies, grid } => {
                let ([x0, y0], [x1, y1]) = (grid.min, grid.max);
                format!(
                    "centre of mass of `{}` ({} x {} cells over [{x0}, {x1}] x [{y0}, {y1}] m)",
                    bodies.join("`, `"),
                    grid.rows,
                    grid.cols,
                )
            }
            Feature::Angle { body, bins, range } => format!(
                "angle of `{body}` ({bins} bins over [{}, {}] rad)",
                range.0, range.1
            ),
        })
        .collect();
    parts.join(" x ")
}
