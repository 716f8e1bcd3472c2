//! Triangle meshes that collect deposit: a thickness per triangle (volume over area, so mass
//! is exact), a per-vertex thickness for smooth display, and a layer that raises each triangle
//! along its normal.

use super::heightfield::ChangedCells;
use super::{DepositSurface, LayerContact, SurfaceMesh};
use crate::checkpoint::{Dec, Enc, StateError};
use crate::collision::broad_phase::Grid;
use crate::collision::{Aabb, Hit, Primitive, Shape, Triangle};
use glam::DVec3;
use std::collections::HashMap;

/// Why triangles do not make a deposit surface.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// No triangle with an area.
    #[error("has no triangle with an area")]
    Empty,
}

/// A triangle mesh with a thickness per triangle. Cells are the triangles, in order; the
/// receiving side of each is the side its normal points to (right-handed in its corner order,
/// as STL and OBJ store outward faces).
#[derive(Clone, Debug)]
pub struct MeshSurface {
    triangles: Vec<Triangle>,
    area: Vec<f64>,
    centroid: Vec<DVec3>,
    /// Per triangle, per edge (corners k → k+1): the triangle across it and the edge's length;
    /// `u32::MAX` across a free edge (or one shared by more than two triangles).
    across: Vec<[(u32, f64); 3]>,
    /// Welded vertices and each triangle's corners among them.
    vertices: Vec<DVec3>,
    corners: Vec<[u32; 3]>,
    thickness: Vec<f64>,
    hits: Vec<u32>,
    changed: ChangedCells,
    max_thickness: f64,
    /// Distance from each centroid to the nearest free edge along the mesh, m.
    edge_distance: Vec<f64>,
    /// Triangles binned by their boxes grown by `reach`, for layer contacts and bare hits.
    index: Grid,
    reach: f64,
    bounds: Aabb,
}

/// Marker of "no triangle across this edge".
const NONE: u32 = u32::MAX;

impl MeshSurface {
    /// A mesh of `triangles` (degenerate ones are refused earlier, by [`Triangle::new`]).
    pub fn new(triangles: Vec<Triangle>) -> Result<MeshSurface, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::Empty);
        }
        let (vertices, corners) = weld(&triangles);
        let across = adjacency(&triangles, &corners);
        let area: Vec<f64> = triangles.iter().map(Triangle::area).collect();
        let centroid: Vec<DVec3> =
            triangles.iter().map(|t| (t.corners[0] + t.corners[1] + t.corners[2]) / 3.0).collect();
        let n = triangles.len();
        let bounds = triangles.iter().filter_map(Triangle::aabb).fold(
            Aabb { min: DVec3::INFINITY, max: DVec3::NEG_INFINITY },
            |b, t| Aabb { min: b.min.min(t.min), max: b.max.max(t.max) },
        );
        let mut mesh = MeshSurface {
            edge_distance: edge_distances(&triangles, &centroid, &across),
            triangles,
            area,
            centroid,
            across,
            vertices,
            corners,
            thickness: vec![0.0; n],
            hits: vec![0; n],
            changed: ChangedCells::new(n),
            max_thickness: 0.0,
            index: Grid::default(),
            reach: 0.0,
            bounds,
        };
        mesh.reindex(0.01);
        Ok(mesh)
    }

    /// The triangles, in cell order.
    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// Writes what deposition changes (thicknesses, impacts, bounds, changed cells, reach).
    pub(crate) fn save_state(&self, e: &mut Enc) {
        e.list(&self.thickness, |e, &x| e.f64(x));
        e.list(&self.hits, |e, &x| e.u32(x));
        e.list(&self.changed.0, |e, &x| e.u64(x));
        e.f64(self.max_thickness);
        e.f64(self.reach);
    }

    /// Reads what [`MeshSurface::save_state`] wrote, over a mesh with as many triangles.
    pub(crate) fn load_state(&mut self, d: &mut Dec<'_>) -> Result<(), StateError> {
        let n = self.thickness.len();
        self.thickness = d.list_of(n, "a mesh's thickness", 8, Dec::f64)?;
        self.hits = d.list_of(n, "a mesh's impacts", 4, Dec::u32)?;
        self.changed.0 = d.list_of(self.changed.0.len(), "a mesh's changes", 8, Dec::u64)?;
        self.max_thickness = d.f64()?;
        let reach = d.f64()?;
        if !(reach.is_finite() && reach > 0.0) {
            return Err(StateError::Mismatch(format!("a mesh's reach is {reach} m")));
        }
        // The index is a function of the reach: rebuilt, it is the one saved.
        if reach != self.reach {
            self.reindex(reach);
        }
        Ok(())
    }

    /// Re-bins the triangles with their boxes grown by `reach` (m) on every side.
    fn reindex(&mut self, reach: f64) {
        let boxes: Vec<Option<Aabb>> =
            self.triangles.iter().map(|t| t.aabb().map(|b| b.inflate(reach))).collect();
        self.index = Grid::new(&boxes, self.bounds.inflate(reach));
        self.reach = reach;
    }

    /// Keeps the bounds of the thickness and the index's reach above the thickest triangle.
    fn raised(&mut self, cell: usize) {
        let t = self.thickness[cell];
        self.changed.mark(cell);
        if t > self.max_thickness {
            self.max_thickness = t;
            if t > self.reach {
                self.reindex(2.0 * t);
            }
        }
    }

    /// The triangle `i` raised by its thickness along its normal.
    fn top(&self, i: usize) -> Triangle {
        let t = &self.triangles[i];
        let lift = t.normal * self.thickness[i];
        Triangle { corners: t.corners.map(|c| c + lift), normal: t.normal }
    }
}

