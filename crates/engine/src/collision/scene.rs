//! The set of surfaces a particle can strike, and the query for the earliest one.

use super::broad_phase::Grid;
use super::{Aabb, Flight, Hit, Primitive, Shape};
use glam::DVec3;

/// Margin of the boxes that reject a surface before its exact test, m: keeps the reject
/// conservative against rounding.
const BOX_MARGIN: f64 = 1e-9;

/// Index of a surface in the [`Scene`], in the order the surfaces were given.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SurfaceId(pub u32);

impl SurfaceId {
    /// The index as a `usize`.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// What a surface belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceKind {
    /// Target number `i` (its deposit surface).
    Target(usize),
    /// Obstacle number `i` (no deposit).
    Obstacle(usize),
}

/// One collidable surface: its shape, its owner and the impact model that applies on it.
#[derive(Clone, Debug)]
pub struct SurfaceRef {
    /// The piece's geometry, in scene coordinates (m).
    pub shape: Shape,
    /// Target or obstacle it belongs to.
    pub kind: SurfaceKind,
    /// Which piece of its owner it is (a mesh's triangle; 0 for a single shape).
    pub piece: u32,
    /// Index into the simulation's impact models.
    pub impact: usize,
    /// How far in front of a face (along its normal) a deposited layer may reach, m; the face's
    /// bounding box is grown by it so that the broad phase sees the layer.
    pub layer: f64,
}

impl SurfaceRef {
    /// Bounding box including the layer allowance (`None` for unbounded planes): flat
    /// surfaces grow along their normal, others on every side.
    fn bounds(&self) -> Option<Aabb> {
        let b = self.shape.aabb()?;
        if self.layer <= 0.0 {
            return Some(b);
        }
        let along = |normal: DVec3| {
            let reach = normal * self.layer;
            Aabb { min: b.min.min(b.min + reach), max: b.max.max(b.max + reach) }
        };
        Some(match &self.shape {
            Shape::Face(f) => along(f.normal),
            Shape::Triangle(t) => along(t.normal),
            _ => b.inflate(self.layer),
        })
    }
}

/// All surfaces of a scenario, indexed for segment queries.
#[derive(Clone, Debug, Default)]
pub struct Scene {
    surfaces: Vec<SurfaceRef>,
    /// Surfaces without a bounding box (infinite planes), tested on every query.
    unbounded: Vec<u32>,
    /// Bounding box per surface (empty for unbounded ones), for a cheap reject before the
    /// exact test.
    boxes: Vec<Aabb>,
    grid: Grid,
    bounds: Aabb,
}

impl Scene {
    /// Indexes `surfaces` for queries inside `bounds` (the simulation domain; nothing outside
    /// it is ever queried).
    pub fn new(surfaces: Vec<SurfaceRef>, bounds: Aabb) -> Scene {
        let boxes: Vec<Option<Aabb>> = surfaces.iter().map(SurfaceRef::bounds).collect();
        let unbounded = (0..surfaces.len() as u32).filter(|&i| boxes[i as usize].is_none()).collect();
        let grid = Grid::new(&boxes, bounds);
        let everywhere = Aabb { min: DVec3::NEG_INFINITY, max: DVec3::INFINITY };
        let boxes = boxes.iter().map(|b| b.map_or(everywhere, |b| b.inflate(BOX_MARGIN))).collect();
        Scene { surfaces, unbounded, boxes, grid, bounds }
    }

    /// Sets how far a layer may reach in front of each surface of `ids` (m). The broad phase
    /// marks the space a layer may take as occupied, so that particles there get the full
    /// search (which finds the layer itself); the surfaces' own cells never change. Growing
    /// costs the cells of the grown zones; any shrinking rebuilds the marks from the binned
    /// grid, so the marks never depend on the history that led to the allowances.
    pub fn set_layer_allowances(&mut self, ids: &[(SurfaceId, f64)]) {
        let shrinks = ids.iter().any(|&(id, reach)| reach < self.surfaces[id.index()].layer);
        for &(id, reach) in ids {
            let s = &mut self.surfaces[id.index()];
            s.layer = reach;
            if let Some(b) = s.bounds() {
                self.boxes[id.index()] = b.inflate(BOX_MARGIN);
            }
        }
        let marked: Vec<usize> = if shrinks {
            self.grid.clear_marks();
            (0..self.surfaces.len()).filter(|&i| self.surfaces[i].layer > 0.0).collect()
        } else {
            ids.iter().filter(|(_, reach)| *reach > 0.0).map(|(id, _)| id.index()).collect()
        };
        for i in marked {
            if let Some(b) = self.surfaces[i].bounds() {
                self.grid.mark(&b);
            }
        }
    }

