//! Expanding the shorthands: the plain bodies and joints a chain or a
//! wall stands for, in the documented order (see [`super`]).

use super::super::physics::{
    limits::{MAX_BODIES, MAX_POINTS},
    BodyKind, BodySpec, JointSpec, PhysicsSpec, ShapeSpec, GROUND,
};
use super::super::Invalid;
use super::{ChainSpec, Each, LinkShape, Placement, WallSpec};
use std::collections::HashMap;

/// Which shorthand generated each body or joint: name -> (`chains` or
/// `walls`, index).
pub(crate) type Origins = HashMap<String, (&'static str, usize)>;

/// A generated length or coordinate, rounded to 1e-12 m (so that computed
/// sums are the numbers one would write), without a negative zero.
fn tidy(x: f64) -> f64 {
    if x.abs() < 1e3 {
        (x * 1e12).round() / 1e12 + 0.0
    } else {
        x + 0.0
    }
}

/// Replaces the shorthands of `spec` (its `walls` and `chains`) by the
/// bodies and joints they stand for, in the documented order; `Err` names
/// the shorthand's field at fault. Returns which shorthand generated which
/// name.
pub(crate) fn expand(spec: &mut PhysicsSpec) -> Result<Origins, Invalid> {
    let mut origins = Origins::new();
    let mut bodies = Vec::new();
    let mut joints = Vec::new();
    for (k, w) in spec.walls.iter().enumerate() {
        for b in wall_boxes(w, k)? {
            origins.entry(b.name.clone()).or_insert(("walls", k));
            bodies.push(b);
        }
    }
    for (k, c) in spec.chains.iter().enumerate() {
        let (links, js) = chain(c, k, |name| {
            bodies
                .iter()
                .chain(&spec.bodies)
                .find(|b| b.name == name)
                .map(|b| (b.position, b.angle))
        })?;
        for name in links
            .iter()
            .map(|b| &b.name)
            .chain(js.iter().map(|j| &j.name))
        {
            origins.entry(name.clone()).or_insert(("chains", k));
        }
        bodies.extend(links);
        joints.extend(js);
    }
    spec.bodies.splice(0..0, bodies);
    spec.joints.splice(0..0, joints);
    spec.walls.clear();
    spec.chains.clear();
    Ok(origins)
}

fn finite(p: (f64, f64)) -> bool {
    p.0.is_finite() && p.1.is_finite()
}

/// The links and joints of chain `c` (entry `k`); `pose` finds a parent
/// body's start pose.
fn chain(
    c: &ChainSpec,
    k: usize,
    pose: impl Fn(&str) -> Option<((f64, f64), f64)>,
) -> Result<(Vec<BodySpec>, Vec<JointSpec>), Invalid> {
    let chain = Chain { c, k };
    chain.check_counts()?;
    chain.check_numbers()?;
    let anchor0 = chain.anchor0(pose)?;
    let n = c.links;
    let (mut bodies, mut joints) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut along = 0.0;
    for i in 0..n {
        let l = c.length.get(i);
        let centre = along + l / 2.0;
        along += l;
        bodies.push(chain.link(i, centre));
        if c.free && i == 0 {
            continue;
        }
        joints.push(chain.joint(i, anchor0));
    }
    Ok((bodies, joints))
}

/// A chain being expanded, entry `k` of `chains`.
struct Chain<'a> {
    c: &'a ChainSpec,
    k: usize,
}