/// Welds corners at identical positions: the shared vertices and each triangle's corners.
fn weld(triangles: &[Triangle]) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut at: HashMap<[u64; 3], u32> = HashMap::new();
    let mut vertices = Vec::new();
    let corners = triangles
        .iter()
        .map(|t| {
            t.corners.map(|p| {
                // + 0.0 makes −0.0 and 0.0 one corner.
                *at.entry((p + DVec3::ZERO).to_array().map(f64::to_bits)).or_insert_with(|| {
                    vertices.push(p);
                    (vertices.len() - 1) as u32
                })
            })
        })
        .collect();
    (vertices, corners)
}

/// For each triangle's edges, the triangle across each and the edge's length.
fn adjacency(triangles: &[Triangle], corners: &[[u32; 3]]) -> Vec<[(u32, f64); 3]> {
    let mut edges: HashMap<(u32, u32), Vec<(u32, usize)>> = HashMap::new();
    for (i, c) in corners.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (c[k], c[(k + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push((i as u32, k));
        }
    }
    let mut across: Vec<[(u32, f64); 3]> = triangles
        .iter()
        .map(|t| std::array::from_fn(|k| (NONE, t.corners[k].distance(t.corners[(k + 1) % 3]))))
        .collect();
    for sharing in edges.values() {
        if let [(i, ki), (j, kj)] = sharing[..] {
            across[i as usize][ki].0 = j;
            across[j as usize][kj].0 = i;
        }
    }
    across
}

/// Distance from `p` to the segment `a → b`, m.
fn to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let e = b - a;
    let f = ((p - a).dot(e) / e.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    p.distance(a + e * f)
}

/// Distance along the mesh from each centroid to the nearest free edge: from the triangles on
/// it inwards through the centroids (Dijkstra), m.
fn edge_distances(triangles: &[Triangle], centroid: &[DVec3], across: &[[(u32, f64); 3]]) -> Vec<f64> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let mut dist = vec![f64::INFINITY; triangles.len()];
    let mut heap = BinaryHeap::new();
    for (i, t) in triangles.iter().enumerate() {
        for (k, &(other, _)) in across[i].iter().enumerate() {
            if other == NONE {
                let d = to_segment(centroid[i], t.corners[k], t.corners[(k + 1) % 3]);
                dist[i] = dist[i].min(d);
            }
        }
        if dist[i].is_finite() {
            heap.push(Reverse((dist[i].to_bits(), i as u32)));
        }
    }
    // Distances are non-negative, so their bits order like the values.
    while let Some(Reverse((bits, i))) = heap.pop() {
        let d = f64::from_bits(bits);
        if d > dist[i as usize] {
            continue;
        }
        for &(j, _) in &across[i as usize] {
            if j == NONE {
                continue;
            }
            let nd = d + centroid[i as usize].distance(centroid[j as usize]);
            if nd < dist[j as usize] {
                dist[j as usize] = nd;
                heap.push(Reverse((nd.to_bits(), j)));
            }
        }
    }
    dist
}

impl DepositSurface for MeshSurface {
    fn colliders(&self) -> Vec<Shape> {
        self.triangles.iter().map(|&t| Shape::Triangle(t)).collect()
    }

    fn piece_of(&self, cell: u32) -> u32 {
        cell
    }

