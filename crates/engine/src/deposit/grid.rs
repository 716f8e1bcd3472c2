//! Heightfields on unrolled surfaces: a rectangle (walls, floors, ceilings, panels) or a
//! cylindrical shell (tunnel linings, shafts, pipes, tanks), optionally with openings.

use super::openings::Perforated;
use super::{
    Chart, Clearance, DepositSurface, HeightField, LayerContact, Layout, Opening, ShellChart, SurfaceMesh,
};
use crate::collision::{Aabb, Face, Hit, Primitive, Shape};
use glam::DVec3;
use std::sync::Arc;

/// A surface with a regular heightfield over its unrolled coordinates. Rows grow along the
/// chart's `v` (a face's `up`, a shell's axis), columns along its `u` (the viewer's right, seen
/// from the receiving side); row 0 is the bottom edge.
#[derive(Clone, Debug)]
pub struct GridSurface<C: Chart> {
    /// How the grid lies on the bare surface; its normal points to the receiving side.
    pub chart: C,
    /// Thickness and impacts per cell.
    pub field: HeightField,
    /// The edges hold the layer (formwork, a floor under a wall): nothing flows over them.
    pub held_edges: bool,
    openings: Vec<Opening>,
}

/// A rectangle that collects deposit in a heightfield.
pub type RectangleSurface = GridSurface<Face>;

/// A cylindrical shell that collects deposit in a heightfield over its unrolled surface.
pub type CylinderSurface = GridSurface<ShellChart>;

impl<C: Chart> GridSurface<C> {
    /// A surface over `chart` with `cols × rows` cells; each stuck particle's volume spreads
    /// over the cells within `splat_radius` (m) of the struck cell's centre.
    pub fn new(chart: C, cols: usize, rows: usize, splat_radius: f64) -> Self {
        let (w, h) = chart.size();
        let mut field = HeightField::new(w, h, cols, rows, splat_radius);
        field.set_wrap(chart.wraps());
        GridSurface { chart, field, held_edges: false, openings: Vec::new() }
    }

    /// The same surface with its edges held (`true`) or free.
    pub fn with_held_edges(self, held: bool) -> Self {
        GridSurface { held_edges: held, ..self }
    }

    /// The same surface with `openings` cut out: the cells whose centre lies in one carry no
    /// surface, and particles pass through.
    pub fn with_openings(mut self, openings: Vec<Opening>) -> Self {
        let cells = self.field.thickness().len() as u32;
        let hole = (0..cells)
            .map(|c| {
                let (u, v) = self.field.cell_center(c);
                openings.iter().any(|o| o.contains(u, v))
            })
            .collect();
        self.field.set_holes(hole);
        GridSurface { openings, ..self }
    }

    /// The openings cut out of the surface.
    pub fn openings(&self) -> &[Opening] {
        &self.openings
    }

    /// The solid cell nearest `(u, v)`, starting from `cell`: a point on the surface near an
    /// opening's edge may lie in a cell whose centre the opening covers.
    fn solid(&self, cell: u32, u: f64, v: f64) -> u32 {
        if !self.field.is_hole(cell) {
            return cell;
        }
        let (cols, rows) = (self.field.cols() as isize, self.field.rows() as isize);
        let (r0, c0) = (cell as isize / cols, cell as isize % cols);
        for reach in 1..cols.max(rows) {
            let mut best: Option<(f64, u32)> = None;
            for r in (r0 - reach).max(0)..=(r0 + reach).min(rows - 1) {
                for c in (c0 - reach).max(0)..=(c0 + reach).min(cols - 1) {
                    let k = (r * cols + c) as u32;
                    if (r - r0).abs().max((c - c0).abs()) != reach || self.field.is_hole(k) {
                        continue;
                    }
                    let (cu, cv) = self.field.cell_center(k);
                    let d = (cu - u).hypot(cv - v);
                    if best.is_none_or(|(bd, bk)| d < bd || (d == bd && k < bk)) {
                        best = Some((d, k));
                    }
                }
            }
            if let Some((_, k)) = best {
                return k;
            }
        }
        cell
    }

