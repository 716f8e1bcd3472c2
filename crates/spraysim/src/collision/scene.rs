//! The set of surfaces a particle can strike, and the query for the earliest one.

use super::{Aabb, Hit, Shape};
use glam::DVec3;

/// What a surface belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceKind {
    /// The face of target number `i` (it has a heightfield).
    Target(usize),
    /// Obstacle number `i` (no heightfield).
    Obstacle(usize),
}

/// One collidable surface: its shape, its owner and the impact model that applies on it.
#[derive(Clone, Debug)]
pub struct SurfaceRef {
    /// Geometry.
    pub shape: Shape,
    /// Bounding box (`None` for unbounded planes).
    pub aabb: Option<Aabb>,
    /// Target or obstacle it belongs to.
    pub kind: SurfaceKind,
    /// Index into the simulation's impact models.
    pub impact: usize,
}

/// All surfaces of a scenario.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    surfaces: Vec<SurfaceRef>,
}

impl Scene {
    /// Adds a surface.
    pub fn push(&mut self, shape: Shape, kind: SurfaceKind, impact: usize) {
        // A small margin keeps the cull conservative against rounding.
        let aabb = shape.aabb().map(|b| b.inflate(1e-9));
        self.surfaces.push(SurfaceRef { shape, aabb, kind, impact });
    }

    /// The surfaces, in the order they were added.
    pub fn surfaces(&self) -> &[SurfaceRef] {
        &self.surfaces
    }

    /// Earliest hit of the segment `p0 → p1` over all surfaces: the surface's index and the hit.
    /// Ties go to the surface added first, so the answer never depends on evaluation order.
    #[inline]
    pub fn first_hit(&self, p0: DVec3, p1: DVec3) -> Option<(usize, Hit)> {
        let seg = Aabb::from_points(p0, p1);
        let mut best: Option<(usize, Hit)> = None;
        for (i, s) in self.surfaces.iter().enumerate() {
            if s.aabb.is_some_and(|b| !b.overlaps(&seg)) {
                continue;
            }
            if let Some(hit) = s.shape.intersect(p0, p1)
                && best.is_none_or(|(_, b)| hit.t < b.t)
            {
                best = Some((i, hit));
            }
        }
        best
    }
}
