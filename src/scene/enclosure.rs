//! Whether the fixed bodies (the walls) enclose the tracked body: a
//! warning of `e3d scene check`, not an error (a scene may leave its
//! tracked body free on purpose).
//!
//! The fixed shapes are rasterised around the effect grid, on square cells
//! a quarter of the tracked body's radius wide: a cell is open when its
//! centre lies at least `radius - cell` from every fixed shape (where the
//! body's centre could be, give or take a cell). A flood fill from the
//! body's start that reaches an open cell outside the walls' bounding box
//! means the body may leave the walls: every gap at least `2 * (radius -
//! cell)` = 1.5 radii wide is found (gaps between 1.5 and 2 radii wide
//! are reported though the body may just not fit).

use super::overlap::{shape, start_aabb, v};
use super::physics::{BodyKind, BodySpec, PhysicsSpec, ShapeSpec};
use parry2d::math::Pose;
use std::collections::VecDeque;

/// The most cells rasterised: beyond, the cells grow.
const MAX_CELLS: f64 = 4e6;

/// Where the tracked body may leave the walls: the last open point inside
/// the walls' bounding box on a path out, and the cell size used.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Leak {
    /// A point near the gap, metres.
    pub point: (f64, f64),
    /// The rasterisation's cell, metres.
    pub cell: f64,
}

