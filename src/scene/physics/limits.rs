//! The bounds of the numbers of a physics scene: what Rapier, which
//! computes in `f32`, can hold, and what one step can carry. A value
//! outside is refused at load with the field, the value and the bound
//! (`docs/robustness.md`, "Numbers a physics scene may hold").

/// Coordinates, anchors, tracked point, grid corners and sizes, in
/// metres: `f32` still resolves 1 mm at this distance from the origin.
pub const MAX_LENGTH: f64 = 1e4;
/// Radius, width and height, in metres.
pub const MIN_SIZE: f64 = 1e-4;
/// A dynamic body's mass (given or from its density), kg.
pub const MIN_MASS: f64 = 1e-6;
/// A dynamic body's mass, kg.
pub const MAX_MASS: f64 = 1e9;
/// Densities, kg/m².
pub const MIN_DENSITY: f64 = 1e-6;
/// Densities, kg/m².
pub const MAX_DENSITY: f64 = 1e9;
/// Angles (start angles, joint limits, targets), radians.
pub const MAX_ANGLE: f64 = 1e3;
/// The magnitude of gravity, m/s².
pub const MAX_GRAVITY: f64 = 1e6;
/// `max_speed`, m/s: below Rapier's own cap of 400 m/s, which would
/// otherwise slow a body down silently before the check sees it.
pub const MAX_SPEED: f64 = 399.0;
/// The speed (m/s) or spin (rad/s) one impulse, force or torque may add
/// to a body in one step, computed on the body alone (its mass, its
/// inertia about its centre): far above any `max_speed`, so such a
/// command is reported as blown up, yet far below the 1.8e19 m/s whose
/// square overflows `f32` (Rapier then stops the body silently, or
/// panics in a motor constraint).
pub const MAX_STEP_CHANGE: f64 = 1e6;
/// Dampings and motor gains.
pub const MAX_COEFFICIENT: f64 = 1e9;
/// Friction coefficients.
pub const MAX_FRICTION: f64 = 1e3;
/// A non-zero number smaller in magnitude is 0 or subnormal in `f32`
/// (`f32::MIN_POSITIVE`, about 1.2e-38): refused rather than read as 0.
pub const MIN_MAGNITUDE: f64 = f32::MIN_POSITIVE as f64;
/// Bodies in a scene.
pub const MAX_BODIES: usize = 10_000;
/// Joints in a scene.
pub const MAX_JOINTS: usize = 10_000;
/// Points of one polyline.
pub const MAX_POINTS: usize = 100_000;

use super::super::Invalid;

/// `Err` unless `v` is finite, in `[lo, hi]` (magnitude `|v|` when
/// `signed`), and 0 or at least [`MIN_MAGNITUDE`] in magnitude.
pub(super) fn in_range(v: f64, lo: f64, hi: f64, signed: bool) -> bool {
    let m = if signed { v.abs() } else { v };
    v.is_finite() && m >= lo && m <= hi && (v == 0.0 || v.abs() >= MIN_MAGNITUDE)
}

/// A number's bounds, for messages: `"in [lo, hi] UNIT"`, `"|v| <= hi UNIT"`.
pub(super) fn bounds(lo: f64, hi: f64, signed: bool, unit: &str) -> String {
    let unit = format!("{}{unit}", if unit.is_empty() { "" } else { " " });
    let tiny = "0 or at least 1.2e-38 in magnitude (f32)";
    match (signed, lo) {
        (true, _) => format!("|value| <= {}{unit}, {tiny}", show(hi)),
        (false, 0.0) => format!("in [0, {}]{unit}, {tiny}", show(hi)),
        (false, l) => format!("in [{}, {}]{unit}", show(l), show(hi)),
    }
}

pub(crate) use crate::text::show_number as show;

/// The bounds of a number: `[lo, hi]`, of its magnitude when `signed`,
/// in `unit` (for messages).
#[derive(Clone, Copy)]
pub(super) struct Bound {
    lo: f64,
    hi: f64,
    signed: bool,
    unit: &'static str,
}

impl Bound {
    /// `|v| <= hi` in `unit`.
    pub(super) const fn magnitude(hi: f64, unit: &'static str) -> Bound {
        Bound {
            lo: 0.0,
            hi,
            signed: true,
            unit,
        }
    }

    /// `v` in `[lo, hi]`, in `unit`.
    pub(super) const fn range(lo: f64, hi: f64, unit: &'static str) -> Bound {
        Bound {
            lo,
            hi,
            signed: false,
            unit,
        }
    }
}

/// Coordinates in metres: `|v| <=` [`MAX_LENGTH`].
pub(super) const COORDINATES: Bound = Bound::magnitude(MAX_LENGTH, "m");

/// The item the errors of a check are about: placed at `anchor` (`None`:
/// at the field), prefixed with `who` (`body `b``; "" for none).
#[derive(Clone, Copy)]
pub(super) struct On<'a> {
    pub anchor: Option<&'a str>,
    pub who: &'a str,
}

impl<'a> On<'a> {
    /// The world's own fields: no anchor, no prefix.
    pub(super) const WORLD: On<'static> = On::new(None, "");

    pub(super) const fn new(anchor: Option<&'a str>, who: &'a str) -> On<'a> {
        On { anchor, who }
    }

    /// The failure at `field`: `who: EXPECTED`.
    pub(super) fn bad(&self, field: &str, expected: impl std::fmt::Display) -> Invalid {
        let text = match self.who {
            "" => expected.to_string(),
            who => format!("{who}: {expected}"),
        };
        Invalid::at(field, self.anchor, &text)
    }

    /// The check of one number: `who: WHAT BOUNDS, found V`.
    pub(super) fn number(&self, field: &str, what: &str, v: f64, b: Bound) -> Result<(), Invalid> {
        if in_range(v, b.lo, b.hi, b.signed) {
            return Ok(());
        }
        let bounds = bounds(b.lo, b.hi, b.signed, b.unit);
        Err(self.bad(field, format!("{what} {bounds}, found {}", show(v))))
    }
}

/// The largest offset (m) start noise may draw for a position.
pub const MAX_POSITION_NOISE: f64 = 100.0;
/// The largest offset (rad) start noise may draw for an angle.
pub const MAX_ANGLE_NOISE: f64 = std::f64::consts::PI;
