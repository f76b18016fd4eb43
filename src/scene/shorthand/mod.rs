//! Shorthands of the physics scene format: `chains` (a serial arm of box
//! links joined end to end) and `walls` (fixed boxes along a polyline or
//! around a rectangular room, with door gaps).
//!
//! The loader expands them into plain [`BodySpec`](super::physics::BodySpec)s and [`JointSpec`](super::physics::JointSpec)s
//! before any other check runs, so every check of bodies and joints
//! applies to generated items too: a loaded scene holds only plain bodies
//! and joints (its `chains` and `walls` are empty), which every consumer
//! reads as before, and [`Scene::to_ron`](super::SceneSpec::to_ron) writes
//! that expanded form (what `e3d scene check --expanded` prints). A scene
//! built in code with shorthands is expanded by
//! [`Scene::expand`](super::SceneSpec::expand).
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

mod expand;

pub(crate) use expand::{expand, Origins};

use super::physics::{MotorSpec, GROUND};
use serde::de::{self, IntoDeserializer};
use serde::{Deserialize, Serialize};
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