    /// True if `surfaces` (allowances aside) and `bounds` are this scene's: a simulation of
    /// them can reuse this scene's index.
    pub fn indexes(&self, surfaces: &[SurfaceRef], bounds: Aabb) -> bool {
        self.bounds == bounds
            && self.surfaces.len() == surfaces.len()
            && self.surfaces.iter().zip(surfaces).all(|(a, b)| {
                a.shape == b.shape && a.kind == b.kind && a.piece == b.piece && a.impact == b.impact
            })
    }

    /// Sets every layer allowance back to 0, as [`Scene::new`] left them (the surfaces are
    /// binned with their allowances at the time).
    pub fn clear_layer_allowances(&mut self) {
        let ids: Vec<_> = (0..self.surfaces.len() as u32).map(|i| (SurfaceId(i), 0.0)).collect();
        self.set_layer_allowances(&ids);
    }

    /// True if the box `b` overlaps surface `id`'s bounds, its layer allowance included, grown
    /// by a rounding margin (always for unbounded planes).
    #[inline]
    pub fn reaches(&self, id: SurfaceId, b: &Aabb) -> bool {
        self.boxes[id.index()].overlaps(b)
    }

    /// Surface `id`'s bounds, its layer allowance included (`None` for unbounded planes).
    pub fn bounds_of(&self, id: SurfaceId) -> Option<Aabb> {
        self.surfaces[id.index()].bounds()
    }

    /// The surface with index `id`.
    #[inline]
    pub fn surface(&self, id: SurfaceId) -> &SurfaceRef {
        &self.surfaces[id.index()]
    }

    /// True if no unbounded plane crosses or touches the box `b` (each has every corner of
    /// the box strictly on one side).
    pub fn unbounded_clear(&self, b: &Aabb) -> bool {
        self.unbounded.iter().all(|&i| match &self.surfaces[i as usize].shape {
            Shape::Plane(plane) => {
                let (lo, hi) = plane.signed_range(b);
                lo > BOX_MARGIN || hi < -BOX_MARGIN
            }
            _ => false,
        })
    }

    /// True if no bounded surface (its layer allowance included) is binned in any cell near the
    /// box `b`: a box inside one empty neighbourhood of the broad phase's distance map.
    pub fn box_is_empty(&self, b: &Aabb) -> bool {
        self.grid.box_is_empty(b)
    }

    /// True if the box `b` is smaller than a cell of the broad phase and its lower corner lies
    /// in a cell whose whole neighbourhood is empty (layer zones included).
    pub fn box_is_clear(&self, b: &Aabb) -> bool {
        self.unbounded.is_empty() && self.grid.box_is_clear(b)
    }

    /// Calls `visit` with every bounded surface binned in the cells that the box `b` overlaps
    /// (a surface spanning several of them once per cell).
    pub fn surfaces_near(&self, b: &Aabb, visit: &mut dyn FnMut(SurfaceId)) {
        self.grid.for_each_in_box(b, |items| items.iter().for_each(|&i| visit(SurfaceId(i))));
    }

    /// The surfaces, in the order they were given.
    pub fn surfaces(&self) -> &[SurfaceRef] {
        &self.surfaces
    }

    /// True if the segment `p0 → p1` certainly hits nothing: the cheap test that lets a
    /// particle in free flight skip the search for the earliest hit.
    #[inline]
    pub fn is_clear(&self, p0: DVec3, p1: DVec3) -> bool {
        self.unbounded.is_empty() && self.grid.is_clear(p0, p1)
    }

