//! Shorthands of the physics scene format: `chains` (a serial arm of box
//! links joined end to end) and `walls` (fixed boxes along a polyline or
//! around a rectangular room, with door gaps).
//!
//! The loader expands them into plain [`BodySpec`]s and [`JointSpec`]s
//! before any other check runs, so every check of bodies and joints
//! applies to generated items too: a loaded scene holds only plain bodies
//! and joints (its `chains` and `walls` are empty), which every consumer
//! reads as before, and [`Scene::to_ron`](super::Scene::to_ron) writes
//! that expanded form (what `e3d scene check --expanded` prints). A scene
//! built in code with shorthands is expanded by
//! [`Scene::expand`](super::Scene::expand).
//!
//! The expanded `bodies` are, in this order: every wall's boxes (walls in
//! their order, each wall's boxes in the order described at [`WallSpec`]),
//! every chain's links (chains in order, link 1 first), then the bodies
//! written in `bodies`. The expanded `joints` are every chain's joints
//! (joint 1 first), then the joints written in `joints`.
//!
//! Generated lengths and coordinates are rounded to 1e-12 m, so that
//! `3.0 + 0.05` is the `3.05` one would write by hand (angles are copied
//! as written).

use super::physics::{
    limits::{MAX_BODIES, MAX_POINTS},
    BodyKind, BodySpec, JointSpec, MotorSpec, PhysicsSpec, ShapeSpec, GROUND,
};
use super::Invalid;
use serde::de::{self, IntoDeserializer};
use serde::{Deserialize, Serialize};
use std::collections::HashMap;
use std::marker::PhantomData;

/// One value for every link (or joint) of a chain, or a list of one value
/// per link: `damping: 0.5` or `damping: [0.5, 0.3, 0.15]`.
#[derive(Debug, Clone, PartialEq)]
pub enum Each<T> {
    /// The same value for all.
    All(T),
    /// One value each, in order (link 1 first).
    List(Vec<T>),
}

impl<T: Clone> Each<T> {
    /// The value of item `i` (0-based); a list too short gives its last.
    ///
    /// # Panics
    /// On an empty list (the loader refuses a list that is not one value
    /// per item).
    pub fn get(&self, i: usize) -> T {
        match self {
            Each::All(v) => v.clone(),
            Each::List(l) => l[i.min(l.len().saturating_sub(1))].clone(),
        }
    }

    fn len(&self) -> Option<usize> {
        match self {
            Each::All(_) => None,
            Each::List(l) => Some(l.len()),
        }
    }
}

impl<T: Serialize> Serialize for Each<T> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Each::All(v) => v.serialize(s),
            Each::List(l) => l.serialize(s),
        }
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Each<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<T>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>> de::Visitor<'de> for V<T> {
            type Value = Each<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("one value for all, or a list `[...]` of one value each")
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, mut a: A) -> Result<Self::Value, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = a.next_element()? {
                    v.push(x);
                }
                Ok(Each::List(v))
            }
            fn visit_map<A: de::MapAccess<'de>>(self, a: A) -> Result<Self::Value, A::Error> {
                T::deserialize(de::value::MapAccessDeserializer::new(a)).map(Each::All)
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<Self::Value, E> {
                T::deserialize(x.into_deserializer()).map(Each::All)
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<Self::Value, E> {
                T::deserialize(x.into_deserializer()).map(Each::All)
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<Self::Value, E> {
                T::deserialize(x.into_deserializer()).map(Each::All)
            }
            fn visit_bool<E: de::Error>(self, x: bool) -> Result<Self::Value, E> {
                T::deserialize(x.into_deserializer()).map(Each::All)
            }
        }
        d.deserialize_any(V(PhantomData))
    }
}

