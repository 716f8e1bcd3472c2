//! A rectangular face with a regular heightfield: walls, floors, ceilings, panels.

use super::{DepositSurface, HeightField, LayerContact, Layout};
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
}

impl RectangleSurface {
    /// A rectangle over `face` with `cols × rows` cells; each stuck particle's volume spreads
    /// over the cells within `splat_radius` (m) of the struck cell's centre.
    pub fn new(face: Face, cols: usize, rows: usize, splat_radius: f64) -> Self {
        let field = HeightField::new(2.0 * face.half_width, 2.0 * face.half_height, cols, rows, splat_radius);
        RectangleSurface { face, field }
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

    fn layout(&self) -> Layout {
        Layout::Grid { rows: self.field.rows(), cols: self.field.cols(), cell: self.field.cell_size() }
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
}
