//! A noisy world's draws: before each command, the start offsets of the
//! bodies of its copy, then one factor per slot for its actions, all from
//! the generator of the command's key (see
//! [`World::set_draw_keys`](crate::World::set_draw_keys)).

use super::joint_start::set_joints;
use super::PhysicsWorld;
use crate::scene::physics::{draw_key, generator, PhysicsSpec, Spread};
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
    /// Per body whose numbers are drawn: its index, and the spreads of
    /// its mass, linear and angular damping and friction factors.
    numbers: Vec<(usize, [Option<Spread>; 4])>,
    /// The keys given for the next commands, and those of the batch
    /// being run.
    given: Vec<u64>,
    batch: Vec<u64>,
    /// Commands executed without keys given: their keys count on.
    unkeyed: u64,
    /// Per copy, then per slot: the factor of the slot's action.
    factors: Vec<Real>,
}

impl Noise {
    /// The noise of `spec`, if it draws anything.
    pub(super) fn of(spec: &PhysicsSpec) -> Option<Noise> {
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
        let numbers = n
            .body_numbers
            .iter()
            .filter_map(|b| Some((spec.body_index(&b.body)?, b.spreads().map(|(_, p)| p))))
            .collect();
        Some(Noise {
            actions: n.actions,
            starts,
            joints,
            carry,
            numbers,
            given: Vec::new(),
            batch: Vec::new(),
            unkeyed: 0,
            factors: Vec::new(),
        })
    }

    /// The keys of the next `n` commands: those given, if `n` were given,
    /// else the next `n` of a count kept by the world (commands executed
    /// outside a session, keyed by the world's history).
    pub(super) fn take_keys(&mut self, n: usize) -> Vec<u64> {
        let given = std::mem::take(&mut self.given);
        if given.len() == n {
            return given;
        }
        let first = self.unkeyed;
        self.unkeyed += n as u64;
        (first..first + n as u64)
            .map(|k| draw_key(u64::MAX, k))
            .collect()
    }

    pub(super) fn give(&mut self, keys: &[u64]) {
        self.given.clear();
        self.given.extend_from_slice(keys);
    }

    pub(super) fn set_batch(&mut self, keys: &[u64]) {
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
    /// joint's coordinate, the trees following), scales the bodies'
    /// numbers (mass, linear and angular damping, friction, each drawn
    /// when given), then draws each slot's factor in slot order.
    pub(super) fn draw_noise(&mut self, n: usize) {
        let slots = self.space.num_slots();
        let Some(noise) = self.noise.as_mut() else {
            return;
        };
        noise.factors.clear();
        noise.factors.resize(n * slots, 1.0);
        for c in 0..n {
            let mut rng = generator(noise.batch[c]);
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
                    b.set_translation(at, true);
                }
                if let Some(a) = angle {
                    let turned = b.rotation().angle() + a.draw(&mut rng) as Real;
                    b.set_rotation(Rotation::new(turned), true);
                }
            }
            if noise.carry {
                for &(k, a) in &noise.joints {
                    target[k].0 += a.draw(&mut rng);
                }
                let listed: Vec<usize> = noise.joints.iter().map(|&(k, _)| k).collect();
                let infos = &self.copies[c].joints;
                set_joints(
                    &mut self.sets,
                    infos,
                    &self.joint_geometry,
                    &target,
                    &listed,
                );
            }
            for &(i, spreads) in &noise.numbers {
                let h = self.copies[c].handles[i];
                let mut factor = |k: usize| spreads[k].map(|p| 1.0 + p.draw(&mut rng) as Real);
                let (mass, linear, angular, friction) =
                    (factor(0), factor(1), factor(2), factor(3));
                let b = &mut self.sets.bodies[h];
                if let Some(k) = linear {
                    b.set_linear_damping(b.linear_damping() * k);
                }
                if let Some(k) = angular {
                    b.set_angular_damping(b.angular_damping() * k);
                }
                let colliders = b.colliders().to_vec();
                let own = b.mass();
                let mut on_colliders = 0.0;
                for co in colliders {
                    let co = &mut self.sets.colliders[co];
                    if let Some(k) = friction {
                        co.set_friction(co.friction() * k);
                    }
                    let m = co.mass();
                    on_colliders += m;
                    if let Some(k) = mass.filter(|_| m > 0.0) {
                        co.set_mass(m * k);
                    }
                }
                // a shape without area carries the body's own mass
                if let Some(k) = mass.filter(|_| on_colliders == 0.0) {
                    self.sets.bodies[h].set_additional_mass(own * k, true);
                }
            }
            if let Some(a) = noise.actions {
                for f in &mut noise.factors[c * slots..(c + 1) * slots] {
                    *f = (1.0 + a.draw(&mut rng)) as Real;
                }
            }
        }
    }
}
