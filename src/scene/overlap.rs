//! Start poses that cannot be simulated as written: bodies that overlap at
//! the start (a wall through a dynamic body, two bodies in one place),
//! which Rapier would push apart explosively before the first command.

use super::physics::{BodyKind, BodySpec, PhysicsSpec, ShapeSpec};
use parry2d::math::{Pose, Vector};
use parry2d::shape::{Ball, Capsule, Cuboid, Polyline, Segment, Shape};

/// How deep two bodies may overlap at the start, in metres: touching
/// (resting on a floor, a link against its neighbour) is fine.
pub const OVERLAP_TOLERANCE: f64 = 1e-3;

pub(crate) fn v(p: (f64, f64)) -> Vector {
    Vector::new(p.0 as f32, p.1 as f32)
}

pub(crate) fn shape(b: &BodySpec) -> Box<dyn Shape> {
    match &b.shape {
        ShapeSpec::Ball { radius } => Box::new(Ball::new(*radius as f32)),
        ShapeSpec::Cuboid { width, height } => Box::new(Cuboid::new(Vector::new(
            (*width / 2.0) as f32,
            (*height / 2.0) as f32,
        ))),
        ShapeSpec::Capsule { a, b: e, radius } => {
            Box::new(Capsule::new(v(*a), v(*e), *radius as f32))
        }
        ShapeSpec::Segment { a, b: e } => Box::new(Segment::new(v(*a), v(*e))),
        ShapeSpec::Polyline { points } => {
            Box::new(Polyline::new(points.iter().map(|p| v(*p)).collect(), None))
        }
    }
}

/// The first pair of bodies that overlap by more than
/// [`OVERLAP_TOLERANCE`] at the start: `(i, j, depth)`, `i < j`. Only
/// pairs that collide count: both with `collide`, at least one dynamic,
/// and not joined directly by a joint without `contacts`.
pub fn first_overlap(spec: &PhysicsSpec) -> Option<(usize, usize, f64)> {
    let n = spec.bodies.len();
    let poses: Vec<Pose> = spec
        .bodies
        .iter()
        .map(|b| Pose::new(v(b.position), b.angle as f32))
        .collect();
    let shapes: Vec<Box<dyn Shape>> = spec.bodies.iter().map(shape).collect();
    let aabbs: Vec<_> = (0..n).map(|i| shapes[i].compute_aabb(&poses[i])).collect();
    let index: std::collections::HashMap<&str, usize> = spec
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| (b.name.as_str(), i))
        .collect();
    let mut joined = std::collections::HashSet::new();
    for j in &spec.joints {
        if let (Some(&p), Some(&c)) = (index.get(j.parent.as_str()), index.get(j.child.as_str())) {
            if !j.contacts {
                joined.insert((p.min(c), p.max(c)));
            }
        }
    }
    // sweep and prune along x
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| aabbs[a].mins.x.total_cmp(&aabbs[b].mins.x));
    let mut found: Option<(usize, usize, f64)> = None;
    for (k, &a) in order.iter().enumerate() {
        for &b in &order[k + 1..] {
            if aabbs[b].mins.x > aabbs[a].maxs.x {
                break;
            }
            let (i, j) = (a.min(b), a.max(b));
            let (bi, bj) = (&spec.bodies[i], &spec.bodies[j]);
            if !(bi.collide && bj.collide)
                || (bi.kind != BodyKind::Dynamic && bj.kind != BodyKind::Dynamic)
                || joined.contains(&(i, j))
                || aabbs[b].mins.y > aabbs[a].maxs.y
                || aabbs[a].mins.y > aabbs[b].maxs.y
            {
                continue;
            }
            let Ok(Some(c)) =
                parry2d::query::contact(&poses[i], &*shapes[i], &poses[j], &*shapes[j], 0.0)
            else {
                continue;
            };
            let depth = -(c.dist as f64);
            if depth > OVERLAP_TOLERANCE && found.is_none_or(|f| (i, j) < (f.0, f.1)) {
                found = Some((i, j, depth));
            }
        }
    }
    found
}

/// The axis-aligned box of a body's shape at its start pose, in metres:
/// `(min, max)`.
pub fn start_aabb(b: &BodySpec) -> ([f64; 2], [f64; 2]) {
    let a = shape(b).compute_aabb(&Pose::new(v(b.position), b.angle as f32));
    (
        [a.mins.x as f64, a.mins.y as f64],
        [a.maxs.x as f64, a.maxs.y as f64],
    )
}
