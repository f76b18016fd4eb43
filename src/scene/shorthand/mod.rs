//! Shorthands of the physics scene format: `chains` (a serial arm of box
//! links joined end to end) and `walls` (fixed boxes along a polyline or
//! around a room, with door gaps), expanded at load into plain bodies and
//! joints, in the order and with the names of `docs/scenes.md`
//! ("Shorthands: chains and walls"); generated lengths and coordinates are
//! rounded to 1e-12 m.

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

/// The visits of one value for all: a number or a boolean.
macro_rules! scalars {
    ($($visit:ident: $t:ty),*) => {$(
        fn $visit<E: de::Error>(self, x: $t) -> Result<Self::Value, E> {
            T::deserialize(x.into_deserializer()).map(Each::All)
        }
    )*};
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Each<T> {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct V<T>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>> de::Visitor<'de> for V<T> {
            type Value = Each<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("one value for all, or a list `[...]` of one value each")
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, a: A) -> Result<Self::Value, A::Error> {
                Vec::deserialize(de::value::SeqAccessDeserializer::new(a)).map(Each::List)
            }
            fn visit_map<A: de::MapAccess<'de>>(self, a: A) -> Result<Self::Value, A::Error> {
                T::deserialize(de::value::MapAccessDeserializer::new(a)).map(Each::All)
            }
            scalars!(visit_f64: f64, visit_i64: i64, visit_u64: u64, visit_bool: bool);
        }
        d.deserialize_any(V(PhantomData))
    }
}

/// A serial chain of `links` box (or capsule) links joined end to end by
/// revolute joints: link 1 hangs on `parent` at `base`, link k on the far
/// end of link k-1, straight along `angle` at rest. Link k is named
/// `{prefix}{k}`, joint k `{joint_prefix}{k}`; a `free` chain has no
/// joint 1 (docs/scenes.md, "Chains (shorthand)").
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
    /// Every link's drag (default none; see
    /// [`DragSpec`](crate::scene::physics::DragSpec)).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub drag: Option<crate::scene::physics::DragSpec>,
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
        let defaults = "(links: 0, length: 0.0, width: 0.0)";
        ChainSpec {
            links,
            length: Each::All(length),
            width: Each::All(width),
            ..ron::from_str(defaults).expect("the other fields have defaults")
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
/// a rectangular `room: (min, max)`, with door gaps: one `Cuboid` of
/// `thickness` per straight piece (cut in two by a door), named `{name}`,
/// `{name}1`, ... or a room's `{name}_south`, ... (docs/scenes.md, "Walls
/// (shorthand)").
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

defaults! {
    link_prefix: String = "link".into();
    joint_prefix: String = "j".into();
    ground: String = GROUND.into();
    no_damping: Each<f64> = Each::All(0.0);
    half: f64 = 0.5;
}
