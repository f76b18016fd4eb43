//! Mirror symmetry of a physics scene (`symmetry: FlipY` or `FlipX`).
//!
//! A scene that a reflection leaves unchanged (every body on the mirror
//! line, its own mirror image; gravity along the line; an effect grid
//! symmetric about it; an alphabet that holds the mirror image of every
//! symbol's action) answers the mirror image of a command with the mirror
//! image of its outcome. Declaring the symmetry halves the simulations: of
//! each pair of mirror-image commands, only the one with the lower index
//! is simulated, the other's terminal point is its reflection (see
//! [`PhysicsWorld`](crate::world::PhysicsWorld)).
//!
//! This holds exactly in real arithmetic, not bit for bit in Rapier, whose
//! floating-point sums, contact ordering and contact features are not
//! mirror-symmetric. Measured on arm7 (all 2187 commands): against Rapier's
//! own outcome of every command, the table with the symmetry has 1896
//! outcomes bit-identical and 2185 effects equal (`tests/physics/symmetry.rs`,
//! docs/benchmarks.md). A scene opts in knowingly.

use super::physics::{PhysicsSpec, ShapeSpec, GROUND};
use super::{Action, Invalid, Scene};
use serde::{Deserialize, Serialize};

/// A reflection that leaves a physics scene unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Symmetry {
    /// `y -> -y`: the mirror line is the x axis.
    FlipY,
    /// `x -> -x`: the mirror line is the y axis.
    FlipX,
}

/// How far an angle may be from the mirror line and still lie on it.
const ANGLE_TOLERANCE: f64 = 1e-9;

impl Symmetry {
    /// The coordinate the reflection negates (0: x, 1: y).
    fn axis(self) -> usize {
        match self {
            Symmetry::FlipY => 1,
            Symmetry::FlipX => 0,
        }
    }

    /// The mirror image of a point or a vector.
    pub fn reflect(self, p: [f64; 2]) -> [f64; 2] {
        match self {
            Symmetry::FlipY => [p[0], -p[1]],
            Symmetry::FlipX => [-p[0], p[1]],
        }
    }

    /// The mirror image of a body's angle (radians, in `(-pi, pi]`).
    pub fn reflect_angle(self, angle: f64) -> f64 {
        use std::f64::consts::{PI, TAU};
        let a = match self {
            Symmetry::FlipY => -angle,
            Symmetry::FlipX => PI - angle,
        };
        let r = a.rem_euclid(TAU);
        if r > PI {
            r - TAU
        } else {
            r
        }
    }

    /// The mirror image of an action: torques and joint targets change
    /// sign (clockwise becomes counter-clockwise), impulses and forces are
    /// reflected, `Idle` stays.
    pub fn mirror_action(self, action: &Action) -> Action {
        let v = |p: (f64, f64)| {
            let [x, y] = self.reflect([p.0, p.1]);
            (x, y)
        };
        match action {
            Action::Torque { joint, torque } => Action::Torque {
                joint: joint.clone(),
                torque: -torque,
            },
            Action::Target { joint, angle } => Action::Target {
                joint: joint.clone(),
                angle: -angle,
            },
            Action::Impulse { body, impulse } => Action::Impulse {
                body: body.clone(),
                impulse: v(*impulse),
            },
            Action::Force { body, force } => Action::Force {
                body: body.clone(),
                force: v(*force),
            },
            other => other.clone(),
        }
    }

    /// Per slot, the index of each symbol's mirror image in the same slot
    /// (`maps[slot][symbol]`), or where an alphabet lacks one.
    pub(crate) fn symbol_maps(self, scene: &Scene) -> Result<Vec<Vec<u8>>, Invalid> {
        // the symbols of the slots before, to place an error on the right
        // occurrence of a symbol that several slots use
        let mut seen: Vec<char> = Vec::new();
        let mut maps = Vec::new();
        for (slot, alphabet) in scene.slots().enumerate() {
            let mut map = Vec::with_capacity(alphabet.len());
            for s in alphabet {
                let m = self.mirror_action(&s.action);
                match alphabet.iter().position(|t| t.action == m) {
                    Some(k) => map.push(k as u8),
                    None => {
                        return Err(Invalid {
                            nth: seen.iter().filter(|&&c| c == s.symbol).count(),
                            ..Invalid::at(
                                "action",
                                Some(&format!("'{}'", s.symbol)),
                                &format!(
                                    "symmetry {self:?}: the mirror image of every symbol's action in the same slot, but slot {slot} has none for '{}' (expected a symbol with {m:?})",
                                    s.symbol
                                ),
                            )
                        })
                    }
                }
            }
            seen.extend(alphabet.iter().map(|s| s.symbol));
            maps.push(map);
        }
        Ok(maps)
    }

