//! A rectangular face with a regular heightfield: walls, floors, ceilings, panels.

use super::{DepositSurface, HeightField, LayerContact, Layout, SurfaceMesh};
use crate::collision::{Face, Shape};
use glam::DVec3;

/// A rectangle that collects deposit in a heightfield. Rows grow along the face's `up`, columns
/// along its `right` (`up × normal`, the viewer's right looking at the face from the spray side);
/// row 0 is the bottom edge.
#[derive(Clone, Debug)]
pub struct RectangleSurface {
    /// Geometry; the normal points to the receiving side.
    pub face: Face,
    /// Thickness and impacts per cell.
    pub field: HeightField,
    /// The edges hold the layer (formwork, a floor under a wall): nothing flows over them.
    pub held_edges: bool,
}

impl RectangleSurface {
    /// A rectangle over `face` with `cols × rows` cells; each stuck particle's volume spreads
    /// over the cells within `splat_radius` (m) of the struck cell's centre.
    pub fn new(face: Face, cols: usize, rows: usize, splat_radius: f64) -> Self {
        let field = HeightField::new(2.0 * face.half_width, 2.0 * face.half_height, cols, rows, splat_radius);
        RectangleSurface { face, field, held_edges: false }
    }

    /// The same surface with its edges held (`true`) or free.
    pub fn with_held_edges(self, held: bool) -> Self {
        RectangleSurface { held_edges: held, ..self }
    }
}

impl DepositSurface for RectangleSurface {
    fn collider(&self) -> Shape {
        Shape::Face(self.face)
    }

    #[inline]
    fn receives(&self, normal: DVec3) -> bool {
        normal.dot(self.face.normal) > 0.0
    }

    #[inline]
    fn cell_at(&self, point: DVec3) -> u32 {
        let (u, v) = self.face.local(point);
        self.field.cell_at(u, v)
    }

    #[inline]
    fn layer_contact(&self, p0: DVec3, p1: DVec3) -> Option<LayerContact> {
        self.field.layer_contact(&self.face, p0, p1)
    }

    #[inline]
    fn normal(&self, _cell: u32) -> DVec3 {
        self.face.normal
    }

    fn uniform_normal(&self) -> Option<DVec3> {
        Some(self.face.normal)
    }

    fn point_above(&self, cell: u32, height: f64) -> DVec3 {
        let (u, v) = self.field.cell_center(cell);
        self.face.point(u, v, height)
    }

    #[inline]
    fn thickness(&self) -> &[f64] {
        self.field.thickness()
    }

    fn mean_thickness(&self, cell: u32, radius: f64) -> f64 {
        self.field.mean_around(cell, radius)
    }

    fn hits(&self) -> &[u32] {
        self.field.hits()
    }

    #[inline]
    fn cell_area(&self, _cell: u32) -> f64 {
        self.field.cell_area()
    }

    fn area_of(&self, cells: &[u32]) -> f64 {
        cells.len() as f64 * self.field.cell_area()
    }

    #[inline]
    fn max_thickness(&self) -> f64 {
        self.field.max_thickness()
    }

    fn volume(&self) -> f64 {
        self.field.volume()
    }

    fn add_hit(&mut self, cell: u32) {
        self.field.add_hit(cell);
    }

    fn deposit(&mut self, cell: u32, volume: f64) {
        self.field.deposit(cell, volume);
    }

    fn remove(&mut self, cell: u32, volume: f64) -> f64 {
        self.field.remove(cell, volume)
    }

    fn neighbours(&self, cell: u32, visit: &mut dyn FnMut(u32, f64)) {
        let (cols, rows) = (self.field.cols(), self.field.rows());
        let (dx, dy) = self.field.cell_size();
        let c = cell as usize;
        let (r, col) = (c / cols, c % cols);
        // Edges first, left, right, below, above: the order cohesion sums what holds a region.
        let (left, right, below, above) = (col > 0, col + 1 < cols, r > 0, r + 1 < rows);
        let edges = [
            (left, c.wrapping_sub(1), dy),
            (right, c + 1, dy),
            (below, c.wrapping_sub(cols), dx),
            (above, c + cols, dx),
        ];
        for (inside, n, edge) in edges {
            if inside {
                visit(n as u32, edge);
            }
        }
        let corners = [
            (left && below, c.wrapping_sub(cols + 1)),
            (right && below, c.wrapping_sub(cols).wrapping_add(1)),
            (left && above, c + cols - 1),
            (right && above, c + cols + 1),
        ];
        for (inside, n) in corners {
            if inside {
                visit(n as u32, 0.0);
            }
        }
    }

