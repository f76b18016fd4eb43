//! MuJoCo's model format (MJCF): a physics scene written as an MJCF
//! model in the x-y plane ([`to_mjcf`]), and the planar subset of MJCF
//! read into a scene (`import`, feature `cli`). `docs/mjcf.md` says what
//! maps exactly and what does not.

mod export;
#[cfg(feature = "cli")]
pub mod import;

pub use export::to_mjcf;

/// The names the export gives, which the import reads back: the site of
/// a body's centre of mass (where its force actuators act), of the
/// effect's points, and the world's origin (the force actuators' frame).
pub(crate) const COM_SITE: &str = "_com";
/// The prefix of the effect's point sites (`e3d_effect0`, ...).
pub(crate) const EFFECT_SITE: &str = "e3d_effect";
/// The world frame's site, the reference of the force actuators.
pub(crate) const ORIGIN_SITE: &str = "e3d_origin";
/// The prefix of a body's drag numeric (`e3d_drag_<body>`: along, across,
/// turn), which the import reads back.
pub(crate) const DRAG: &str = "e3d_drag_";
/// The half-thickness along z given to boxes (MuJoCo is 3D).
pub(crate) const DEPTH: f64 = 0.1;
/// The radius of the capsules that stand for segments and polylines.
pub(crate) const THIN: f64 = 0.001;