    /// Earliest hit of the segment `p0 → p1` over all surfaces: the surface's index and the hit.
    /// Ties go to the surface given first, so the answer never depends on traversal order.
    #[inline]
    pub fn first_hit(&self, p0: DVec3, p1: DVec3) -> Option<(SurfaceId, Hit)> {
        let mut best: Option<(usize, Hit)> = None;
        let seg = Aabb::from_points(p0, p1);
        let test = |i: u32, best: &mut Option<(usize, Hit)>| {
            let i = i as usize;
            if !self.boxes[i].overlaps(&seg) {
                return;
            }
            if let Some(hit) = self.surfaces[i].shape.intersect(p0, p1)
                && best.is_none_or(|(j, b)| hit.t < b.t || (hit.t == b.t && i < j))
            {
                *best = Some((i, hit));
            }
        };
        for &i in &self.unbounded {
            test(i, &mut best);
        }
        self.grid.walk(p0, p1, |items| {
            for &i in items {
                test(i, &mut best);
            }
            best.map_or(f64::INFINITY, |(_, h)| h.t)
        });
        best.map(|(i, h)| (SurfaceId(i as u32), h))
    }

    /// How long (s, at most `horizon`) the flight from `x` with velocity `v` under
    /// acceleration `g` certainly hits nothing: 0 near any surface or when unbounded planes
    /// exist (see `Grid::free_flight`).
    pub fn free_flight(&self, x: DVec3, v: DVec3, g: DVec3, horizon: f64) -> f64 {
        if self.unbounded.is_empty() { self.grid.free_flight(x, v, g, horizon) } else { 0.0 }
    }

    /// True if the arc certainly hits nothing (it stays inside one empty neighbourhood).
    #[inline]
    pub fn arc_is_clear(&self, arc: &Flight) -> bool {
        self.unbounded.is_empty() && self.grid.box_is_clear(&arc.aabb())
    }

    /// Earliest exact hit of a ballistic arc over all surfaces: the surface's index and the hit
    /// (`Hit::t` is the fraction of the arc's duration). Ties go to the surface given first.
    pub fn first_hit_arc(&self, arc: &Flight) -> Option<(SurfaceId, Hit)> {
        self.first_hit_within(arc, &[arc.aabb()])
    }

    /// [`Scene::first_hit_arc`] for an arc held by the boxes `pieces`: only the surfaces near
    /// one of them are solved (a long arc's pieces leave out most of its one box).
    pub fn first_hit_within(&self, arc: &Flight, pieces: &[Aabb]) -> Option<(SurfaceId, Hit)> {
        let mut best: Option<(usize, Hit)> = None;
        let mut test = |i: u32| {
            let i = i as usize;
            if let Some(hit) = self.surfaces[i].shape.intersect_arc(arc)
                && best.is_none_or(|(j, b)| hit.t < b.t || (hit.t == b.t && i < j))
            {
                best = Some((i, hit));
            }
        };
        self.unbounded.iter().for_each(|&i| test(i));
        // A surface spanning several of the cells is solved once (the answer does not depend on
        // the order of the tests, only on which surfaces are tested).
        let mut seen = [u32::MAX; 16];
        let mut n = 0;
        for piece in pieces {
            self.grid.for_each_in_box(piece, |items| {
                for &i in items {
                    if seen[..n].contains(&i) || !self.boxes[i as usize].overlaps(piece) {
                        continue;
                    }
                    if n < seen.len() {
                        seen[n] = i;
                        n += 1;
                    }
                    test(i);
                }
            });
        }
        best.map(|(i, h)| (SurfaceId(i as u32), h))
    }

    /// Earliest hit by testing every surface, without the grid: the reference the indexed
    /// query must agree with.
    pub fn first_hit_linear(&self, p0: DVec3, p1: DVec3) -> Option<(SurfaceId, Hit)> {
        let mut best: Option<(usize, Hit)> = None;
        for (i, s) in self.surfaces.iter().enumerate() {
            if let Some(hit) = s.shape.intersect(p0, p1)
                && best.is_none_or(|(_, b)| hit.t < b.t)
            {
                best = Some((i, hit));
            }
        }
        best.map(|(i, h)| (SurfaceId(i as u32), h))
    }
}
