//! A noisy world's draws: before each command, the start offsets of the
//! bodies of its copy, then the factors of the bodies' numbers, then one
//! factor per slot for its actions, all from the generators of the
//! command's keys (see [`World::set_draw_keys`](crate::World::set_draw_keys)):
//! the numbers drawn per session from the session's key, the rest from
//! the execution's.

use super::joint_start::set_joints;
use super::{PhysicsWorld, Replica, Sets};
use crate::rng::SessionRng;
use crate::scene::physics::{draw_key, generator, session_key, DrawKey, Per, PhysicsSpec, Spread};
use rapier2d::math::{Real, Rotation, Vector};

/// A scene's noise, resolved to body indices.
#[derive(Debug, Clone)]
pub(super) struct Noise {
    actions: Option<Spread>,
    /// Per noisy body: its index in the scene, its position's and its
    /// angle's spreads.
    starts: Vec<(usize, Option<Spread>, Option<Spread>)>,
    /// Per noisy joint: its index in the scene and its coordinate's spread.
    joints: Vec<(usize, Spread)>,
    /// Whether the joints are set after the offsets: some joint is noisy,
    /// or some noisy body carries a joint (its tree follows it).
    carry: bool,
    /// Per entry of `body_numbers`: its body's index, when it is drawn,
    /// and the spreads of its mass, linear and angular damping and
    /// friction factors.
    numbers: Vec<(usize, Per, [Option<Spread>; 4])>,
    /// Per body of the scene: its numbers in the scene (those the factors
    /// multiply, whatever state a command starts from).
    bases: Vec<Numbers>,
    /// Whether the start offsets are applied: the command starts from a
    /// start state (not from where an earlier command of an episode left
    /// the world). Drawn either way.
    pub(super) offsets: bool,
    /// The keys given for the next commands, and those of the batch
    /// being run.
    given: Vec<DrawKey>,
    batch: Vec<DrawKey>,
    /// Commands executed without keys given: their keys count on.
    unkeyed: u64,
    /// Per copy, then per slot: the factor of the slot's action.
    factors: Vec<Real>,
}

/// A body's numbers in the scene: its linear and angular damping, its
/// mass, and each collider's friction and mass.
#[derive(Debug, Clone, Default)]
struct Numbers {
    linear: Real,
    angular: Real,
    mass: Real,
    colliders: Vec<(Real, Real)>,
}

impl Noise {
    /// The noise of `spec`, if it draws anything; `sets` and `copy` are
    /// the world's pristine sets and copy 0, whose bodies' numbers the
    /// factors multiply.
    pub(super) fn of(spec: &PhysicsSpec, sets: &Sets, copy: &Replica) -> Option<Noise> {
        let n = spec.active_noise()?;
        let starts = n
            .starts
            .iter()
            .filter_map(|s| Some((spec.body_index(&s.body)?, s.position, s.angle)))
            .collect();
        let joints: Vec<(usize, Spread)> = (n.starts.iter())
            .filter_map(|s| {
                Some((
                    spec.joints.iter().position(|j| j.name == s.joint)?,
                    s.angle?,
                ))
            })
            .collect();
        let carries = |b: &str| spec.joints.iter().any(|j| j.parent == b);
        let carry = !joints.is_empty() || n.starts.iter().any(|s| carries(&s.body));
        let numbers: Vec<(usize, Per, [Option<Spread>; 4])> = (n.body_numbers.iter())
            .filter_map(|b| {
                let spreads = b.spreads().map(|(_, p)| p);
                Some((spec.body_index(&b.body)?, b.per, spreads))
            })
            .collect();
        let mut bases = vec![Numbers::default(); copy.handles.len()];
        for &(i, _, _) in &numbers {
            let b = &sets.bodies[copy.handles[i]];
            let colliders = b.colliders().iter().map(|&c| &sets.colliders[c]);
            bases[i] = Numbers {
                linear: b.linear_damping(),
                angular: b.angular_damping(),
                mass: b.mass(),
                colliders: colliders.map(|c| (c.friction(), c.mass())).collect(),
            };
        }
        Some(Noise {
            actions: n.actions,
            starts,
            joints,
            carry,
            numbers,
            bases,
            offsets: true,
            given: Vec::new(),
            batch: Vec::new(),
            unkeyed: 0,
            factors: Vec::new(),
        })
    }

    /// The keys of the next `n` commands: those given, if `n` were given,
    /// else the next `n` of a count kept by the world (commands executed
    /// outside a session, keyed by the world's history).
    /// (The session of those: the seed `u64::MAX`'s.)
    pub(super) fn take_keys(&mut self, n: usize) -> Vec<DrawKey> {
        let given = std::mem::take(&mut self.given);
        if given.len() == n {
            return given;
        }
        let first = self.unkeyed;
        self.unkeyed += n as u64;
        let session = session_key(u64::MAX);
        (first..first + n as u64)
            .map(|k| DrawKey {
                session,
                execution: draw_key(u64::MAX, k),
            })
            .collect()
    }