    /// Through the index of the triangles' boxes, not over every triangle.
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let mut best: Option<(u32, Hit)> = None;
        self.index.walk(p0, p1, |items| {
            for &i in items {
                if let Some(h) = self.triangles[i as usize].intersect(p0, p1)
                    && best.is_none_or(|(j, b)| h.t < b.t || (h.t == b.t && i < j))
                {
                    best = Some((i, h));
                }
            }
            best.map_or(f64::INFINITY, |(_, h)| h.t)
        });
        best.map(|(_, h)| h)
    }

    #[inline]
    fn cell_at(&self, piece: u32, _point: DVec3) -> u32 {
        piece
    }

    fn layer_contact(&self, p0: DVec3, p1: DVec3) -> Option<LayerContact> {
        if self.max_thickness <= 0.0
            || !Aabb::from_points(p0, p1).overlaps(&self.bounds.inflate(self.max_thickness))
        {
            return None;
        }
        let mut best: Option<(u32, f64, DVec3)> = None;
        self.index.walk(p0, p1, |items| {
            for &i in items {
                let iu = i as usize;
                if self.thickness[iu] <= 0.0 {
                    continue;
                }
                // Only from the receiving side: the raised top is entered from above it.
                let top = self.top(iu);
                let (d0, d1) = ((p0 - top.corners[0]).dot(top.normal), (p1 - top.corners[0]).dot(top.normal));
                if d0 <= 0.0 || d1 > 0.0 {
                    continue;
                }
                let s = d0 / (d0 - d1);
                let q = p0.lerp(p1, s);
                if top.covers(q) && best.is_none_or(|(j, b, _)| s < b || (s == b && i < j)) {
                    best = Some((i, s, q));
                }
            }
            best.map_or(f64::INFINITY, |(_, s, _)| s)
        });
        best.map(|(i, s, point)| LayerContact {
            s,
            point,
            normal: self.triangles[i as usize].normal,
            cell: i,
        })
    }

    #[inline]
    fn normal(&self, cell: u32) -> DVec3 {
        self.triangles[cell as usize].normal
    }

    fn point_above(&self, cell: u32, height: f64) -> DVec3 {
        self.centroid[cell as usize] + self.triangles[cell as usize].normal * height
    }

    #[inline]
    fn thickness(&self) -> &[f64] {
        &self.thickness
    }

    fn hits(&self) -> &[u32] {
        &self.hits
    }

    #[inline]
    fn cell_area(&self, cell: u32) -> f64 {
        self.area[cell as usize]
    }

    /// Kept as the layer grows, not found by visiting every cell.
    #[inline]
    fn max_thickness(&self) -> f64 {
        self.max_thickness
    }

    fn add_hits(&mut self, cell: u32, n: u32) {
        let h = &mut self.hits[cell as usize];
        *h = h.saturating_add(n);
    }

    fn neighbours(&self, cell: u32, visit: &mut dyn FnMut(u32, f64)) {
        for &(j, edge) in &self.across[cell as usize] {
            if j != NONE {
                visit(j, edge);
            }
        }
    }

    fn stencil(&self, cell: u32, visit: &mut dyn FnMut(Option<u32>, DVec3)) {
        let c = cell as usize;
        let t = &self.triangles[c];
        for k in 0..3 {
            let j = self.across[c][k].0;
            if j != NONE {
                visit(Some(j), self.centroid[j as usize]);
            } else {
                // Past a free edge: the centroid mirrored across it, in the triangle's plane.
                let (a, b) = (t.corners[k], t.corners[(k + 1) % 3]);
                let e = (b - a).normalize_or_zero();
                let foot = a + e * (self.centroid[c] - a).dot(e);
                visit(None, 2.0 * foot - self.centroid[c]);
            }
        }
    }

    fn edge_distance(&self, cell: u32) -> f64 {
        self.edge_distance[cell as usize]
    }

    fn add_thickness(&mut self, cell: u32, dt: f64) {
        let c = cell as usize;
        self.thickness[c] = (self.thickness[c] + dt).max(0.0);
        self.raised(c);
    }

    fn take_changed(&mut self) -> Vec<u32> {
        self.changed.take()
    }

    /// The mesh itself, its welded vertices carrying the area-weighted mean thickness and
    /// normal of the triangles around them (`max_cells` is not used: a mesh is not averaged
    /// down).
    fn mesh(&self, lift: bool, _max_cells: usize) -> SurfaceMesh {
        let nv = self.vertices.len();
        let (mut sum, mut weight, mut normal) = (vec![0.0; nv], vec![0.0; nv], vec![DVec3::ZERO; nv]);
        for (i, c) in self.corners.iter().enumerate() {
            for &v in c {
                let v = v as usize;
                sum[v] += self.thickness[i] * self.area[i];
                weight[v] += self.area[i];
                normal[v] += self.triangles[i].normal * self.area[i];
            }
        }
        let mut mesh = SurfaceMesh::default();
        for v in 0..nv {
            let t = if weight[v] > 0.0 { sum[v] / weight[v] } else { 0.0 };
            let n = normal[v].normalize_or_zero();
            mesh.positions.push(self.vertices[v] + if lift { n * t } else { DVec3::ZERO });
            mesh.normals.push(n);
            mesh.thickness.push(t);
        }
        mesh.triangles = self.corners.clone();
        mesh.cell = (0..self.triangles.len() as u32).collect();
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 1 m strip in the z = 0 plane facing +z: two unit squares, four triangles.
    fn strip() -> MeshSurface {
        let p = |x: f64, y: f64| DVec3::new(x, y, 0.0);
        let t = |a, b, c| Triangle::new(a, b, c).expect("a triangle");
        MeshSurface::new(vec![
            t(p(0.0, 0.0), p(1.0, 0.0), p(1.0, 1.0)),
            t(p(0.0, 0.0), p(1.0, 1.0), p(0.0, 1.0)),
            t(p(1.0, 0.0), p(2.0, 0.0), p(2.0, 1.0)),
            t(p(1.0, 0.0), p(2.0, 1.0), p(1.0, 1.0)),
        ])
        .expect("a mesh")
    }

    #[test]
    fn triangles_share_welded_edges_and_know_how_far_the_free_edges_are() {
        let m = strip();
        assert_eq!(m.vertices.len(), 6, "corners at the same place are one vertex");
        let mut seen = Vec::new();
        m.neighbours(0, &mut |n, edge| seen.push((n, edge)));
        // Triangle 0 shares its diagonal with 1 and its right edge with 3.
        seen.sort_by_key(|s| s.0);
        assert_eq!(seen.len(), 2);
        assert!(seen[0].0 == 1 && (seen[0].1 - 2f64.sqrt()).abs() < 1e-12);
        assert!(seen[1].0 == 3 && (seen[1].1 - 1.0).abs() < 1e-12);
        // Past a free edge the stencil mirrors the centroid: below the bottom edge of 0.
        let mut ghosts = Vec::new();
        m.stencil(0, &mut |k, c| {
            if k.is_none() {
                ghosts.push(c)
            }
        });
        assert_eq!(ghosts.len(), 1);
        assert!(ghosts[0].abs_diff_eq(DVec3::new(2.0 / 3.0, -1.0 / 3.0, 0.0), 1e-12), "{}", ghosts[0]);
        // Every triangle touches the free boundary or lies a centroid away from it.
        assert!((m.edge_distance(0) - 1.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn deposits_are_volume_over_area_and_the_layer_is_struck_on_its_raised_top() {
        let mut m = strip();
        m.deposit(2, 0.05); // 0.1 m on a 0.5 m² triangle
        assert!((m.thickness()[2] - 0.1).abs() < 1e-15 && (m.volume() - 0.05).abs() < 1e-15);
        // A drop onto triangle 2 meets its top 0.1 m up; one onto triangle 0 the bare mesh.
        let c =
            m.layer_contact(DVec3::new(1.8, 0.2, 1.0), DVec3::new(1.8, 0.2, -1.0)).expect("the raised top");
        assert!((c.point.z - 0.1).abs() < 1e-12 && c.cell == 2 && c.normal == DVec3::Z);
        assert!(m.layer_contact(DVec3::new(0.8, 0.2, 1.0), DVec3::new(0.8, 0.2, -1.0)).is_none());
        // From below (the back), no layer.
        assert!(m.layer_contact(DVec3::new(1.8, 0.2, -1.0), DVec3::new(1.8, 0.2, 1.0)).is_none());
        // The bare surface, found through the index.
        let hit = m.intersect(DVec3::new(0.5, 0.5, 1.0), DVec3::new(0.5, 0.5, -1.0)).expect("the strip");
        assert!(hit.point.z.abs() < 1e-12);
        // The exported mesh: welded vertices, each the area-weighted mean of its triangles.
        let mesh = m.mesh(true, usize::MAX);
        assert_eq!((mesh.positions.len(), mesh.triangles.len()), (6, 4));
        let far = mesh.positions.iter().position(|p| p.x == 2.0 && p.y == 0.0).expect("a corner");
        assert!((mesh.thickness[far] - 0.1).abs() < 1e-15, "only triangle 2 touches (2, 0)");
    }
}
