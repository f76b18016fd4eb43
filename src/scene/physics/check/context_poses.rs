//! Where a start context puts the scene's bodies, computed from the scene
//! file alone (forward kinematics of the listed joints, free bodies placed
//! with the trees they carry), and the refusal of a context whose start
//! puts two bodies into one another, as the scene's own start is refused.

use super::super::context::StartState;
use super::super::{to_world, PhysicsSpec};
use crate::scene::overlap::{first_overlap, OVERLAP_TOLERANCE};
use crate::scene::Invalid;

/// The most ranged coordinates (a ranged body's x and y count two, a
/// ranged joint one) whose every corner is checked; beyond, only the two
/// corners where every range is at its first end, or every range at its
/// `to` end.
pub const MAX_CHECKED_RANGES: usize = 8;

impl PhysicsSpec {
    /// Every body's start pose `(x, y, angle)` in context `k`, in the scene's
    /// order: its free bodies placed (with the trees they carry), then its
    /// joints turned from the root outwards; a ranged field at its first end.
    ///
    /// ```
    /// use e3d::Scene;
    /// let scene = Scene::load("scenes/arm7_poses.ron").unwrap();
    /// let p = scene.as_physics().unwrap().spec();
    /// let straight = p.context_poses(0);
    /// let raised = p.context_poses(1);
    /// assert_eq!(straight.len(), 7); // link1..link7
    /// assert!((raised[0].2 - 1.2).abs() < 1e-12); // link1 turned by j1
    /// assert!((raised[6].2 - 1.2).abs() < 1e-12); // and every link it carries
    /// assert_ne!(straight[6], raised[6]);
    /// ```
    pub fn context_poses(&self, k: usize) -> Vec<(f64, f64, f64)> {
        self.poses_at_corner(&self.contexts[k], 0)
    }

    /// [`context_poses`](Self::context_poses) of `c` with its ranged
    /// coordinates at the ends picked by the bits of `corner` (bit `i`
    /// set: the `i`-th ranged coordinate, bodies' x then y in order, then
    /// joints, at its `to` end).
    pub(crate) fn poses_at_corner(&self, c: &StartState, corner: u64) -> Vec<(f64, f64, f64)> {
        let mut poses: Vec<(f64, f64, f64)> = self
            .bodies
            .iter()
            .map(|b| (b.position.0, b.position.1, b.angle))
            .collect();
        let mut k = Corner { corner, bit: 0 };
        for b in &c.bodies {
            let Some(i) = self.body_index(&b.body) else {
                continue;
            };
            let (x0, y0, a0) = poses[i];
            let (x, y) = match (b.position, b.to) {
                (Some((x, y)), Some(t)) => (k.pick(x, t.0), k.pick(y, t.1)),
                (Some(p), None) => p,
                (None, _) => (x0, y0),
            };
            let a = b.angle.unwrap_or(a0);
            // the body and what it carries: rotate about its origin, then move it
            for j in self.carried_by(i) {
                let (px, py, pa) = poses[j];
                let (dx, dy) = (px - x0, py - y0);
                let (s, co) = (a - a0).sin_cos();
                poses[j] = (x + co * dx - s * dy, y + s * dx + co * dy, pa + a - a0);
            }
        }
        // the coordinates in the order listed (the corner's bits), then
        // the joints turned from the root outwards
        let mut q = vec![0.0; self.joints.len()];
        for s in &c.joints {
            if let (Some(j), Some(a)) =
                (self.joints.iter().position(|j| j.name == s.joint), s.angle)
            {
                q[j] = s.to.map_or(a, |t| k.pick(a, t));
            }
        }
        let mut order: Vec<usize> = (0..self.joints.len()).collect();
        order.sort_by_key(|&j| (self.joint_depth(j), j));
        for j in order.into_iter().filter(|&j| q[j] != 0.0) {
            self.turn_joint(&mut poses, j, q[j]);
        }
        poses
    }

    /// `bare` (this scene without its contexts) with its bodies where
    /// context `c` puts them at `corner` (see
    /// [`poses_at_corner`](Self::poses_at_corner)).
    pub(crate) fn posed(&self, bare: &PhysicsSpec, c: &StartState, corner: u64) -> PhysicsSpec {
        let mut posed = bare.clone();
        for (b, p) in posed.bodies.iter_mut().zip(self.poses_at_corner(c, corner)) {
            b.position = (p.0, p.1);
            b.angle = p.2;
        }
        posed
    }

