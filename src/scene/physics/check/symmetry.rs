//! The check of a declared symmetry: the reflection leaves the world and
//! its command unchanged.

use super::super::{PhysicsSpec, ShapeSpec, GROUND};
use super::quoted;
use crate::scene::symmetry::Symmetry;
use crate::scene::{Invalid, SceneSpec};

/// How far an angle may be from the mirror line and still lie on it.
const ANGLE_TOLERANCE: f64 = 1e-9;

impl Symmetry {
    /// Checks that the reflection leaves `spec` (and its command) unchanged,
    /// each body being its own mirror image.
    pub(crate) fn validate(self, spec: &PhysicsSpec, scene: &SceneSpec) -> Result<(), Invalid> {
        let k = self.axis();
        let coord = ["x", "y"][k];
        let across = |p: (f64, f64)| [p.0, p.1][k];
        // only a point's world cell reflects as a point: a joint's
        // coordinate, an angle, a point in another body's frame or a
        // product would need their own reflections
        let Some((_, point, g)) = spec.effect.world_point() else {
            return self.fail(
                "symmetry",
                None,
                "no symmetry with this effect: a symmetry reflects the effect's point in the world, and this effect is not one point's world cell (a joint's coordinate, an angle, a point in another body's frame or a product); remove `symmetry`".to_string(),
            );
        };
        let gravity = spec.gravity;
        if across(gravity) != 0.0 {
            let what = format!("gravity along the mirror line ({coord} = 0), found {gravity:?}");
            return self.fail("gravity", None, what);
        }
        // a body's local x axis must lie along the mirror line, so that the
        // reflection acts on its frame as local y -> -y
        let along = |a: f64| match self {
            Symmetry::FlipY => a.sin().abs() < ANGLE_TOLERANCE,
            Symmetry::FlipX => a.cos().abs() < ANGLE_TOLERANCE,
        };
        let on_line = match self {
            Symmetry::FlipY => "0 or pi",
            Symmetry::FlipX => "pi/2 or -pi/2",
        };
        for b in &spec.bodies {
            let (name, p) = (&b.name, b.position);
            let (field, what) = if across(p) != 0.0 {
                (
                    "position",
                    format!(
                        "every body its own mirror image, on the mirror line ({coord} = 0), but `{name}` is at {p:?}"
                    ),
                )
            } else if !along(b.angle) {
                (
                    "angle",
                    format!(
                        "every body along the mirror line (angle {on_line}), but `{name}` has angle {}",
                        b.angle
                    ),
                )
            } else if !symmetric(&b.shape) {
                (
                    "shape",
                    format!(
                        "shapes symmetric about the body's local x axis (local y = 0 for every point), but `{name}`'s is not"
                    ),
                )
            } else {
                continue;
            };
            return self.fail(field, Some(&quoted(name)), what);
        }
        for j in &spec.joints {
            let (name, pa, ca) = (&j.name, j.parent_anchor, j.child_anchor);
            // an anchor on `ground` is in world coordinates, others local
            let parent_off = if j.parent == GROUND { across(pa) } else { pa.1 };
            let (field, what) = if parent_off != 0.0 || ca.1 != 0.0 {
                (
                    "parent_anchor",
                    format!(
                        "hinges on the mirror line (local y = 0; {coord} = 0 on `ground`), but joint `{name}` has {pa:?} and {ca:?}"
                    ),
                )
            } else if let Some((lo, hi)) = j.limits.filter(|(lo, hi)| *lo != -hi) {
                (
                    "limits",
                    format!(
                        "limits symmetric about 0, (-m, m), but joint `{name}` has ({lo}, {hi})"
                    ),
                )
            } else {
                continue;
            };
            return self.fail(field, Some(&quoted(name)), what);
        }
        if point.1 != 0.0 {
            let what =
                format!("a tracked point on its body's local x axis (y = 0), found {point:?}");
            return self.fail("point", None, what);
        }
        if g.min[k] != -g.max[k] {
            let (lo, hi) = (g.min, g.max);
            return self.fail(
                "grid",
                None,
                format!(
                    "an effect grid symmetric about the mirror line (min {coord} = -max {coord}), found min {lo:?}, max {hi:?}"
                ),
            );
        }
        self.symbol_maps(scene).map(drop)
    }

    /// The error at `field` (and `anchor` in it): what the symmetry
    /// needs.
    fn fail<T>(self, field: &str, anchor: Option<&str>, what: String) -> Result<T, Invalid> {
        let what = format!("symmetry {self:?}: {what}");
        Err(Invalid::at(field, anchor, &what))
    }
}

/// Whether a shape is symmetric about its body's local x axis.
fn symmetric(shape: &ShapeSpec) -> bool {
    match shape {
        ShapeSpec::Ball { .. } | ShapeSpec::Cuboid { .. } => true,
        ShapeSpec::Capsule { a, b, .. } | ShapeSpec::Segment { a, b } => a.1 == 0.0 && b.1 == 0.0,
        ShapeSpec::Polyline { points } => points.iter().all(|p| p.1 == 0.0),
    }
}
