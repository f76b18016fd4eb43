//! What is possible but suspicious in a physics world, for `e3d scene
//! check`.

use super::limits::show;
use super::to_world;
use super::{BodyKind, BodySpec, PhysicsSpec};

impl PhysicsSpec {
    /// What is possible but suspicious, for `e3d scene check`: a tracked point
    /// or a dynamic body starting outside the effect grid, walls that do not
    /// enclose the tracked body or lie wholly outside the grid (only for an
    /// effect that is one point's world cell). Each context's start is checked
    /// too (a drawn one at its two extreme corners), its new warnings prefixed
    /// with `context `NAME`: `.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = self.start_warnings();
        if self.contexts.is_empty() || self.effect.world_point().is_none() {
            return out;
        }
        let bare = self.without_contexts();
        let own: std::collections::HashSet<String> = out.iter().cloned().collect();
        for c in &self.contexts {
            let corners: &[u64] = if c.is_sampled() { &[0, u64::MAX] } else { &[0] };
            let mut seen = std::collections::HashSet::new();
            for &corner in corners {
                for w in self.posed(&bare, c, corner).start_warnings() {
                    if !own.contains(&w) && seen.insert(w.clone()) {
                        out.push(format!("context `{}`: {w}", crate::text::echo(&c.name)));
                    }
                }
            }
        }
        out
    }

    /// [`warnings`](Self::warnings) of the scene's own start.
    fn start_warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let Some((tracked, point, g)) = self.effect.world_point() else {
            return out;
        };
        let inside = |p: (f64, f64)| {
            p.0 >= g.min[0] && p.0 <= g.max[0] && p.1 >= g.min[1] && p.1 <= g.max[1]
        };
        let body = self.body(tracked);
        let start = body.map(|b| to_world(b.position, b.angle, point));
        if let Some(p) = start.filter(|p| !inside(*p)) {
            out.push(format!(
                "the tracked point starts at ({}, {}), outside the effect grid [{}, {}] x [{}, {}]: it counts in the nearest border cell",
                show(p.0), show(p.1), g.min[0], g.max[0], g.min[1], g.max[1]
            ));
        }
        let outside = |b: &&BodySpec| b.kind == BodyKind::Dynamic && !inside(b.position);
        for b in self.bodies.iter().filter(outside) {
            let (name, (x, y)) = (&b.name, b.position);
            let (x, y) = (show(x), show(y));
            out.push(format!(
                "dynamic body `{name}` starts at ({x}, {y}), outside the effect grid"
            ));
        }
        // walls that do not enclose a free tracked body
        if let Some(l) = crate::scene::enclosure::leak(self) {
            let start = body.map_or((0.0, 0.0), |b| b.position);
            out.push(format!(
                "the walls do not enclose the tracked body `{}`: from its start ({}, {}) it may leave them near ({:.2}, {:.2}) (fixed bodies rasterised on {} m cells; a gap of 1.5 times its radius or more counts)",
                tracked,
                show(start.0),
                show(start.1),
                l.point.0,
                l.point.1,
                show(l.cell)
            ));
        }
        // a fixed body that neither lies in nor touches the effect grid
        // bounds no motion there: most likely a misplaced wall
        let tol = crate::scene::overlap::OVERLAP_TOLERANCE;
        for b in self
            .bodies
            .iter()
            .filter(|b| b.kind == BodyKind::Fixed && b.collide)
        {
            let (lo, hi) = crate::scene::overlap::start_aabb(b);
            if lo[0] > g.max[0] + tol
                || hi[0] < g.min[0] - tol
                || lo[1] > g.max[1] + tol
                || hi[1] < g.min[1] - tol
            {
                out.push(format!(
                    "fixed body `{}` spans [{}, {}] x [{}, {}], wholly outside the effect grid [{}, {}] x [{}, {}]: it bounds no motion on the grid (a misplaced wall?)",
                    b.name,
                    show(lo[0]), show(hi[0]), show(lo[1]), show(hi[1]),
                    g.min[0], g.max[0], g.min[1], g.max[1]
                ));
            }
        }
        out
    }
}