    fn stencil(&self, cell: u32, visit: &mut dyn FnMut(Option<u32>, DVec3)) {
        let (cols, rows) = (self.field.cols() as isize, self.field.rows() as isize);
        let (dx, dy) = self.field.cell_size();
        let (r, c) = (cell as isize / cols, cell as isize % cols);
        let (u, v) = self.field.cell_center(cell);
        for (dr, dc) in [(0, -1), (0, 1), (-1, 0), (1, 0), (-1, -1), (-1, 1), (1, -1), (1, 1)] {
            let (rr, cc) = (r + dr, c + dc);
            let inside = (0..rows).contains(&rr) && (0..cols).contains(&cc);
            if !inside && self.held_edges {
                continue;
            }
            let centre = self.face.point(u + dc as f64 * dx, v + dr as f64 * dy, 0.0);
            visit(inside.then(|| (rr * cols + cc) as u32), centre);
        }
    }

    fn spacing(&self, _cell: u32) -> f64 {
        let (dx, dy) = self.field.cell_size();
        dx.min(dy)
    }

    fn add_thickness(&mut self, cell: u32, dt: f64) {
        self.field.add(cell, dt);
    }

    fn take_changed(&mut self) -> Vec<u32> {
        self.field.take_changed()
    }

    fn layout(&self) -> Layout {
        Layout::Grid { rows: self.field.rows(), cols: self.field.cols(), cell: self.field.cell_size() }
    }