/// A serial chain of `links` box (or capsule) links joined end to end by
/// revolute joints: link 1 hangs on `parent` (default `ground`) at `base`,
/// link k on the far end of link k-1. At rest the chain is straight,
/// pointing along `angle`.
///
/// Link k (1-based) is a dynamic `Cuboid(width: length_k, height:
/// width_k)` (with `shape: Capsule`, a `Capsule(a: (-length_k / 2, 0), b:
/// (length_k / 2, 0), radius: width_k / 2)`: rounded ends centred on the
/// hinges) named `{prefix}{k}` (or `names[k-1]`), at angle `angle`,
/// centred `length_1 + ... + length_(k-1) + length_k / 2` metres from
/// `base` along `angle`. Joint k is named `{joint_prefix}{k}` (or
/// `joint_names[k-1]`); its parent is `parent` (joint 1, anchored at
/// `base`: world coordinates for `ground`, else converted to the parent's
/// frame) or link k-1 (anchored at `(length_(k-1) / 2, 0)`), its child
/// link k, anchored at `(-length_k / 2, 0)`.
///
/// A `free` chain has no joint 1: link 1 is a free body (a free-floating
/// base, its near end at `base`), and the chain has `links - 1` joints,
/// joint k joining link k + 1 to link k (named `{joint_prefix}{k}`, `k`
/// from 1).
///
/// ```ron
/// chains: [(links: 7, length: 0.25, width: 0.04, mass: 0.1, limits: (-2.5, 2.5),
///           damping: [0.5, 0.3, 0.15, 0.08, 0.04, 0.02, 0.01], friction: 1.0)],
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainSpec {
    /// The number of links (and joints), at least 1.
    pub links: usize,
    /// Link k is named `{prefix}{k}` (default `link`: `link1`, `link2`, ...).
    #[serde(default = "link_prefix")]
    pub prefix: String,
    /// Joint k is named `{joint_prefix}{k}` (default `j`: `j1`, `j2`, ...).
    #[serde(default = "joint_prefix")]
    pub joint_prefix: String,
    /// The links' names, one per link, instead of `prefix` (default none).
    #[serde(default)]
    pub names: Vec<String>,
    /// The joints' names, one per joint, instead of `joint_prefix`.
    #[serde(default)]
    pub joint_names: Vec<String>,
    /// What link 1 hangs on: `ground` (default) or a body (a wall's box, an
    /// earlier chain's link, or one of `bodies`).
    #[serde(default = "ground")]
    pub parent: String,
    /// The hinge of joint 1, in world coordinates, metres (default (0, 0)).
    #[serde(default)]
    pub base: (f64, f64),
    /// The direction of the chain at rest, radians counter-clockwise from
    /// +x (default 0); every link's start angle.
    #[serde(default)]
    pub angle: f64,
    /// Each link's length along the chain, metres: one for all, or a list.
    pub length: Each<f64>,
    /// Each link's width across the chain, metres: one for all, or a list.
    pub width: Each<f64>,
    /// Each link's mass, kg (default: from `density`, else density 1).
    #[serde(default)]
    pub mass: Option<Each<f64>>,
    /// Each link's density, kg/m² (give `mass` or `density`).
    #[serde(default)]
    pub density: Option<Each<f64>>,
    /// Every joint's limits `(min, max)`, radians (default none).
    #[serde(default)]
    pub limits: Option<(f64, f64)>,
    /// Each joint's viscous damping, N·m·s/rad (default 0).
    #[serde(default = "no_damping")]
    pub damping: Each<f64>,
    /// Each joint's position motor `(stiffness: ..., damping: ...)`
    /// (default none).
    #[serde(default)]
    pub motor: Option<Each<MotorSpec>>,
    /// Whether neighbouring links collide (every joint's `contacts`,
    /// default false).
    #[serde(default)]
    pub contacts: bool,
    /// Every link's linear damping, 1/s (default 0).
    #[serde(default)]
    pub linear_damping: f64,
    /// Every link's angular damping, 1/s (default 0).
    #[serde(default)]
    pub angular_damping: f64,
    /// Every link's friction (default 0.5).
    #[serde(default = "half")]
    pub friction: f64,
    /// Every link's restitution (default 0).
    #[serde(default)]
    pub restitution: f64,
    /// The links' shape: `Cuboid` (default) or `Capsule`.
    #[serde(default, skip_serializing_if = "LinkShape::is_cuboid")]
    pub shape: LinkShape,
    /// A free-floating chain (default false): link 1 is not joined to
    /// anything (no joint 1, no `parent`), the chain has `links - 1`
    /// joints.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub free: bool,
}