impl Chain<'_> {
    /// The error at the chain's `field`.
    fn bad(&self, field: &str, msg: String) -> Invalid {
        let k = self.k;
        Invalid::new(field, format!("chains[{k}]: {msg}")).within("chains", k)
    }

    /// The number of links, and one value per link (per joint) or a list
    /// of as many for each field that takes a list.
    fn check_counts(&self) -> Result<(), Invalid> {
        let c = self.c;
        let n = c.links;
        if n == 0 || n > MAX_BODIES {
            return Err(self.bad(
                "links",
                format!("between 1 and {MAX_BODIES} links, found {n}"),
            ));
        }
        let counts: [(&str, Option<usize>, &str); 7] = [
            ("length", c.length.len(), "lengths"),
            ("width", c.width.len(), "widths"),
            ("mass", c.mass.as_ref().and_then(Each::len), "masses"),
            (
                "density",
                c.density.as_ref().and_then(Each::len),
                "densities",
            ),
            ("damping", c.damping.len(), "dampings"),
            ("motor", c.motor.as_ref().and_then(Each::len), "motors"),
            (
                "names",
                (!c.names.is_empty()).then_some(c.names.len()),
                "names",
            ),
        ];
        let joint_names = (!c.joint_names.is_empty()).then_some(c.joint_names.len());
        // a free chain has no joint 1
        let nj = n - usize::from(c.free);
        for (field, len, what) in counts
            .into_iter()
            .chain([("joint_names", joint_names, "names")])
        {
            let per_joint = matches!(field, "damping" | "motor" | "joint_names");
            let want = if per_joint { nj } else { n };
            if let Some(m) = len.filter(|&m| m != want) {
                let of = if per_joint && c.free {
                    format!("{nj} joints (a free chain of {n} links)")
                } else if per_joint {
                    format!("{n} joints")
                } else {
                    format!("{n} links")
                };
                return Err(self.bad(
                    field,
                    format!(
                        "one value for all {of} or a list of {want} {what} (one per {}), found a list of {m}",
                        if per_joint { "joint" } else { "link" }
                    ),
                ));
            }
        }
        Ok(())
    }

    /// No parent for a free chain, lengths and widths > 0, a finite base
    /// and angle.
    fn check_numbers(&self) -> Result<(), Invalid> {
        let c = self.c;
        if c.free && c.parent != GROUND {
            return Err(self.bad(
                "parent",
                format!(
                    "no `parent` for a free chain (`free: true`: link 1 is joined to nothing), found `{}`",
                    c.parent
                ),
            ));
        }
        for (field, each) in [("length", &c.length), ("width", &c.width)] {
            for i in 0..c.links {
                let v = each.get(i);
                if !(v.is_finite() && v > 0.0) {
                    return Err(self.bad(
                        field,
                        format!("a {field} > 0 m for every link, found {v} (link {})", i + 1),
                    ));
                }
            }
        }
        if !finite(c.base) || !c.angle.is_finite() {
            return Err(self.bad(
                if finite(c.base) { "angle" } else { "base" },
                "a finite base and angle".into(),
            ));
        }
        Ok(())
    }

    /// Joint 1's anchor on its parent: the base on ground, or the base in
    /// the parent body's frame (its start pose found by `pose`).
    fn anchor0(
        &self,
        pose: impl Fn(&str) -> Option<((f64, f64), f64)>,
    ) -> Result<(f64, f64), Invalid> {
        let c = self.c;
        if c.parent == GROUND {
            return Ok((tidy(c.base.0), tidy(c.base.1)));
        }
        let Some((p, a)) = pose(&c.parent) else {
            return Err(self.bad(
                "parent",
                format!(
                    "`ground` or a body written before the chain (a wall's box, an earlier chain's link, or one of `bodies`), found `{}`",
                    c.parent
                ),
            ));
        };
        let (s, co) = a.sin_cos();
        let (dx, dy) = (c.base.0 - p.0, c.base.1 - p.1);
        Ok((tidy(co * dx + s * dy), tidy(-s * dx + co * dy)))
    }

    /// Link `i`'s name.
    fn link_name(&self, i: usize) -> String {
        let named = self.c.names.get(i).cloned();
        named.unwrap_or_else(|| format!("{}{}", self.c.prefix, i + 1))
    }

    /// Link `i` (0-based), its centre `centre` metres along the chain.
    fn link(&self, i: usize, centre: f64) -> BodySpec {
        let c = self.c;
        let l = c.length.get(i);
        let (s, co) = c.angle.sin_cos();
        BodySpec {
            name: self.link_name(i),
            kind: BodyKind::Dynamic,
            shape: match c.shape {
                LinkShape::Cuboid => ShapeSpec::Cuboid {
                    width: tidy(l),
                    height: tidy(c.width.get(i)),
                },
                LinkShape::Capsule => ShapeSpec::Capsule {
                    a: (tidy(-l / 2.0), 0.0),
                    b: (tidy(l / 2.0), 0.0),
                    radius: tidy(c.width.get(i) / 2.0),
                },
            },
            mass: c.mass.as_ref().map(|m| m.get(i)),
            density: c.density.as_ref().map(|d| d.get(i)),
            position: (tidy(c.base.0 + co * centre), tidy(c.base.1 + s * centre)),
            angle: c.angle,
            linear_damping: c.linear_damping,
            angular_damping: c.angular_damping,
            friction: c.friction,
            restitution: c.restitution,
            lock_rotation: false,
            collide: true,
            fast_rotation: false,
            drag: c.drag,
            inertia: None,
        }
    }

    /// The joint that joins link `i` (0-based, not link 0 of a free
    /// chain) to the link before it, or link 0 to the parent at
    /// `anchor0`.
    fn joint(&self, i: usize, anchor0: (f64, f64)) -> JointSpec {
        let c = self.c;
        // joint j (0-based) of a free chain joins link j + 2 to link j + 1
        let j = i - usize::from(c.free);
        let name = c.joint_names.get(j).cloned();
        let (parent, parent_anchor) = match i {
            0 => (c.parent.clone(), anchor0),
            _ => (
                self.link_name(i - 1),
                (tidy(c.length.get(i - 1) / 2.0), 0.0),
            ),
        };
        JointSpec {
            name: name.unwrap_or_else(|| format!("{}{}", c.joint_prefix, j + 1)),
            parent,
            child: self.link_name(i),
            parent_anchor,
            child_anchor: (tidy(-c.length.get(i) / 2.0), 0.0),
            limits: c.limits,
            damping: c.damping.get(j),
            motor: c.motor.as_ref().map(|m| m.get(j)),
            kind: Default::default(),
            contacts: c.contacts,
        }
    }
}