    fn mesh(&self, lift: bool, max_cells: usize) -> SurfaceMesh {
        let (cols, rows) = (self.field.cols(), self.field.rows());
        // The smallest whole factor that brings the cell count under the limit.
        let mut k = 1;
        while (cols.div_ceil(k) * rows.div_ceil(k)) > max_cells.max(1) {
            k += 1;
        }
        let (mc, mr) = (cols.div_ceil(k), rows.div_ceil(k));
        // Mean thickness of each block of k × k cells.
        let t = self.field.thickness();
        let mut block = vec![(0.0, 0.0); mc * mr];
        for r in 0..rows {
            for c in 0..cols {
                let b = &mut block[(r / k) * mc + c / k];
                *b = (b.0 + t[r * cols + c], b.1 + 1.0);
            }
        }
        let block: Vec<f64> = block.iter().map(|&(s, n)| s / n).collect();
        // Vertices at the block corners, each with the mean of the blocks that touch it.
        let (w, h) = (2.0 * self.face.half_width, 2.0 * self.face.half_height);
        let mut mesh = SurfaceMesh::default();
        for vr in 0..=mr {
            for vc in 0..=mc {
                let (mut sum, mut n) = (0.0, 0.0);
                for (br, bc) in [
                    (vr.wrapping_sub(1), vc.wrapping_sub(1)),
                    (vr.wrapping_sub(1), vc),
                    (vr, vc.wrapping_sub(1)),
                    (vr, vc),
                ] {
                    if br < mr && bc < mc {
                        sum += block[br * mc + bc];
                        n += 1.0;
                    }
                }
                let thickness = sum / n;
                let u = ((vc * k).min(cols) as f64 / cols as f64 - 0.5) * w;
                let v = ((vr * k).min(rows) as f64 / rows as f64 - 0.5) * h;
                mesh.positions.push(self.face.point(u, v, if lift { thickness } else { 0.0 }));
                mesh.normals.push(self.face.normal);
                mesh.thickness.push(thickness);
            }
        }
        let at = |r: usize, c: usize| (r * (mc + 1) + c) as u32;
        for br in 0..mr {
            for bc in 0..mc {
                // right × up = normal: (c, r) → (c+1, r) → (c+1, r+1) turns counter-clockwise
                // seen from the normal's side.
                let (a, b, c, d) = (at(br, bc), at(br, bc + 1), at(br + 1, bc + 1), at(br + 1, bc));
                let cell = ((br * k) * cols + bc * k) as u32;
                mesh.triangles.extend([[a, b, c], [a, c, d]]);
                mesh.cell.extend([cell, cell]);
            }
        }
        mesh
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wall() -> RectangleSurface {
        // 2 m wide, 1 m high, facing −x; 4 × 2 cells of 0.5 m.
        RectangleSurface::new(
            Face::new(DVec3::new(0.0, 0.0, 1.0), DVec3::NEG_X, DVec3::Z, [2.0, 1.0]),
            4,
            2,
            0.0,
        )
    }

    #[test]
    fn impacts_map_to_cells_and_cells_back_to_points_on_the_receiving_side() {
        let w = wall();
        for cell in 0..8 {
            let p = w.point_above(cell, 0.01);
            assert_eq!(w.cell_at(p), cell, "cell {cell} at {p}");
            assert!((p.x + 0.01).abs() < 1e-12, "raised towards the spray side: {p}");
        }
        // Row 0 is the bottom edge, columns grow along right = up × normal = −y.
        assert_eq!(w.cell_at(DVec3::new(0.0, 0.9, 0.6)), 0);
        assert_eq!(w.cell_at(DVec3::new(0.0, -0.9, 1.4)), 7);
        assert!(w.receives(DVec3::NEG_X) && !w.receives(DVec3::X));
        assert_eq!(w.normal(3), DVec3::NEG_X);
        assert_eq!(w.uniform_normal(), Some(DVec3::NEG_X));
    }

    #[test]
    fn neighbours_list_shared_edges_first_then_corners() {
        let w = wall();
        let mut seen = Vec::new();
        w.neighbours(1, &mut |n, edge| seen.push((n, edge)));
        // Cell 1 (row 0, col 1): left 0, right 2 (edges of 1 m / 2 rows = 0.5 m high), above 5
        // (0.5 m wide), corners 4 and 6.
        assert_eq!(seen, [(0, 0.5), (2, 0.5), (5, 0.5), (4, 0.0), (6, 0.0)]);
        let mut corner = Vec::new();
        w.neighbours(7, &mut |n, edge| corner.push((n, edge)));
        assert_eq!(corner, [(6, 0.5), (3, 0.5), (2, 0.0)]);
    }

    #[test]
    fn deposits_and_removals_conserve_volume_and_areas_add_up() {
        let mut w = wall();
        w.deposit(5, 0.01);
        w.deposit(5, 0.02);
        assert!((w.volume() - 0.03).abs() < 1e-15);
        assert!((w.thickness()[5] - 0.03 / 0.25).abs() < 1e-15);
        assert!((w.remove(5, 0.05) - 0.03).abs() < 1e-15, "no more than there is");
        assert_eq!(w.volume(), 0.0);
        assert_eq!(w.area_of(&[0, 1, 2]), 0.75);
        assert_eq!(w.layout(), Layout::Grid { rows: 2, cols: 4, cell: (0.5, 0.5) });
    }

    #[test]
    fn the_mesh_covers_the_face_faces_the_spray_and_carries_the_layer() {
        let mut w = wall();
        w.deposit(5, 0.25 * 0.1); // 0.1 m on cell 5 (row 1, column 1)
        let m = w.mesh(true, usize::MAX);
        assert_eq!((m.positions.len(), m.triangles.len()), (15, 16));
        // Every triangle turns counter-clockwise seen from the spray side (the face's normal).
        for t in &m.triangles {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            assert!((b - a).cross(c - a).dot(w.face.normal) > 0.0, "{t:?}");
        }
        // The corners span the face; the vertices around cell 5 are raised along the normal.
        let (lo, hi) = m
            .positions
            .iter()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), &p| (l.min(p), h.max(p)));
        assert!((hi.y - lo.y - 2.0).abs() < 1e-12 && (hi.z - lo.z - 1.0).abs() < 1e-12);
        let top = m.thickness.iter().copied().fold(0.0, f64::max);
        assert!((top - 0.1 / 2.0).abs() < 1e-12, "a vertex shared by two cells averages them: {top}");
        assert!(m.positions.iter().zip(&m.thickness).all(|(p, t)| (p.x + t).abs() < 1e-12));
        assert_eq!(m.cell.iter().filter(|&&c| c == 5).count(), 2);
        // Averaged down to at most 2 cells: blocks of 2 × 2.
        let coarse = w.mesh(false, 2);
        assert_eq!(coarse.triangles.len(), 4);
        assert!(coarse.positions.iter().all(|p| p.x == 0.0), "not lifted");
    }
}