/// The shape of a chain's links.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum LinkShape {
    /// A rectangle `length` x `width` (the default).
    #[default]
    Cuboid,
    /// A capsule: a segment of `length` between the hinges, with radius
    /// `width / 2` (rounded ends centred on the hinges).
    Capsule,
}

impl LinkShape {
    fn is_cuboid(&self) -> bool {
        *self == LinkShape::Cuboid
    }
}

impl ChainSpec {
    /// A chain of `links` links of `length` x `width` metres, every other
    /// field at its default (from `ground` at the origin along +x, named
    /// `link1`..., joints `j1`...).
    pub fn new(links: usize, length: f64, width: f64) -> ChainSpec {
        ChainSpec {
            links,
            prefix: link_prefix(),
            joint_prefix: joint_prefix(),
            names: Vec::new(),
            joint_names: Vec::new(),
            parent: ground(),
            base: (0.0, 0.0),
            angle: 0.0,
            length: Each::All(length),
            width: Each::All(width),
            mass: None,
            density: None,
            limits: None,
            damping: no_damping(),
            motor: None,
            contacts: false,
            linear_damping: 0.0,
            angular_damping: 0.0,
            friction: half(),
            restitution: 0.0,
            shape: LinkShape::Cuboid,
            free: false,
        }
    }
}

/// Where a wall's boxes lie with respect to its line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum Placement {
    /// Centred on the line (the default): each box reaches `thickness / 2`
    /// on either side, and `thickness / 2` past every corner.
    #[default]
    Centred,
    /// Outside the line: away from the enclosed area of a closed wall or a
    /// room, to the right of the direction of travel of an open one; each
    /// box reaches `thickness` past every corner, which closes the
    /// corners.
    Outside,
    /// Inside the line: the other side; boxes end at the corners.
    Inside,
}

/// Fixed wall boxes along a polyline (`points`, `closed` or not) or around
/// a rectangular `room: (min, max)`, with door gaps.
///
/// Each straight piece of the line gives one fixed `Cuboid` of
/// `thickness`: an axis-aligned piece gives an axis-aligned box at angle 0
/// (a vertical one `width: thickness`, its length as `height`), any other
/// `width: length, height: thickness` at the piece's angle. A door
/// `((x1, y1), (x2, y2))`, two points on one piece, cuts that piece in two.
/// The boxes follow the pieces in order: the polyline's (with the closing
/// piece last), or a room's sides south, north, west, east (each from its
/// lower-left end). Default names: `{name}` for a wall of one box, else
/// `{name}1`, `{name}2`, ...; a room's sides `{name}_south`,
/// `{name}_north`, `{name}_west`, `{name}_east` (`{name}_south1`, ... when
/// a door cuts it); `names` gives every box's name instead.
///
/// ```ron
/// walls: [
///     (name: "wall", room: ((0.0, 0.0), (6.0, 3.0)), thickness: 0.1, placement: Outside),
///     (name: "inner", points: [(3.0, 0.0), (3.0, 3.0)], thickness: 0.1,
///      doors: [((3.0, 1.0), (3.0, 2.0))], names: ["inner_low", "inner_high"]),
/// ],
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WallSpec {
    /// The wall's name: in messages, and the stem of its boxes' names.
    pub name: String,
    /// The line, at least two points (give `points` or `room`).
    #[serde(default)]
    pub points: Vec<(f64, f64)>,
    /// Whether the line closes back from its last point to its first
    /// (default false); each corner is listed once.
    #[serde(default)]
    pub closed: bool,
    /// A rectangle `((min_x, min_y), (max_x, max_y))`: a closed wall of
    /// four sides (give `points` or `room`).
    #[serde(default)]
    pub room: Option<((f64, f64), (f64, f64))>,
    /// The boxes' thickness across the line, metres.
    pub thickness: f64,
    /// Centred (default), Outside or Inside.
    #[serde(default)]
    pub placement: Placement,
    /// The boxes' friction (default 0.5).
    #[serde(default = "half")]
    pub friction: f64,
    /// The boxes' restitution (default 0).
    #[serde(default)]
    pub restitution: f64,
    /// Door gaps, each two points on one straight piece of the line
    /// (default none).
    #[serde(default)]
    pub doors: Vec<((f64, f64), (f64, f64))>,
    /// The boxes' names, one per box, in order (default: see above).
    #[serde(default)]
    pub names: Vec<String>,
}