/// `Some(leak)` when the scene has colliding fixed bodies, a free tracked
/// body (dynamic, colliding, in no joint, a ball, box or capsule) and a
/// path for that body's centre from its start to outside the bounding box
/// of the fixed bodies near the effect grid; `None` otherwise (enclosed, or
/// nothing to check).
pub fn leak(spec: &PhysicsSpec) -> Option<Leak> {
    let (tracked, _, g) = spec.effect.world_point()?;
    let t = spec.body(tracked)?;
    let r = free_radius(spec, t)?;
    let start = t.position;
    // the grid's box, with the start
    let (mut lo, mut hi) = (
        [g.min[0].min(start.0), g.min[1].min(start.1)],
        [g.max[0].max(start.0), g.max[1].max(start.1)],
    );
    let cell_w = ((g.max[0] - g.min[0]) / g.cols as f64).max((g.max[1] - g.min[1]) / g.rows as f64);
    let near = |a: &([f64; 2], [f64; 2])| {
        a.0[0] <= hi[0] + cell_w
            && a.1[0] >= lo[0] - cell_w
            && a.0[1] <= hi[1] + cell_w
            && a.1[1] >= lo[1] - cell_w
    };
    let walls: Vec<_> = spec
        .bodies
        .iter()
        .filter(|b| b.kind == BodyKind::Fixed && b.collide)
        .map(|b| (b, start_aabb(b)))
        .filter(|(_, a)| near(a))
        .collect();
    if walls.is_empty() {
        return None;
    }
    let mut h = r / 4.0;
    let margin = 2.0 * r + 2.0 * h;
    let (mut wlo, mut whi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for k in 0..2 {
        for (_, (a, b)) in &walls {
            wlo[k] = wlo[k].min(a[k]);
            whi[k] = whi[k].max(b[k]);
        }
        lo[k] = lo[k].min(wlo[k]) - margin;
        hi[k] = hi[k].max(whi[k]) + margin;
    }
    let area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    if area / (h * h) > MAX_CELLS {
        h = (area / MAX_CELLS).sqrt();
    }
    let raster = Raster {
        lo,
        h,
        nx: ((hi[0] - lo[0]) / h).ceil() as usize + 1,
        ny: ((hi[1] - lo[1]) / h).ceil() as usize + 1,
    };
    let blocked = raster.blocked(&walls, (r - h).max(0.0));
    let outside = |p: (f64, f64)| p.0 < wlo[0] || p.0 > whi[0] || p.1 < wlo[1] || p.1 > whi[1];
    if outside(start) {
        return Some(Leak {
            point: start,
            cell: h,
        });
    }
    raster.flood(&blocked, start, outside)
}

/// The radius of the tracked body `t` when it is free: dynamic,
/// colliding, in no joint, a ball, box (its half short side) or capsule;
/// `None` otherwise.
fn free_radius(spec: &PhysicsSpec, t: &BodySpec) -> Option<f64> {
    if t.kind != BodyKind::Dynamic
        || !t.collide
        || spec
            .joints
            .iter()
            .any(|j| j.parent == t.name || j.child == t.name)
    {
        return None;
    }
    match t.shape {
        ShapeSpec::Ball { radius } | ShapeSpec::Capsule { radius, .. } => Some(radius),
        ShapeSpec::Cuboid { width, height } => Some(width.min(height) / 2.0),
        _ => None,
    }
}

/// A box: its lower and upper corners.
type Aabb = ([f64; 2], [f64; 2]);

/// Square cells `h` wide, `nx` by `ny`, from `lo`.
struct Raster {
    lo: [f64; 2],
    h: f64,
    nx: usize,
    ny: usize,
}

impl Raster {
    /// The centre of cell `(i, j)`.
    fn centre(&self, i: usize, j: usize) -> (f64, f64) {
        (
            self.lo[0] + (i as f64 + 0.5) * self.h,
            self.lo[1] + (j as f64 + 0.5) * self.h,
        )
    }

    /// Per cell (row by row): whether its centre lies within `clearance`
    /// of one of the `walls` (each with its start box).
    fn blocked(&self, walls: &[(&BodySpec, Aabb)], clearance: f64) -> Vec<bool> {
        let (lo, h, nx, ny) = (self.lo, self.h, self.nx, self.ny);
        let mut blocked = vec![false; nx * ny];
        for (b, (a0, a1)) in walls {
            let s = shape(b);
            let pose = Pose::new(v(b.position), b.angle as f32);
            let reach = clearance + h;
            let i0 = (((a0[0] - reach - lo[0]) / h).floor().max(0.0) as usize).min(nx - 1);
            let i1 = (((a1[0] + reach - lo[0]) / h).ceil().max(0.0) as usize).min(nx - 1);
            let j0 = (((a0[1] - reach - lo[1]) / h).floor().max(0.0) as usize).min(ny - 1);
            let j1 = (((a1[1] + reach - lo[1]) / h).ceil().max(0.0) as usize).min(ny - 1);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    if blocked[j * nx + i] {
                        continue;
                    }
                    let p = self.centre(i, j);
                    let d = s.distance_to_point(&pose, v(p), true) as f64;
                    if d <= clearance {
                        blocked[j * nx + i] = true;
                    }
                }
            }
        }
        blocked
    }

    /// A flood fill of the open cells from `start`'s: the leak at the
    /// first cell reached that is `outside` the walls' box (or on the
    /// raster's border), `None` when none is.
    fn flood(
        &self,
        blocked: &[bool],
        start: (f64, f64),
        outside: impl Fn((f64, f64)) -> bool,
    ) -> Option<Leak> {
        let (lo, h, nx, ny) = (self.lo, self.h, self.nx, self.ny);
        let si = (((start.0 - lo[0]) / h) as usize).min(nx - 1);
        let sj = (((start.1 - lo[1]) / h) as usize).min(ny - 1);
        if blocked[sj * nx + si] {
            return None;
        }
        let mut from = vec![usize::MAX; nx * ny];
        let s0 = sj * nx + si;
        from[s0] = s0;
        let mut queue = VecDeque::from([s0]);
        while let Some(c) = queue.pop_front() {
            let (i, j) = (c % nx, c / nx);
            if outside(self.centre(i, j)) || i == 0 || j == 0 || i + 1 == nx || j + 1 == ny {
                // the cell it came from is the last inside the walls' box
                // (the border of the raster lies outside that box)
                return Some(Leak {
                    point: self.centre(from[c] % nx, from[c] / nx),
                    cell: h,
                });
            }
            let mut next = |n: usize| {
                if !blocked[n] && from[n] == usize::MAX {
                    from[n] = c;
                    queue.push_back(n);
                }
            };
            next(c - 1);
            next(c + 1);
            next(c - nx);
            next(c + nx);
        }
        None
    }
}
