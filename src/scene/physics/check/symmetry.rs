//! The check of a declared symmetry: the reflection leaves the world and
//! its command unchanged.

use super::super::{PhysicsSpec, ShapeSpec, GROUND};
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
        if across(spec.gravity) != 0.0 {
            return self.fail(
                "gravity",
                None,
                format!(
                    "gravity along the mirror line ({coord} = 0), found {:?}",
                    spec.gravity
                ),
            );
        }
        self.check_bodies(spec)?;
        self.check_joints(spec)?;
        if point.1 != 0.0 {
            return self.fail(
                "point",
                None,
                format!(
                    "a tracked point on its body's local x axis (y = 0), found {:?}",
                    point
                ),
            );
        }
        if g.min[k] != -g.max[k] {
            return self.fail(
                "grid",
                None,
                format!(
                    "an effect grid symmetric about the mirror line (min {coord} = -max {coord}), found min {:?}, max {:?}",
                    g.min, g.max
                ),
            );
        }
        self.symbol_maps(scene).map(drop)
    }

    /// The error at `field` (and `anchor` in it): what the symmetry
    /// needs.
    fn fail<T>(self, field: &str, anchor: Option<&str>, what: String) -> Result<T, Invalid> {
        Err(Invalid::at(
            field,
            anchor,
            &format!("symmetry {self:?}: {what}"),
        ))
    }

    /// Every body its own mirror image: on the mirror line, along it, its
    /// shape symmetric about its local x axis.
    fn check_bodies(self, spec: &PhysicsSpec) -> Result<(), Invalid> {
        let k = self.axis();
        let coord = ["x", "y"][k];
        let across = |p: (f64, f64)| [p.0, p.1][k];
        // a body's local x axis must lie along the mirror line, so that the
        // reflection acts on its frame as local y -> -y
        let along = |angle: f64| match self {
            Symmetry::FlipY => angle.sin().abs() < ANGLE_TOLERANCE,
            Symmetry::FlipX => angle.cos().abs() < ANGLE_TOLERANCE,
        };
        let on_line = match self {
            Symmetry::FlipY => "0 or pi",
            Symmetry::FlipX => "pi/2 or -pi/2",
        };
        for b in &spec.bodies {
            let at = format!("\"{}\"", b.name);
            if across(b.position) != 0.0 {
                return self.fail(
                    "position",
                    Some(&at),
                    format!(
                        "every body its own mirror image, on the mirror line ({coord} = 0), but `{}` is at {:?}",
                        b.name, b.position
                    ),
                );
            }
            if !along(b.angle) {
                return self.fail(
                    "angle",
                    Some(&at),
                    format!(
                        "every body along the mirror line (angle {on_line}), but `{}` has angle {}",
                        b.name, b.angle
                    ),
                );
            }
            let symmetric = match &b.shape {
                ShapeSpec::Ball { .. } | ShapeSpec::Cuboid { .. } => true,
                ShapeSpec::Capsule { a, b, .. } | ShapeSpec::Segment { a, b } => {
                    a.1 == 0.0 && b.1 == 0.0
                }
                ShapeSpec::Polyline { points } => points.iter().all(|p| p.1 == 0.0),
            };
            if !symmetric {
                return self.fail(
                    "shape",
                    Some(&at),
                    format!(
                        "shapes symmetric about the body's local x axis (local y = 0 for every point), but `{}`'s is not",
                        b.name
                    ),
                );
            }
        }
        Ok(())
    }

    /// Every joint's hinge on the mirror line, its limits symmetric about
    /// 0.
    fn check_joints(self, spec: &PhysicsSpec) -> Result<(), Invalid> {
        let coord = ["x", "y"][self.axis()];
        let across = |p: (f64, f64)| [p.0, p.1][self.axis()];
        for j in &spec.joints {
            let at = format!("\"{}\"", j.name);
            // an anchor on `ground` is in world coordinates, others local
            let parent_off = if j.parent == GROUND {
                across(j.parent_anchor)
            } else {
                j.parent_anchor.1
            };
            if parent_off != 0.0 || j.child_anchor.1 != 0.0 {
                return self.fail(
                    "parent_anchor",
                    Some(&at),
                    format!(
                        "hinges on the mirror line (local y = 0; {coord} = 0 on `ground`), but joint `{}` has {:?} and {:?}",
                        j.name, j.parent_anchor, j.child_anchor
                    ),
                );
            }
            if let Some((lo, hi)) = j.limits {
                if lo != -hi {
                    return self.fail(
                        "limits",
                        Some(&at),
                        format!(
                            "limits symmetric about 0, (-m, m), but joint `{}` has ({lo}, {hi})",
                            j.name
                        ),
                    );
                }
            }
        }
        Ok(())
    }
}