/// One straight piece of a wall's line: from `a` along unit `u` for
/// `len` metres; `out`, the unit normal on the Outside side; whether each
/// end meets another piece; the stem of its boxes' default names.
struct Piece {
    a: (f64, f64),
    u: (f64, f64),
    len: f64,
    out: (f64, f64),
    joined: (bool, bool),
    stem: Option<String>,
}

/// The fixed boxes of wall `w` (entry `k`), in order.
fn wall_boxes(w: &WallSpec, k: usize) -> Result<Vec<BodySpec>, Invalid> {
    let wall = Wall {
        w,
        k,
        who: format!("wall `{}`", w.name),
    };
    if w.name.trim().is_empty() {
        return Err(wall.bad("name", "a non-empty name".into()));
    }
    let t = w.thickness;
    if !(t.is_finite() && t > 0.0) {
        return Err(wall.bad("thickness", format!("a thickness > 0 m, found {t}")));
    }
    let pieces = wall.pieces()?;
    let cuts = wall.door_cuts(&pieces)?;
    let mut boxes = Vec::new();
    for (s, c) in pieces.iter().zip(cuts) {
        boxes.extend(wall.piece_boxes(s, c)?);
    }
    wall.name_boxes(&mut boxes)?;
    Ok(boxes)
}

/// A door's cut along a piece: where it starts and ends along it, and
/// the door's index.
type Cut = (f64, f64, usize);

/// A wall whose boxes are being made, entry `k` of `walls`; `who` names
/// it in errors.
struct Wall<'a> {
    w: &'a WallSpec,
    k: usize,
    who: String,
}

