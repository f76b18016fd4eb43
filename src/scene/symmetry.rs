//! Mirror symmetry of a physics scene (`symmetry: FlipY` or `FlipX`): a
//! scene a reflection leaves unchanged answers the mirror image of a
//! command with the mirror image of its outcome, so of each pair of
//! mirror-image commands only the one with the lower index is simulated
//! (see [`PhysicsWorld`](crate::world::PhysicsWorld)).
//!
//! Exact in real arithmetic, not bit for bit in Rapier (measured on arm7:
//! 1896 of 2187 outcomes bit-identical, 2185 effects equal;
//! `tests/physics/symmetry.rs`, docs/benchmarks.md): a scene opts in
//! knowingly.

use super::{Action, Invalid, SceneSpec};
use serde::{Deserialize, Serialize};

/// A reflection that leaves a physics scene unchanged.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum Symmetry {
    /// `y -> -y`: the mirror line is the x axis.
    FlipY,
    /// `x -> -x`: the mirror line is the y axis.
    FlipX,
}

impl Symmetry {
    /// The coordinate the reflection negates (0: x, 1: y).
    pub(crate) fn axis(self) -> usize {
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
        let mut mirrored = action.clone();
        match &mut mirrored {
            Action::Torque { torque: a, .. } | Action::Target { angle: a, .. } => *a = -*a,
            Action::Impulse { impulse: p, .. } | Action::Force { force: p, .. } => *p = v(*p),
            _ => {}
        }
        mirrored
    }

    /// Per slot, the index of each symbol's mirror image in the same slot
    /// (`maps[slot][symbol]`), or where an alphabet lacks one.
    pub(crate) fn symbol_maps(self, scene: &SceneSpec) -> Result<Vec<Vec<u8>>, Invalid> {
        // the symbols of the slots before, to place an error on the right
        // occurrence of a symbol that several slots use
        let mut seen: Vec<char> = Vec::new();
        let mut maps = Vec::new();
        for (slot, alphabet) in scene.slots().enumerate() {
            let mut map = Vec::with_capacity(alphabet.len());
            for s in alphabet {
                let m = self.mirror_action(&s.action);
                let Some(k) = alphabet.iter().position(|t| t.action == m) else {
                    let what = format!(
                        "symmetry {self:?}: the mirror image of every symbol's action in the same slot, but slot {slot} has none for '{}' (expected a symbol with {m:?})",
                        s.symbol
                    );
                    let nth = seen.iter().filter(|&&c| c == s.symbol).count();
                    return Err(
                        Invalid::at("action", Some(&format!("'{}'", s.symbol)), &what).nth(nth),
                    );
                };
                map.push(k as u8);
            }
            seen.extend(alphabet.iter().map(|s| s.symbol));
            maps.push(map);
        }
        Ok(maps)
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