    pub(super) fn give(&mut self, keys: &[DrawKey]) {
        self.given.clear();
        self.given.extend_from_slice(keys);
    }

    pub(super) fn set_batch(&mut self, keys: &[DrawKey]) {
        self.batch.clear();
        self.batch.extend_from_slice(keys);
    }

    /// The factor of slot `slot`'s action on copy `copy`.
    pub(super) fn factor(&self, copy: usize, slots: usize, slot: usize) -> Real {
        self.factors
            .get(copy * slots + slot)
            .copied()
            .unwrap_or(1.0)
    }
}

impl PhysicsWorld {
    /// Draws the noise of the first `n` copies' commands, keyed by the
    /// batch's keys: offsets the starts of the noisy bodies (after the
    /// restore; x, y, then the angle, body after body; then each noisy
    /// joint's coordinate, the trees following; drawn but not applied
    /// when the command continues an episode), sets the bodies' numbers
    /// to the scene's times drawn factors (mass, linear and angular
    /// damping, friction, each drawn when given; entry after entry, those
    /// drawn per execution from the execution's generator, those per
    /// session from the session's), then draws each slot's factor in slot
    /// order.
    pub(super) fn draw_noise(&mut self, n: usize) {
        let slots = self.space.num_slots();
        let Some(noise) = self.noise.as_mut() else {
            return;
        };
        noise.factors.clear();
        noise.factors.resize(n * slots, 1.0);
        for c in 0..n {
            let mut rng = generator(noise.batch[c].execution);
            // the joints' coordinates before the bodies move: kept unless noisy
            let mut target: Vec<(f64, f64)> = match noise.carry {
                true => (self.copies[c].joints.iter())
                    .map(|j| j.coordinate(&self.sets.bodies))
                    .collect(),
                false => Vec::new(),
            };
            for &(i, position, angle) in &noise.starts {
                let b = &mut self.sets.bodies[self.copies[c].handles[i]];
                if let Some(p) = position {
                    let (dx, dy) = (p.draw(&mut rng), p.draw(&mut rng));
                    let t = b.translation();
                    let at = Vector::new(t.x + dx as Real, t.y + dy as Real);
                    if noise.offsets {
                        b.set_translation(at, true);
                    }
                }
                if let Some(a) = angle {
                    let turned = b.rotation().angle() + a.draw(&mut rng) as Real;
                    if noise.offsets {
                        b.set_rotation(Rotation::new(turned), true);
                    }
                }
            }
            if noise.carry {
                for &(k, a) in &noise.joints {
                    target[k].0 += a.draw(&mut rng);
                }
                let listed: Vec<usize> = noise.joints.iter().map(|&(k, _)| k).collect();
                if noise.offsets {
                    let infos = &self.copies[c].joints;
                    let geometry = &self.joint_geometry;
                    set_joints(&mut self.sets, infos, geometry, &target, &listed);
                }
            }
            let mut session = None;
            for &(i, per, spreads) in &noise.numbers {
                let rng = match per {
                    Per::Execution => &mut rng,
                    Per::Session => {
                        session.get_or_insert_with(|| generator(noise.batch[c].session))
                    }
                };
                let h = self.copies[c].handles[i];
                scale_numbers(&mut self.sets, h, &noise.bases[i], spreads, rng);
            }
            if let Some(a) = noise.actions {
                for f in &mut noise.factors[c * slots..(c + 1) * slots] {
                    *f = (1.0 + a.draw(&mut rng)) as Real;
                }
            }
        }
    }
}

/// Sets body `h`'s numbers to `base` times factors `1 + x` drawn with
/// `rng` (mass, linear and angular damping, friction; each when its
/// spread is given).
fn scale_numbers(
    sets: &mut Sets,
    h: rapier2d::prelude::RigidBodyHandle,
    base: &Numbers,
    spreads: [Option<Spread>; 4],
    rng: &mut SessionRng,
) {
    let mut factor = |k: usize| spreads[k].map(|p| 1.0 + p.draw(rng) as Real);
    let (mass, linear, angular, friction) = (factor(0), factor(1), factor(2), factor(3));
    let b = &mut sets.bodies[h];
    if let Some(k) = linear {
        b.set_linear_damping(base.linear * k);
    }
    if let Some(k) = angular {
        b.set_angular_damping(base.angular * k);
    }
    let colliders = b.colliders().to_vec();
    let mut on_colliders = 0.0;
    for (co, &(f, m)) in colliders.into_iter().zip(&base.colliders) {
        let co = &mut sets.colliders[co];
        if let Some(k) = friction {
            co.set_friction(f * k);
        }
        on_colliders += m;
        if let Some(k) = mass.filter(|_| m > 0.0) {
            co.set_mass(m * k);
        }
    }
    // a shape without area carries the body's own mass
    if let Some(k) = mass.filter(|_| on_colliders == 0.0) {
        sets.bodies[h].set_additional_mass(base.mass * k, true);
    }
}