impl Wall<'_> {
    /// The error at the wall's `field`.
    fn bad(&self, field: &str, msg: String) -> Invalid {
        Invalid::new(field, format!("{}: {msg}", self.who)).within("walls", self.k)
    }

    /// The straight pieces of the wall's line: a room's four sides, or a
    /// line's segments.
    fn pieces(&self) -> Result<Vec<Piece>, Invalid> {
        let w = self.w;
        match (&w.room, w.points.is_empty()) {
            (Some(_), false) => Err(self.bad("room", "`points` or `room`, not both".into())),
            (None, true) => Err(self.bad(
                "points",
                "a line: `points: [(x, y), ...]` or `room: ((min_x, min_y), (max_x, max_y))`"
                    .into(),
            )),
            (Some((lo, hi)), true) => self.room_pieces(*lo, *hi),
            (None, false) => self.line_pieces(),
        }
    }

    /// The four sides of a room from `lo` to `hi`: south, north, west,
    /// east, each joined at both ends.
    fn room_pieces(&self, lo: (f64, f64), hi: (f64, f64)) -> Result<Vec<Piece>, Invalid> {
        if !(finite(lo) && finite(hi) && lo.0 < hi.0 && lo.1 < hi.1) {
            return Err(self.bad(
                "room",
                format!(
                    "a room ((min_x, min_y), (max_x, max_y)) with min < max, found (({}, {}), ({}, {}))",
                    lo.0, lo.1, hi.0, hi.1
                ),
            ));
        }
        let (dx, dy) = (hi.0 - lo.0, hi.1 - lo.1);
        let side = |a, u, len, out, stem: &str| Piece {
            a,
            u,
            len,
            out,
            joined: (true, true),
            stem: Some(format!("{}_{stem}", self.w.name)),
        };
        Ok(vec![
            side(lo, (1.0, 0.0), dx, (0.0, -1.0), "south"),
            side((lo.0, hi.1), (1.0, 0.0), dx, (0.0, 1.0), "north"),
            side(lo, (0.0, 1.0), dy, (-1.0, 0.0), "west"),
            side((hi.0, lo.1), (0.0, 1.0), dy, (1.0, 0.0), "east"),
        ])
    }

    /// The segments of the wall's `points`, open or closed, with their
    /// outside normals.
    fn line_pieces(&self) -> Result<Vec<Piece>, Invalid> {
        let w = self.w;
        let p = &w.points;
        if p.len() > MAX_POINTS {
            return Err(self.bad(
                "points",
                format!("at most {MAX_POINTS} points, found {}", p.len()),
            ));
        }
        if p.len() < 2 + usize::from(w.closed) {
            return Err(self.bad(
                "points",
                format!(
                    "at least {} points for {} wall, found {}",
                    2 + usize::from(w.closed),
                    if w.closed { "a closed" } else { "an open" },
                    p.len()
                ),
            ));
        }
        if let Some(q) = p.iter().find(|q| !finite(**q)) {
            return Err(self.bad("points", format!("finite points, found ({}, {})", q.0, q.1)));
        }
        let n = p.len();
        let segs = if w.closed { n } else { n - 1 };
        // the enclosed area's orientation: its outside is on the right
        // of a counter-clockwise line
        let area: f64 = (0..n)
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % n]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum();
        let flip = if w.closed && area < 0.0 { -1.0 } else { 1.0 };
        let mut out = Vec::with_capacity(segs);
        for i in 0..segs {
            let (a, b) = (p[i], p[(i + 1) % n]);
            let (dx, dy) = (b.0 - a.0, b.1 - a.1);
            let len = dx.hypot(dy);
            if len <= 0.0 {
                return Err(self.bad(
                    "points",
                    format!(
                        "distinct consecutive points{}, but point {} ({}, {}) repeats the one before",
                        if w.closed { " (a closed wall lists each corner once)" } else { "" },
                        (i + 1) % n,
                        b.0,
                        b.1
                    ),
                ));
            }
            let u = (dx / len, dy / len);
            out.push(Piece {
                a,
                u,
                len,
                out: (flip * u.1, -flip * u.0),
                joined: (w.closed || i > 0, w.closed || i + 1 < segs),
                stem: None,
            });
        }
        Ok(out)
    }

    /// The doors: per piece, the intervals along it that doors cut
    /// (start, end, door index), in the doors' order.
    fn door_cuts(&self, pieces: &[Piece]) -> Result<Vec<Vec<Cut>>, Invalid> {
        let mut cuts: Vec<Vec<Cut>> = vec![Vec::new(); pieces.len()];
        for (d, &(p, q)) in self.w.doors.iter().enumerate() {
            let door = format!("door {d} (({}, {}), ({}, {}))", p.0, p.1, q.0, q.1);
            if !(finite(p) && finite(q)) || p == q {
                return Err(self.bad("doors", format!("{door}: two distinct finite points")));
            }
            let Some(i) = pieces.iter().position(|s| on_piece(s, p) && on_piece(s, q)) else {
                let off = [p, q]
                    .into_iter()
                    .find(|x| !pieces.iter().any(|s| on_piece(s, *x)));
                let what = match off {
                    Some(x) => format!(
                        "ends on the wall's line, but ({}, {}) is not on it",
                        x.0, x.1
                    ),
                    None => "both ends on one straight piece of the wall".into(),
                };
                return Err(self.bad("doors", format!("{door}: {what}")));
            };
            let s = &pieces[i];
            let at =
                |x: (f64, f64)| ((x.0 - s.a.0) * s.u.0 + (x.1 - s.a.1) * s.u.1).clamp(0.0, s.len);
            let (s0, s1) = (at(p).min(at(q)), at(p).max(at(q)));
            cuts[i].push((s0, s1, d));
        }
        Ok(cuts)
    }

    /// The boxes of piece `s`: one per solid interval between the doors
    /// `c` that cut it, named after the piece's stem if it has one.
    fn piece_boxes(&self, s: &Piece, mut c: Vec<Cut>) -> Result<Vec<BodySpec>, Invalid> {
        c.sort_by(|a, b| a.0.total_cmp(&b.0));
        for pair in c.windows(2) {
            if pair[1].0 < pair[0].1 {
                return Err(self.bad(
                    "doors",
                    format!(
                        "doors that do not overlap, but doors {} and {} do",
                        pair[0].2, pair[1].2
                    ),
                ));
            }
        }
        // the solid intervals between the doors
        let mut from = (0.0, s.joined.0);
        let mut spans = Vec::new();
        for &(d0, d1, _) in &c {
            spans.push((from, (d0, false)));
            from = (d1, false);
        }
        spans.push((from, (s.len, s.joined.1)));
        let mut here: Vec<BodySpec> = spans
            .into_iter()
            .filter(|((s0, _), (s1, _))| s1 - s0 > 1e-12)
            .map(|(from, to)| self.span_box(s, from, to))
            .collect();
        if let Some(stem) = &s.stem {
            name_after(&mut here, stem);
        }
        Ok(here)
    }

    /// The (unnamed) box of piece `s` from `s0` to `s1` along it, each
    /// end extended over the corner when it meets another piece (`j0`,
    /// `j1`).
    fn span_box(&self, s: &Piece, (s0, j0): (f64, bool), (s1, j1): (f64, bool)) -> BodySpec {
        let (w, t) = (self.w, self.w.thickness);
        // how far a box reaches past a corner, and its centre off the line
        let (ext, off) = match w.placement {
            Placement::Outside => (t, t / 2.0),
            Placement::Centred => (t / 2.0, 0.0),
            Placement::Inside => (0.0, -t / 2.0),
        };
        let (e0, e1) = (if j0 { ext } else { 0.0 }, if j1 { ext } else { 0.0 });
        let len = s1 - s0 + e0 + e1;
        let mid = (s0 + s1) / 2.0 + (e1 - e0) / 2.0;
        let position = (
            tidy(s.a.0 + s.u.0 * mid + s.out.0 * off),
            tidy(s.a.1 + s.u.1 * mid + s.out.1 * off),
        );
        // an axis-aligned piece: an axis-aligned box (a vertical one
        // `width: thickness`); any other along the piece, at its angle
        let ((width, height), angle) = if s.u.1 == 0.0 {
            ((len, t), 0.0)
        } else if s.u.0 == 0.0 {
            ((t, len), 0.0)
        } else {
            ((len, t), s.u.1.atan2(s.u.0))
        };
        BodySpec {
            name: String::new(),
            kind: BodyKind::Fixed,
            shape: ShapeSpec::Cuboid {
                width: tidy(width),
                height: tidy(height),
            },
            mass: None,
            density: None,
            position,
            angle,
            linear_damping: 0.0,
            angular_damping: 0.0,
            friction: w.friction,
            restitution: w.restitution,
            lock_rotation: false,
            collide: true,
            fast_rotation: false,
            drag: None,
            inertia: None,
        }
    }

    /// Names the wall's boxes: by its `names`, else (a line's) after the
    /// wall, numbered when there are several.
    fn name_boxes(&self, boxes: &mut [BodySpec]) -> Result<(), Invalid> {
        let w = self.w;
        if !w.names.is_empty() {
            if w.names.len() != boxes.len() {
                return Err(self.bad(
                    "names",
                    format!(
                        "one name per box: the wall gives {} box(es), found {} name(s)",
                        boxes.len(),
                        w.names.len()
                    ),
                ));
            }
            for (b, n) in boxes.iter_mut().zip(&w.names) {
                b.name = n.clone();
            }
        } else if w.room.is_none() {
            name_after(boxes, &w.name);
        }
        Ok(())
    }
}

/// Names `boxes` after `stem`: `stem` for one box, else `stem1`, `stem2`, ...
fn name_after(boxes: &mut [BodySpec], stem: &str) {
    let one = boxes.len() == 1;
    for (m, b) in boxes.iter_mut().enumerate() {
        b.name = if one {
            stem.to_string()
        } else {
            format!("{stem}{}", m + 1)
        };
    }
}

fn on_piece(s: &Piece, x: (f64, f64)) -> bool {
    let (rx, ry) = (x.0 - s.a.0, x.1 - s.a.1);
    let along = rx * s.u.0 + ry * s.u.1;
    let across = (rx * s.u.1 - ry * s.u.0).abs();
    let tol = 1e-9 * (1.0 + x.0.abs().max(x.1.abs()));
    across <= tol && along >= -tol && along <= s.len + tol
}