    /// Checks that the reflection leaves `spec` (and its command) unchanged,
    /// each body being its own mirror image.
    pub(crate) fn validate(self, spec: &PhysicsSpec, scene: &Scene) -> Result<(), Invalid> {
        let k = self.axis();
        let coord = ["x", "y"][k];
        let across = |p: (f64, f64)| [p.0, p.1][k];
        let fail = |field: &str, anchor: Option<&str>, what: String| {
            Err(Invalid::at(
                field,
                anchor,
                &format!("symmetry {self:?}: {what}"),
            ))
        };
        // only a point's world cell reflects as a point: a joint's
        // coordinate, an angle, a point in another body's frame or a
        // product would need their own reflections
        let Some((_, point, g)) = spec.effect.world_point() else {
            return fail(
                "symmetry",
                None,
                "no symmetry with this effect: a symmetry reflects the effect's point in the world, and this effect is not one point's world cell (a joint's coordinate, an angle, a point in another body's frame or a product); remove `symmetry`".to_string(),
            );
        };
        if across(spec.gravity) != 0.0 {
            return fail(
                "gravity",
                None,
                format!(
                    "gravity along the mirror line ({coord} = 0), found {:?}",
                    spec.gravity
                ),
            );
        }
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
                return fail(
                    "position",
                    Some(&at),
                    format!(
                        "every body its own mirror image, on the mirror line ({coord} = 0), but `{}` is at {:?}",
                        b.name, b.position
                    ),
                );
            }
            if !along(b.angle) {
                return fail(
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
                return fail(
                    "shape",
                    Some(&at),
                    format!(
                        "shapes symmetric about the body's local x axis (local y = 0 for every point), but `{}`'s is not",
                        b.name
                    ),
                );
            }
        }
        for j in &spec.joints {
            let at = format!("\"{}\"", j.name);
            // an anchor on `ground` is in world coordinates, others local
            let parent_off = if j.parent == GROUND {
                across(j.parent_anchor)
            } else {
                j.parent_anchor.1
            };
            if parent_off != 0.0 || j.child_anchor.1 != 0.0 {
                return fail(
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
                    return fail(
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
        if point.1 != 0.0 {
            return fail(
                "point",
                None,
                format!(
                    "a tracked point on its body's local x axis (y = 0), found {:?}",
                    point
                ),
            );
        }
        if g.min[k] != -g.max[k] {
            return fail(
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
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflections() {
        assert_eq!(Symmetry::FlipY.reflect([1.0, 2.0]), [1.0, -2.0]);
        assert_eq!(Symmetry::FlipX.reflect([1.0, 2.0]), [-1.0, 2.0]);
        assert_eq!(Symmetry::FlipY.reflect_angle(0.5), -0.5);
        let a = Symmetry::FlipX.reflect_angle(-std::f64::consts::FRAC_PI_2);
        assert!((a + std::f64::consts::FRAC_PI_2).abs() < 1e-12, "{a}");
        let t = Action::Torque {
            joint: "j".into(),
            torque: 1.5,
        };
        assert_eq!(
            Symmetry::FlipX.mirror_action(&t),
            Action::Torque {
                joint: "j".into(),
                torque: -1.5
            }
        );
        let i = Action::Impulse {
            body: "b".into(),
            impulse: (1.0, 2.0),
        };
        assert_eq!(
            Symmetry::FlipY.mirror_action(&i),
            Action::Impulse {
                body: "b".into(),
                impulse: (1.0, -2.0)
            }
        );
    }
}