    /// Turns (or slides) joint `j` by `q` in `poses`: its child and every
    /// body beyond it rotate about the joint's anchor (a hinge) or move
    /// along its axis (a slider).
    fn turn_joint(&self, poses: &mut [(f64, f64, f64)], j: usize, q: f64) {
        let spec = &self.joints[j];
        let Some(child) = self.body_index(&spec.child) else {
            return;
        };
        let parent = self.body_index(&spec.parent).map(|p| poses[p]);
        let (ax, ay) = match parent {
            Some((x, y, a)) => to_world((x, y), a, spec.parent_anchor),
            None => spec.parent_anchor,
        };
        let (s, co) = q.sin_cos();
        let slide = spec.axis().map(|axis| {
            let pa = parent.map_or(0.0, |p| p.2);
            to_world((0.0, 0.0), pa, axis)
        });
        for b in self.carried_by(child) {
            let (x, y, a) = poses[b];
            poses[b] = match slide {
                None => {
                    let (dx, dy) = (x - ax, y - ay);
                    (ax + co * dx - s * dy, ay + s * dx + co * dy, a + q)
                }
                Some((wx, wy)) => (x + q * wx, y + q * wy, a),
            };
        }
    }

    /// Body `i` and every body its joints carry (children, their
    /// children, ...).
    fn carried_by(&self, i: usize) -> Vec<usize> {
        let mut out = vec![i];
        let mut k = 0;
        while k < out.len() && out.len() <= self.bodies.len() {
            let name = &self.bodies[out[k]].name;
            for j in self.joints.iter().filter(|j| &j.parent == name) {
                if let Some(c) = self.body_index(&j.child).filter(|c| !out.contains(c)) {
                    out.push(c);
                }
            }
            k += 1;
        }
        out
    }

    /// How many joints lie between joint `j`'s parent and the ground or a
    /// free body.
    fn joint_depth(&self, j: usize) -> usize {
        self.joints_above(&self.joints[j].parent).count()
    }

    /// No context starts two bodies in one another ([`first_overlap`]): a
    /// named context's start, and every corner of a drawn one's ranges (the two
    /// extreme corners beyond [`MAX_CHECKED_RANGES`] ranged coordinates).
    pub(crate) fn check_context_overlaps(&self) -> Result<(), Invalid> {
        if self.contexts.is_empty() {
            return Ok(());
        }
        // the scene without its contexts, posed for each (a clone of the
        // whole scene per context was quadratic in the contexts)
        let bare = self.without_contexts();
        for (k, c) in self.contexts.iter().enumerate() {
            let ranged = c.bodies.iter().filter(|b| b.to.is_some()).count() * 2
                + c.joints.iter().filter(|j| j.to.is_some()).count();
            let corners: Vec<u64> = if ranged <= MAX_CHECKED_RANGES {
                (0..1u64 << ranged).collect()
            } else {
                vec![0, u64::MAX]
            };
            for corner in corners {
                let Some((i, j, depth)) = first_overlap(&self.posed(&bare, c, corner)) else {
                    continue;
                };
                let where_ = if ranged == 0 {
                    String::new()
                } else {
                    format!(" (at a corner of its ranges: {})", corner_text(c, corner))
                };
                let field = if c.joints.is_empty() {
                    "bodies"
                } else {
                    "joints"
                };
                return Err(Invalid::new(
                    field,
                    format!(
                        "context `{}`: a start where no two bodies overlap, but `{}` and `{}` overlap by {:.4} m there{where_} (at most {} m, touching, is allowed)",
                        crate::text::echo(&c.name),
                        self.bodies[i].name,
                        self.bodies[j].name,
                        depth,
                        OVERLAP_TOLERANCE
                    ),
                )
                .within("contexts", k));
            }
        }
        Ok(())
    }
}

/// The ranged fields of `c` at `corner`, as `body.x=…, joint=…`.
fn corner_text(c: &StartState, corner: u64) -> String {
    let mut parts = Vec::new();
    let mut k = Corner { corner, bit: 0 };
    for b in &c.bodies {
        if let (Some(p), Some(t)) = (b.position, b.to) {
            let (x, y) = (k.pick(p.0, t.0), k.pick(p.1, t.1));
            parts.push(format!("`{}` at ({x}, {y})", b.body));
        }
    }
    for j in &c.joints {
        if let (Some(a), Some(t)) = (j.angle, j.to) {
            parts.push(format!("`{}` at {}", j.joint, k.pick(a, t)));
        }
    }
    parts.join(", ")
}

/// The ends of a context's ranged coordinates at `corner`, taken in order
/// (bit `i` set: the `i`-th ranged coordinate at its `to` end; `u64::MAX`:
/// every one).
struct Corner {
    corner: u64,
    bit: usize,
}

impl Corner {
    /// The next ranged coordinate, from `first` to `to`, at this corner.
    fn pick(&mut self, first: f64, to: f64) -> f64 {
        let i = self.bit;
        self.bit += 1;
        if self.corner == u64::MAX || (i < 64 && self.corner >> i & 1 == 1) {
            to
        } else {
            first
        }
    }
}