fn link_prefix() -> String {
    "link".into()
}
fn joint_prefix() -> String {
    "j".into()
}
fn ground() -> String {
    GROUND.into()
}
fn no_damping() -> Each<f64> {
    Each::All(0.0)
}
fn half() -> f64 {
    0.5
}

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

fn bad(list: &'static str, k: usize, field: &str, msg: String) -> Invalid {
    Invalid {
        within: Some((list, k)),
        ..Invalid::at(field, None, &msg)
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
        for b in &links {
            origins.entry(b.name.clone()).or_insert(("chains", k));
        }
        for j in &js {
            origins.entry(j.name.clone()).or_insert(("chains", k));
        }
        bodies.extend(links);
        joints.extend(js);
    }
    bodies.append(&mut spec.bodies);
    joints.append(&mut spec.joints);
    spec.bodies = bodies;
    spec.joints = joints;
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
    let bad = |field: &str, msg: String| bad("chains", k, field, format!("chains[{k}]: {msg}"));
    let n = c.links;
    if n == 0 || n > MAX_BODIES {
        return Err(bad(
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
        if let Some(m) = len {
            if m != want {
                let of = if per_joint && c.free {
                    format!("{nj} joints (a free chain of {n} links)")
                } else if per_joint {
                    format!("{n} joints")
                } else {
                    format!("{n} links")
                };
                return Err(bad(
                    field,
                    format!(
                        "one value for all {of} or a list of {want} {what} (one per {}), found a list of {m}",
                        if per_joint { "joint" } else { "link" }
                    ),
                ));
            }
        }
    }
    if c.free && c.parent != GROUND {
        return Err(bad(
            "parent",
            format!(
                "no `parent` for a free chain (`free: true`: link 1 is joined to nothing), found `{}`",
                c.parent
            ),
        ));
    }
    for (field, each) in [("length", &c.length), ("width", &c.width)] {
        for i in 0..n {
            let v = each.get(i);
            if !(v.is_finite() && v > 0.0) {
                return Err(bad(
                    field,
                    format!("a {field} > 0 m for every link, found {v} (link {})", i + 1),
                ));
            }
        }
    }
    if !finite(c.base) || !c.angle.is_finite() {
        return Err(bad(
            if finite(c.base) { "angle" } else { "base" },
            "a finite base and angle".into(),
        ));
    }
    let anchor0 = if c.parent == GROUND {
        (tidy(c.base.0), tidy(c.base.1))
    } else {
        let Some((p, a)) = pose(&c.parent) else {
            return Err(bad(
                "parent",
                format!(
                    "`ground` or a body written before the chain (a wall's box, an earlier chain's link, or one of `bodies`), found `{}`",
                    c.parent
                ),
            ));
        };
        let (s, co) = a.sin_cos();
        let (dx, dy) = (c.base.0 - p.0, c.base.1 - p.1);
        (tidy(co * dx + s * dy), tidy(-s * dx + co * dy))
    };
    let link_name = |i: usize| match c.names.get(i) {
        Some(s) => s.clone(),
        None => format!("{}{}", c.prefix, i + 1),
    };
    let joint_name = |i: usize| match c.joint_names.get(i) {
        Some(s) => s.clone(),
        None => format!("{}{}", c.joint_prefix, i + 1),
    };
    let (s, co) = c.angle.sin_cos();
    let (mut bodies, mut joints) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let mut along = 0.0;
    for i in 0..n {
        let l = c.length.get(i);
        let centre = along + l / 2.0;
        along += l;
        bodies.push(BodySpec {
            name: link_name(i),
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
        });
        if c.free && i == 0 {
            continue;
        }
        // joint j (0-based) of a free chain joins link j + 2 to link j + 1
        let j = i - usize::from(c.free);
        joints.push(JointSpec {
            name: joint_name(j),
            parent: if i == 0 {
                c.parent.clone()
            } else {
                link_name(i - 1)
            },
            child: link_name(i),
            parent_anchor: if i == 0 {
                anchor0
            } else {
                (tidy(c.length.get(i - 1) / 2.0), 0.0)
            },
            child_anchor: (tidy(-l / 2.0), 0.0),
            limits: c.limits,
            damping: c.damping.get(j),
            motor: c.motor.as_ref().map(|m| m.get(j)),
            kind: Default::default(),
            contacts: c.contacts,
        });
    }
    Ok((bodies, joints))
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
    let who = format!("wall `{}`", w.name);
    let bad = |field: &str, msg: String| bad("walls", k, field, format!("{who}: {msg}"));
    if w.name.trim().is_empty() {
        return Err(bad("name", "a non-empty name".into()));
    }
    let t = w.thickness;
    if !(t.is_finite() && t > 0.0) {
        return Err(bad("thickness", format!("a thickness > 0 m, found {t}")));
    }
    let pieces: Vec<Piece> = match (&w.room, w.points.is_empty()) {
        (Some(_), false) => return Err(bad("room", "`points` or `room`, not both".into())),
        (None, true) => {
            return Err(bad(
                "points",
                "a line: `points: [(x, y), ...]` or `room: ((min_x, min_y), (max_x, max_y))`"
                    .into(),
            ))
        }
        (Some((lo, hi)), true) => {
            if !(finite(*lo) && finite(*hi) && lo.0 < hi.0 && lo.1 < hi.1) {
                return Err(bad(
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
                stem: Some(format!("{}_{stem}", w.name)),
            };
            vec![
                side(*lo, (1.0, 0.0), dx, (0.0, -1.0), "south"),
                side((lo.0, hi.1), (1.0, 0.0), dx, (0.0, 1.0), "north"),
                side(*lo, (0.0, 1.0), dy, (-1.0, 0.0), "west"),
                side((hi.0, lo.1), (0.0, 1.0), dy, (1.0, 0.0), "east"),
            ]
        }
        (None, false) => {
            let p = &w.points;
            if p.len() > MAX_POINTS {
                return Err(bad(
                    "points",
                    format!("at most {MAX_POINTS} points, found {}", p.len()),
                ));
            }
            if p.len() < 2 + usize::from(w.closed) {
                return Err(bad(
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
                return Err(bad(
                    "points",
                    format!("finite points, found ({}, {})", q.0, q.1),
                ));
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
                    return Err(bad(
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
            out
        }
    };
    // the doors: an interval along one piece each
    let mut cuts: Vec<Vec<(f64, f64, usize)>> = vec![Vec::new(); pieces.len()];
    for (d, &(p, q)) in w.doors.iter().enumerate() {
        let door = format!("door {d} (({}, {}), ({}, {}))", p.0, p.1, q.0, q.1);
        if !(finite(p) && finite(q)) || p == q {
            return Err(bad("doors", format!("{door}: two distinct finite points")));
        }
        let Some(i) = pieces.iter().position(|s| on_piece(s, p) && on_piece(s, q)) else {
            return Err(
                match [p, q]
                    .into_iter()
                    .find(|x| !pieces.iter().any(|s| on_piece(s, *x)))
                {
                    Some(x) => bad(
                        "doors",
                        format!(
                            "{door}: ends on the wall's line, but ({}, {}) is not on it",
                            x.0, x.1
                        ),
                    ),
                    None => bad(
                        "doors",
                        format!("{door}: both ends on one straight piece of the wall"),
                    ),
                },
            );
        };
        let s = &pieces[i];
        let at = |x: (f64, f64)| ((x.0 - s.a.0) * s.u.0 + (x.1 - s.a.1) * s.u.1).clamp(0.0, s.len);
        let (s0, s1) = (at(p).min(at(q)), at(p).max(at(q)));
        cuts[i].push((s0, s1, d));
    }
    let mut boxes = Vec::new();
    for (i, s) in pieces.iter().enumerate() {
        let mut c = cuts[i].clone();
        c.sort_by(|a, b| a.0.total_cmp(&b.0));
        for pair in c.windows(2) {
            if pair[1].0 < pair[0].1 {
                return Err(bad(
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
        let ext = match w.placement {
            Placement::Outside => t,
            Placement::Centred => t / 2.0,
            Placement::Inside => 0.0,
        };
        let off = match w.placement {
            Placement::Outside => t / 2.0,
            Placement::Centred => 0.0,
            Placement::Inside => -t / 2.0,
        };
        let mut here = Vec::new();
        for ((s0, j0), (s1, j1)) in spans {
            if s1 - s0 <= 1e-12 {
                continue;
            }
            let (e0, e1) = (if j0 { ext } else { 0.0 }, if j1 { ext } else { 0.0 });
            let len = s1 - s0 + e0 + e1;
            let mid = (s0 + s1) / 2.0 + (e1 - e0) / 2.0;
            let position = (
                tidy(s.a.0 + s.u.0 * mid + s.out.0 * off),
                tidy(s.a.1 + s.u.1 * mid + s.out.1 * off),
            );
            let (shape, angle) = if s.u.1 == 0.0 {
                (
                    ShapeSpec::Cuboid {
                        width: tidy(len),
                        height: tidy(t),
                    },
                    0.0,
                )
            } else if s.u.0 == 0.0 {
                (
                    ShapeSpec::Cuboid {
                        width: tidy(t),
                        height: tidy(len),
                    },
                    0.0,
                )
            } else {
                (
                    ShapeSpec::Cuboid {
                        width: tidy(len),
                        height: tidy(t),
                    },
                    s.u.1.atan2(s.u.0),
                )
            };
            here.push(BodySpec {
                name: String::new(),
                kind: BodyKind::Fixed,
                shape,
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
            });
        }
        if let Some(stem) = &s.stem {
            let one = here.len() == 1;
            for (m, b) in here.iter_mut().enumerate() {
                b.name = if one {
                    stem.clone()
                } else {
                    format!("{stem}{}", m + 1)
                };
            }
        }
        boxes.extend(here);
    }
    if !w.names.is_empty() {
        if w.names.len() != boxes.len() {
            return Err(bad(
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
        let one = boxes.len() == 1;
        for (m, b) in boxes.iter_mut().enumerate() {
            b.name = if one {
                w.name.clone()
            } else {
                format!("{}{}", w.name, m + 1)
            };
        }
    }
    Ok(boxes)
}

fn on_piece(s: &Piece, x: (f64, f64)) -> bool {
    let (rx, ry) = (x.0 - s.a.0, x.1 - s.a.1);
    let along = rx * s.u.0 + ry * s.u.1;
    let across = (rx * s.u.1 - ry * s.u.0).abs();
    let tol = 1e-9 * (1.0 + x.0.abs().max(x.1.abs()));
    across <= tol && along >= -tol && along <= s.len + tol
}