    fn shape(&self) -> Shape {
        if self.openings.is_empty() {
            self.chart.shape()
        } else {
            Shape::Custom(Arc::new(Perforated {
                chart: self.chart.clone(),
                shape: self.chart.shape(),
                openings: self.openings.clone(),
            }))
        }
    }
}

impl<C: Chart> DepositSurface for GridSurface<C> {
    fn colliders(&self) -> Vec<Shape> {
        vec![self.shape()]
    }

    fn piece_of(&self, _cell: u32) -> u32 {
        0
    }

    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        self.shape().intersect(p0, p1)
    }

    #[inline]
    fn receives(&self, _piece: u32, point: DVec3, normal: DVec3) -> bool {
        let n = self.chart.uniform_normal().unwrap_or_else(|| {
            let (u, v, _) = self.chart.local(point);
            self.chart.frame(u, v).0
        });
        normal.dot(n) > 0.0
    }

    #[inline]
    fn cell_at(&self, _piece: u32, point: DVec3) -> u32 {
        let (u, v, _) = self.chart.local(point);
        self.solid(self.field.cell_at(u, v), u, v)
    }

    #[inline]
    fn layer_contact(&self, p0: DVec3, p1: DVec3) -> Option<LayerContact> {
        // A contact by an opening's edge is booked to the solid cell beside it.
        let mut contact = self.field.layer_contact(&self.chart, p0, p1)?;
        let (u, v, _) = self.chart.local(contact.point);
        contact.cell = self.solid(contact.cell, u, v);
        Some(contact)
    }

    fn layer_clearance(&self, b: &Aabb, ceiling: f64) -> Clearance {
        // On a flat surface the height above it and the in-face coordinates are affine, so the
        // box's corners bound them over the box.
        if self.chart.uniform_normal().is_none() {
            return Clearance::Unknown;
        }
        let (lo, hi) = self.chart.box_range(b);
        let (w, h) = self.chart.size();
        if hi.z < 0.0 || hi.x < -0.5 * w || lo.x > 0.5 * w || hi.y < -0.5 * h || lo.y > 0.5 * h {
            return Clearance::Free;
        }
        if lo.z > ceiling {
            return Clearance::Above { height: lo.z, top: self.field.max_thickness() };
        }
        let (nodes, top) = self.field.nodes_under((lo.x, hi.x), (lo.y, hi.y));
        Clearance::Over { nodes, height: lo.z, top }
    }

    #[inline]
    fn node_bound(&self, level: u32, col: u32, row: u32) -> f64 {
        self.field.node_bound(level, col, row)
    }

    #[inline]
    fn normal(&self, cell: u32) -> DVec3 {
        match self.chart.uniform_normal() {
            Some(n) => n,
            None => {
                let (u, v) = self.field.cell_center(cell);
                self.chart.frame(u, v).0
            }
        }
    }

    fn uniform_normal(&self) -> Option<DVec3> {
        self.chart.uniform_normal()
    }

    fn point_above(&self, cell: u32, height: f64) -> DVec3 {
        let (u, v) = self.field.cell_center(cell);
        self.chart.point(u, v, height)
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
    fn cell_area(&self, cell: u32) -> f64 {
        if self.field.is_hole(cell) { 0.0 } else { self.field.cell_area() }
    }

    fn area_of(&self, cells: &[u32]) -> f64 {
        cells.iter().filter(|&&c| !self.field.is_hole(c)).count() as f64 * self.field.cell_area()
    }

    #[inline]
    fn max_thickness(&self) -> f64 {
        self.field.max_thickness()
    }

    fn volume(&self) -> f64 {
        self.field.volume()
    }

    fn add_hits(&mut self, cell: u32, n: u32) {
        self.field.add_hits(cell, n);
    }

    fn footprint(&self, cell: u32, visit: &mut dyn FnMut(u32)) {
        let (u, v) = self.field.cell_center(cell);
        self.field.footprint(self.solid(cell, u, v), visit);
    }

    fn deposit(&mut self, cell: u32, volume: f64) {
        let (u, v) = self.field.cell_center(cell);
        let cell = self.solid(cell, u, v);
        self.field.deposit(cell, volume);
    }

    fn remove(&mut self, cell: u32, volume: f64) -> f64 {
        self.field.remove(cell, volume)
    }

    fn neighbours(&self, cell: u32, visit: &mut dyn FnMut(u32, f64)) {
        let (cols, rows) = (self.field.cols(), self.field.rows());
        let (dx, dy) = self.field.cell_size();
        let (r, col) = (cell as usize / cols, cell as usize % cols);
        // Edges first, left, right, below, above: the order cohesion sums what holds a region.
        let steps = [
            (-1, 0, dy),
            (1, 0, dy),
            (0, -1, dx),
            (0, 1, dx),
            (-1, -1, 0.0),
            (1, -1, 0.0),
            (-1, 1, 0.0),
            (1, 1, 0.0),
        ];
        for (dc, dr, edge) in steps {
            let rr = r as isize + dr;
            let Some(cc) = self.field.column(col as isize + dc) else { continue };
            if (0..rows as isize).contains(&rr) {
                let n = (rr as usize * cols + cc) as u32;
                if !self.field.is_hole(n) {
                    visit(n, edge);
                }
            }
        }
    }

    fn stencil(&self, cell: u32, visit: &mut dyn FnMut(Option<u32>, DVec3)) {
        let (cols, rows) = (self.field.cols() as isize, self.field.rows() as isize);
        let (dx, dy) = self.field.cell_size();
        let (r, c) = (cell as isize / cols, cell as isize % cols);
        let (u, v) = self.field.cell_center(cell);
        for (dr, dc) in [(0, -1), (0, 1), (-1, 0), (1, 0), (-1, -1), (-1, 1), (1, -1), (1, 1)] {
            let rr = r + dr;
            let column = self.field.column(c + dc);
            let inside = (0..rows).contains(&rr) && column.is_some();
            if !inside && self.held_edges {
                continue;
            }
            // Into an opening the layer runs off, as over a free edge.
            let k = column
                .filter(|_| inside)
                .map(|cc| (rr * cols + cc as isize) as u32)
                .filter(|&k| !self.field.is_hole(k));
            let centre = self.chart.point(u + dc as f64 * dx, v + dr as f64 * dy, 0.0);
            visit(k, centre);
        }
    }

    fn spacing(&self, _cell: u32) -> f64 {
        let (dx, dy) = self.field.cell_size();
        dx.min(dy)
    }

    fn drop_bound(&self, cell: u32, up: DVec3) -> f64 {
        // Flat: every neighbour lies in the plane, at most as steep as the plane.
        match self.chart.uniform_normal() {
            Some(n) => (1.0 - n.dot(up).powi(2)).max(0.0).sqrt(),
            None => {
                let own = self.point_above(cell, 0.0);
                let mut most = 0.0_f64;
                self.stencil(cell, &mut |_, centre| {
                    most = most.max((own - centre).dot(up) / centre.distance(own))
                });
                most
            }
        }
    }

    fn edge_distance(&self, cell: u32) -> f64 {
        let (u, v) = self.field.cell_center(cell);
        let (w, h) = self.chart.size();
        // Across the seam of a full turn the surface goes on.
        let across = if self.chart.wraps() { f64::INFINITY } else { 0.5 * w - u.abs() };
        let border = across.min(0.5 * h - v.abs());
        self.openings.iter().map(|o| o.distance(u, v)).fold(border, f64::min)
    }

    fn add_thickness(&mut self, cell: u32, dt: f64) {
        self.field.add(cell, dt);
    }

    fn take_changed(&mut self) -> Vec<u32> {
        self.field.take_changed()
    }

    fn layout(&self) -> Layout {
        Layout::Grid {
            rows: self.field.rows(),
            cols: self.field.cols(),
            cell: self.field.cell_size(),
            axes: self.chart.axes(),
        }
    }

    fn mesh(&self, lift: bool, max_cells: usize) -> SurfaceMesh {
        grid_mesh(self, lift, max_cells)
    }
}

/// The triangle mesh of a grid surface, averaged down by a whole factor `k` so that it has at
/// most about `max_cells` blocks of `k × k` cells; blocks wholly cut away are left out.
fn grid_mesh<C: Chart>(s: &GridSurface<C>, lift: bool, max_cells: usize) -> SurfaceMesh {
    let f = &s.field;
    let (cols, rows) = (f.cols(), f.rows());
    // The smallest whole factor that brings the cell count under the limit.
    let mut k = 1;
    while (cols.div_ceil(k) * rows.div_ceil(k)) > max_cells.max(1) {
        k += 1;
    }
    let (mc, mr) = (cols.div_ceil(k), rows.div_ceil(k));
    // Mean thickness of the solid cells of each block of k × k cells (`None`: all cut away).
    let t = f.thickness();
    let mut sum = vec![(0.0, 0.0); mc * mr];
    for r in 0..rows {
        for c in 0..cols {
            if !f.is_hole((r * cols + c) as u32) {
                let b = &mut sum[(r / k) * mc + c / k];
                *b = (b.0 + t[r * cols + c], b.1 + 1.0);
            }
        }
    }
    let block: Vec<Option<f64>> = sum.iter().map(|&(s, n)| (n > 0.0).then(|| s / n)).collect();
    // Vertices at the block corners, each with the mean of the solid blocks that touch it.
    let (w, h) = s.chart.size();
    let mut mesh = SurfaceMesh { block: k, ..SurfaceMesh::default() };
    for vr in 0..=mr {
        for vc in 0..=mc {
            let around = [
                (vr.wrapping_sub(1), vc.wrapping_sub(1)),
                (vr.wrapping_sub(1), vc),
                (vr, vc.wrapping_sub(1)),
                (vr, vc),
            ];
            let (total, n) = around
                .iter()
                .filter(|&&(br, bc)| br < mr && bc < mc)
                .filter_map(|&(br, bc)| block[br * mc + bc])
                .fold((0.0, 0.0), |(t, n), b| (t + b, n + 1.0));
            let thickness = if n > 0.0 { total / n } else { 0.0 };
            let u = ((vc * k).min(cols) as f64 / cols as f64 - 0.5) * w;
            let v = ((vr * k).min(rows) as f64 / rows as f64 - 0.5) * h;
            mesh.positions.push(s.chart.point(u, v, if lift { thickness } else { 0.0 }));
            mesh.normals.push(s.chart.frame(u, v).0);
            mesh.thickness.push(thickness);
        }
    }
    let at = |r: usize, c: usize| (r * (mc + 1) + c) as u32;
    for br in 0..mr {
        for bc in 0..mc {
            if block[br * mc + bc].is_none() {
                continue;
            }
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
            assert_eq!(w.cell_at(0, p), cell, "cell {cell} at {p}");
            assert!((p.x + 0.01).abs() < 1e-12, "raised towards the spray side: {p}");
        }
        // Row 0 is the bottom edge, columns grow along right = up × normal = −y.
        assert_eq!(w.cell_at(0, DVec3::new(0.0, 0.9, 0.6)), 0);
        assert_eq!(w.cell_at(0, DVec3::new(0.0, -0.9, 1.4)), 7);
        assert!(w.receives(0, DVec3::ZERO, DVec3::NEG_X) && !w.receives(0, DVec3::ZERO, DVec3::X));
        assert_eq!(w.normal(3), DVec3::NEG_X);
        assert_eq!(w.uniform_normal(), Some(DVec3::NEG_X));
    }

    /// A box over the wall is answered with the nodes under it at or below the ceiling, and
    /// without them above it, with the same least height and a bound of the whole layer.
    #[test]
    fn a_box_above_the_ceiling_needs_no_nodes() {
        let mut w = wall();
        w.field.deposit(5, 0.02 * w.field.cell_area());
        // 0.1 m to 0.2 m in front of the wall (its receiving side faces −x), over cells 5 and 6.
        let b = Aabb { min: DVec3::new(-0.2, -0.4, 1.1), max: DVec3::new(-0.1, 0.4, 1.3) };
        let Clearance::Over { height, top, .. } = w.layer_clearance(&b, f64::INFINITY) else {
            panic!("the box is over the wall")
        };
        assert!((height - 0.1).abs() < 1e-12 && (top - 0.02).abs() < 1e-12, "{height} {top}");
        assert!(matches!(w.layer_clearance(&b, 0.1 + 1e-9), Clearance::Over { .. }));
        match w.layer_clearance(&b, 0.05) {
            Clearance::Above { height: h, top: t } => assert!(h == height && t >= top, "{h} {t}"),
            other => panic!("{other:?}"),
        }
        // Behind the wall or beside it nothing can reach the box, whatever the ceiling.
        let behind = Aabb { min: DVec3::new(0.1, -0.4, 1.1), max: DVec3::new(0.2, 0.4, 1.3) };
        assert_eq!(w.layer_clearance(&behind, 0.05), Clearance::Free);
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
        assert!(matches!(w.layout(), Layout::Grid { rows: 2, cols: 4, cell: (0.5, 0.5), .. }));
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
            assert!((b - a).cross(c - a).dot(w.chart.normal) > 0.0, "{t:?}");
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

#[cfg(test)]
mod openings {
    use super::*;

    /// A 1 m square floor of 10 cm cells with a 34 cm window at its centre.
    fn floor() -> RectangleSurface {
        let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
        RectangleSurface::new(face, 10, 10, 0.15)
            .with_openings(vec![Opening::rectangle((0.0, 0.0), (0.34, 0.34))])
    }

    #[test]
    fn cells_in_an_opening_carry_no_surface_and_deposits_keep_out_of_them() {
        let mut f = floor();
        let holes: Vec<u32> = (0..100).filter(|&c| f.cell_area(c) == 0.0).collect();
        // Cell centres at ±0.05 and ±0.15 m: the 4 × 4 cells within 0.17 m of the middle.
        let expected: Vec<u32> = (3..7).flat_map(|r| (3..7).map(move |c| r * 10 + c)).collect();
        assert_eq!(holes, expected);
        // A splat next to the window spreads over solid cells only, keeping all its volume.
        f.deposit(32, 1e-3);
        assert!((f.volume() - 1e-3).abs() < 1e-15 && holes.iter().all(|&c| f.thickness()[c as usize] == 0.0));
        // A hit on the solid rim of a cell whose centre the opening covers settles beside it.
        let cell = f.cell_at(0, DVec3::new(0.0, -0.18, 0.0));
        assert_eq!(cell, 24, "the cell below the rim's");
        // Particles pass through the window, and strike around it.
        let shape = &f.colliders()[0];
        assert!(shape.intersect(DVec3::new(0.05, 0.05, 1.0), DVec3::new(0.05, 0.05, -1.0)).is_none());
        assert!(shape.intersect(DVec3::new(0.4, 0.05, 1.0), DVec3::new(0.4, 0.05, -1.0)).is_some());
        // Openings are edges: of the statistics' margin, and of the slumping layer.
        assert!((f.edge_distance(32) - 0.08).abs() < 1e-12, "{}", f.edge_distance(32));
        let mut ghosts = 0;
        f.stencil(32, &mut |k, _| ghosts += usize::from(k.is_none()));
        assert_eq!(ghosts, 2, "right and up-right lie in the window");
    }
}

#[cfg(test)]
mod full_turn {
    use super::*;
    use crate::collision::CylinderShell;
    use std::f64::consts::PI;

    /// A tank's wall seen from outside: a full turn of 36 columns (10°) by 10 rows, 1 m radius,
    /// 1 m long, its seam (angle ±180°) on the side away from the reference direction.
    fn tank(angles: [f64; 2]) -> CylinderSurface {
        let shell = CylinderShell::new(DVec3::ZERO, DVec3::Z, DVec3::X, 1.0, 1.0, angles).expect("valid");
        CylinderSurface::new(ShellChart { shell, inside: false }, 36, 10, 0.3)
    }

    #[test]
    fn a_full_turn_has_no_edge_at_its_seam() {
        let mut t = tank([-PI, PI]);
        let seam = 5 * 36; // column 0 of the middle row, next to the seam
        let mut seen = Vec::new();
        t.neighbours(seam, &mut |n, _| seen.push(n));
        assert!(seen.contains(&(5 * 36 + 35)), "the last column is across the seam: {seen:?}");
        let mut ghosts = 0;
        t.stencil(seam, &mut |k, _| ghosts += usize::from(k.is_none()));
        assert_eq!(ghosts, 0, "nothing runs off at the seam");
        // Only the ends of the axis are edges.
        assert!((t.edge_distance(seam) - 0.45).abs() < 1e-12, "{}", t.edge_distance(seam));
        // A splat at the seam spreads across it and keeps its volume.
        t.deposit(seam, 1e-3);
        assert!(t.thickness()[5 * 36 + 35] > 0.0);
        assert!((t.volume() - 1e-3).abs() < 1e-15);
        // The same shell cut just short of a full turn has an edge there.
        let cut = tank([-PI, 0.99 * PI]);
        let mut ghosts = 0;
        cut.stencil(seam, &mut |k, _| ghosts += usize::from(k.is_none()));
        assert_eq!(ghosts, 3);
        assert!(cut.edge_distance(seam) < 0.1);
    }
}

#[cfg(test)]
mod lined_arch {
    use super::*;
    use crate::collision::CylinderShell;

    /// A tunnel's arch seen from inside (1.5 m radius, 30° to 150°, 2 m long, axis along y
    /// through (0, 0, 1)), 120 × 80 cells, lined `lining` m thick.
    fn arch(lining: f64) -> CylinderSurface {
        let shell =
            CylinderShell::new(DVec3::Z, DVec3::Y, DVec3::X, 1.5, 2.0, [30f64, 150.0].map(f64::to_radians))
                .expect("valid");
        let mut s = CylinderSurface::new(ShellChart { shell, inside: true }, 120, 80, 0.0);
        for cell in 0..s.thickness().len() as u32 {
            s.add_thickness(cell, lining);
        }
        s
    }

    #[test]
    fn a_step_through_a_curved_lining_and_the_surface_behind_it_meets_the_lining() {
        let s = arch(0.05);
        // From beside the axis to well behind the arch, in one step: along the chord the height
        // above the surface is not linear (the chord lies nearer the axis than the straight line
        // between its ends' heights says), so the lining lies past where that line meets the
        // surface; and straight up, where it is linear.
        for (p0, p1) in [
            (DVec3::new(-0.06, -0.69, 0.89), DVec3::new(-1.77, -0.59, 2.67)),
            (DVec3::new(0.4, 0.2, 0.7), DVec3::new(-1.0, 0.3, 3.0)),
            (DVec3::new(0.0, 0.1, 1.2), DVec3::new(0.0, 0.1, 3.0)),
            // Short steps through the lining alone, and into it from just above.
            (DVec3::new(0.3, 0.0, 2.40), DVec3::new(0.3, 0.0, 2.52)),
            (DVec3::new(0.0, 0.5, 2.44), DVec3::new(0.0, 0.5, 2.47)),
        ] {
            let c = s.layer_contact(p0, p1).unwrap_or_else(|| panic!("{p0} → {p1} meets the lining"));
            let r = (c.point - DVec3::Z).reject_from(DVec3::Y).length();
            assert!((r - 1.45).abs() < 1e-9, "{p0} → {p1}: met at {r} m from the axis");
            let bare = s.intersect(p0, p1).map_or(f64::INFINITY, |h| h.t);
            assert!(c.s < bare, "the lining before the bare surface");
        }
        // Started behind the surface, a step meets no lining; and a bare arch has none.
        assert!(s.layer_contact(DVec3::new(0.0, 0.0, 2.8), DVec3::new(0.0, 0.0, 1.2)).is_none());
        assert!(arch(0.0).layer_contact(DVec3::new(0.0, 0.1, 1.2), DVec3::new(0.0, 0.1, 3.0)).is_none());
    }
}
