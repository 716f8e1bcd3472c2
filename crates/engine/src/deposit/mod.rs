//! Deposit surfaces: the surfaces of targets, which collect what sticks to them.
//!
//! A [`DepositSurface`] owns how an impact maps to a cell, how the deposited layer offsets
//! later impacts, the surface's orientation at each cell (for cohesion and the other layer
//! stages), which cells neighbour each other, and how its field is laid out for writers. The
//! built-in kinds are listed once, in the `surfaces!` invocation below, which generates the
//! [`Surface`] enum and its static dispatch: a heightfield on an unrolled surface
//! ([`GridSurface`]: a rectangle, [`RectangleSurface`], or a cylindrical shell,
//! [`CylinderSurface`]) and a triangle mesh with a thickness per triangle ([`MeshSurface`]).

mod chart;
mod grid;
mod heightfield;
mod mesh;
mod openings;
mod pending;
mod pyramid;
mod sums;

pub use chart::{Chart, ShellChart};
pub use grid::{CylinderSurface, GridSurface, RectangleSurface};
pub use heightfield::{HeightField, footprint_cells};
pub use mesh::{MeshError, MeshSurface};
pub use openings::Opening;
pub use pending::{Gathered, Pending, WEAR_QUANTUM, share, wear_quanta};

use crate::collision::{Aabb, Hit, Primitive, Shape};
use glam::DVec3;

/// Where a path meets a deposited layer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LayerContact {
    /// Fraction of the path at the contact.
    pub s: f64,
    /// Contact point, m.
    pub point: DVec3,
    /// The layer's unit normal there, from the thickness gradient.
    pub normal: DVec3,
    /// The cell the material settles in: the one entered from above, or, entering a taller
    /// column through its side, the column the particle was over.
    pub cell: u32,
}

/// A rectangle of nodes of one level of a surface's bounds (level `k`: blocks of `2ᵏ × 2ᵏ`
/// cells; level 0: the cells), both ranges inclusive.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Nodes {
    /// Level of the bounds the nodes belong to: each node covers `2ˡᵉᵛᵉˡ × 2ˡᵉᵛᵉˡ` cells.
    pub level: u32,
    /// First and last node column.
    pub cols: (u32, u32),
    /// First and last node row.
    pub rows: (u32, u32),
    /// Nodes per row of the level.
    pub stride: u32,
}

/// How a box (the bounds of a flight) stands to a deposited layer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Clearance {
    /// It lies nowhere over the receiving side: no layer can ever reach it.
    Free,
    /// It lies over the cells of `nodes`; its lowest point is `height` (m) above the bare
    /// surface, and `top` (m), the largest of the nodes' bounds, bounds the layer under it
    /// now. It clears the layer while every node's [`DepositSurface::node_bound`] stays
    /// below `height`.
    Over {
        /// The nodes under the box.
        nodes: Nodes,
        /// Least height of the box above the bare surface, m.
        height: f64,
        /// Upper bound of the layer under the box now, m.
        top: f64,
    },
    /// It lies over the surface, wholly higher than the `ceiling` asked about: `height` (m) is
    /// its least height above the bare surface and `top` (m) bounds the whole layer now. No
    /// node under it was looked up.
    Above {
        /// Least height of the box above the bare surface, m.
        height: f64,
        /// Upper bound of the whole layer now, m.
        top: f64,
    },
    /// The surface cannot tell.
    Unknown,
}

/// A triangle mesh of a deposit surface, for drawing and export: vertices on the bare surface
/// (or on the layer's top), the thickness at each vertex, and the cell each triangle belongs to.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Vertex positions, m.
    pub positions: Vec<DVec3>,
    /// Unit normals of the bare surface at the vertices, towards the receiving side.
    pub normals: Vec<DVec3>,
    /// Thickness at each vertex, m: the area-weighted mean of the cells around it.
    pub thickness: Vec<f64>,
    /// Triangles as vertex indices, counter-clockwise seen from the receiving side.
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the cell whose data it shows (a cell of the mesh: with
    /// downsampling, the first cell of the block it stands for).
    pub cell: Vec<u32>,
    /// Side of the blocks of a grid averaged down, cells: a triangle's `cell` and the next
    /// `block − 1` cells along its row and column (0 or 1: every cell stands for itself).
    pub block: usize,
}

/// How a surface's cells are laid out, for the writers of maps and meshes.
#[derive(Clone, Debug, PartialEq)]
pub enum Layout {
    /// `rows × cols` cells stored row-major from row 0; `cell` is their size `(along a row,
    /// along a column)`, m; `axes` label the map's horizontal and vertical axes.
    Grid {
        /// Rows of cells, bottom (row 0) to top.
        rows: usize,
        /// Cells per row.
        cols: usize,
        /// Cell size `(width, height)`, m.
        cell: (f64, f64),
        /// What the columns and the rows run along.
        axes: [MapAxis; 2],
    },
    /// Cells without a grid (a mesh's triangles), one value each.
    Cells {
        /// Number of cells, one value each.
        count: usize,
    },
}

/// One axis of a map: what it measures and the values at its two ends (the first and last
/// column's outer edges, or the bottom and top rows').
#[derive(Clone, Debug, PartialEq)]
pub struct MapAxis {
    /// Label with its unit.
    pub label: &'static str,
    /// Value at the start (left or bottom edge).
    pub from: f64,
    /// Value at the end (right or top edge).
    pub to: f64,
}

/// A surface that collects deposit. Cells are numbered `0..n`, `n` the length of
/// [`DepositSurface::thickness`]; thickness is volume per area of the bare surface, m.
///
/// # The core
///
/// A new kind of surface implements sixteen methods; the others are provided, derived from
/// these, and a kind overrides them where it knows a faster or finer way (a grid splats a
/// deposit, bounds its layer by a pyramid and averages over blocks; a mesh finds hits through
/// an index):
///
/// - the bare surface: [`colliders`](Self::colliders), [`piece_of`](Self::piece_of),
///   [`cell_at`](Self::cell_at), [`normal`](Self::normal), [`point_above`](Self::point_above),
///   [`cell_area`](Self::cell_area);
/// - the cells around a cell: [`neighbours`](Self::neighbours), [`stencil`](Self::stencil),
///   [`edge_distance`](Self::edge_distance);
/// - the layer's storage: [`thickness`](Self::thickness), [`hits`](Self::hits),
///   [`add_hits`](Self::add_hits), [`add_thickness`](Self::add_thickness),
///   [`take_changed`](Self::take_changed);
/// - the layer's shape: [`layer_contact`](Self::layer_contact), and [`mesh`](Self::mesh) for
///   drawing and export.
///
/// Provided: [`intersect`](Self::intersect) (from the colliders),
/// [`receives`](Self::receives) (from the normal of the cell struck),
/// [`uniform_normal`](Self::uniform_normal) (none), [`layer_clearance`](Self::layer_clearance) and
/// [`node_bound`](Self::node_bound) (no bounds: flights over the layer are stepped),
/// [`mean_thickness`](Self::mean_thickness) (through the neighbours),
/// [`area_of`](Self::area_of), [`max_thickness`](Self::max_thickness) and
/// [`volume`](Self::volume) (from the cells), [`deposit`](Self::deposit) and
/// [`remove`](Self::remove) (through [`add_thickness`](Self::add_thickness), in the one cell),
/// [`spacing`](Self::spacing) and [`drop_bound`](Self::drop_bound) (over the stencil), and
/// [`layout`](Self::layout) (cells without a grid).
///
/// A built-in kind is also listed in the `surfaces!` invocation of this module, and its
/// checkpoint arms in [`Surface`]'s `save_state` and `load_state`.
pub trait DepositSurface: Send + Sync + std::fmt::Debug {
    /// The bare surface as collision shapes, its pieces: one for a heightfield, a triangle per
    /// cell for a mesh.
    fn colliders(&self) -> Vec<Shape>;

    /// The piece of [`DepositSurface::colliders`] that `cell` lies on.
    fn piece_of(&self, cell: u32) -> u32;

    /// The cell under a point on `piece` of the bare surface (clamped to the surface).
    fn cell_at(&self, piece: u32, point: DVec3) -> u32;

    /// Unit normal of the bare surface at `cell`, towards the receiving side.
    fn normal(&self, cell: u32) -> DVec3;

    /// The point `height` (m) in front of the bare surface at the centre of `cell`.
    fn point_above(&self, cell: u32, height: f64) -> DVec3;

    /// Area of `cell` on the bare surface, m² (0 for a cell cut away).
    fn cell_area(&self, cell: u32) -> f64;

    /// Calls `visit(neighbour, shared edge length in m)` for each cell that touches `cell`:
    /// first the ones sharing an edge, then the ones sharing only a corner (length 0).
    fn neighbours(&self, cell: u32, visit: &mut dyn FnMut(u32, f64));

    /// Calls `visit(neighbour, centre)` for each cell around `cell` that material can flow to,
    /// with the centre (m, on the bare surface) of that cell, or, past an edge that does not
    /// hold the layer, of where it would be (`None`: material flowing there leaves the surface).
    fn stencil(&self, cell: u32, visit: &mut dyn FnMut(Option<u32>, DVec3));

    /// Distance from `cell`'s centre to the nearest edge of the surface or of an opening,
    /// along the surface, m.
    fn edge_distance(&self, cell: u32) -> f64;

    /// Thickness per cell, m. Its storage is allocated with the surface and written in place,
    /// so it keeps its address for the surface's life (bindings view it without a copy).
    fn thickness(&self) -> &[f64];

    /// Impacts per cell (stuck or rebounded); stored in place like [`DepositSurface::thickness`].
    fn hits(&self) -> &[u32];

    /// Counts `n` impacts in `cell`.
    fn add_hits(&mut self, cell: u32, n: u32);

    /// Adds `dt` (m, negative to remove) to `cell`'s thickness, never below 0, keeping
    /// [`DepositSurface::max_thickness`] a bound and marking the cell changed.
    fn add_thickness(&mut self, cell: u32, dt: f64);

    /// The cells whose thickness changed since the last call, ascending.
    fn take_changed(&mut self) -> Vec<u32>;

    /// Where the segment `p0 → p1` first enters the deposited layer on the receiving side.
    fn layer_contact(&self, p0: DVec3, p1: DVec3) -> Option<LayerContact>;

    /// A triangle mesh of the surface, its vertices raised by the layer when `lift`; grids
    /// are averaged down by a whole factor so that the mesh has at most about `max_cells` cells.
    fn mesh(&self, lift: bool, max_cells: usize) -> SurfaceMesh;

    /// Where the segment `p0 → p1` first meets the bare surface. By default, the nearest hit
    /// on any of the [`colliders`](DepositSurface::colliders) (the first piece among equals).
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        for piece in self.colliders() {
            if let Some(h) = piece.intersect(p0, p1)
                && best.is_none_or(|b| h.t < b.t)
            {
                best = Some(h);
            }
        }
        best
    }

    /// True if a hit at `point` on `piece` whose normal (facing the incoming particle) is
    /// `normal` strikes the receiving side. By default, by the normal of the cell under it.
    fn receives(&self, piece: u32, point: DVec3, normal: DVec3) -> bool {
        normal.dot(self.normal(self.cell_at(piece, point))) > 0.0
    }

    /// The normal shared by every cell, for flat surfaces (`None`: it varies, or the surface
    /// does not say).
    fn uniform_normal(&self) -> Option<DVec3> {
        None
    }

    /// How the box `b` stands to the deposited layer: what a flight inside `b` needs to know
    /// to sleep over the layer (see [`Clearance`]); a box wholly higher than `ceiling` (m) above
    /// the bare surface may be answered [`Clearance::Above`], without the nodes under it.
    /// Surfaces that cannot bound their layer under a box cheaply answer
    /// [`Clearance::Unknown`] (the default), and the particle is stepped.
    fn layer_clearance(&self, b: &Aabb, ceiling: f64) -> Clearance {
        let _ = (b, ceiling);
        Clearance::Unknown
    }

    /// An upper bound of the thickness over node `(col, row)` of level `level` of the
    /// surface's bounds (see [`Clearance::Over`]), m; by default, none (infinite).
    fn node_bound(&self, level: u32, col: u32, row: u32) -> f64 {
        let _ = (level, col, row);
        f64::INFINITY
    }

    /// Mean thickness over the cells whose centres lie within `radius` (m) of `cell`'s, weighted
    /// by area (`cell`'s own thickness when `radius` is below a cell), m. By default over the
    /// cells reached from `cell` through [`neighbours`](DepositSurface::neighbours) whose
    /// centres lie within `radius`.
    fn mean_thickness(&self, cell: u32, radius: f64) -> f64 {
        let t = self.thickness();
        let c0 = self.point_above(cell, 0.0);
        let (mut sum, mut area) = (0.0, 0.0);
        let (mut stack, mut seen) = (vec![cell], vec![cell]);
        while let Some(i) = stack.pop() {
            let a = self.cell_area(i);
            sum += t[i as usize] * a;
            area += a;
            self.neighbours(i, &mut |j, _| {
                if !seen.contains(&j) && self.point_above(j, 0.0).distance(c0) <= radius {
                    seen.push(j);
                    stack.push(j);
                }
            });
        }
        sum / area
    }

    /// Total area of `cells`, m².
    fn area_of(&self, cells: &[u32]) -> f64 {
        cells.iter().map(|&c| self.cell_area(c)).sum()
    }

    /// An upper bound of every cell's thickness, m; by default the largest thickness, found
    /// by visiting every cell.
    fn max_thickness(&self) -> f64 {
        self.thickness().iter().copied().fold(0.0, f64::max)
    }

    /// Σ thickness × area: the volume held, m³.
    fn volume(&self) -> f64 {
        self.thickness().iter().enumerate().map(|(c, t)| t * self.cell_area(c as u32)).sum()
    }

    /// Calls `visit` with each cell among which a deposit struck at `cell` is shared evenly (its
    /// splat), in a fixed order, the cell it centres on first: by default `cell` alone.
    fn footprint(&self, cell: u32, visit: &mut dyn FnMut(u32)) {
        visit(cell);
    }

    /// Deposits `volume` (m³) centred on `cell`, conserving it exactly (up to rounding). By
    /// default all of it stays in `cell`.
    fn deposit(&mut self, cell: u32, volume: f64) {
        let area = self.cell_area(cell);
        self.add_thickness(cell, volume / area);
    }

    /// Removes up to `volume` (m³) from `cell`; returns the volume removed, m³.
    fn remove(&mut self, cell: u32, volume: f64) -> f64 {
        let area = self.cell_area(cell);
        let take = (volume / area).min(self.thickness()[cell as usize]);
        self.add_thickness(cell, -take);
        take * area
    }

    /// The smallest distance between the centres of `cell` and of a cell in its stencil, m. The
    /// surface is flat over a stencil: the drop from `cell` to a neighbour per metre between
    /// them is at most the sine of the surface's tilt there.
    fn spacing(&self, cell: u32) -> f64 {
        let own = self.point_above(cell, 0.0);
        let mut least = f64::INFINITY;
        self.stencil(cell, &mut |_, centre| least = least.min(centre.distance(own)));
        least
    }

    /// An upper bound of the drop, per metre between centres, from `cell` to any cell of its
    /// stencil (or where a missing one would be), along unit `up`: dimensionless.
    fn drop_bound(&self, cell: u32, up: DVec3) -> f64 {
        let own = self.point_above(cell, 0.0);
        let mut most = 0.0_f64;
        self.stencil(cell, &mut |_, centre| {
            let l = centre.distance(own);
            if l > 0.0 {
                most = most.max((own - centre).dot(up) / l);
            }
        });
        most
    }

    /// How the cells are laid out; by default as cells without a grid.
    fn layout(&self) -> Layout {
        Layout::Cells { count: self.thickness().len() }
    }
}

/// Declares the built-in deposit surfaces: the [`Surface`] enum and its dispatch.
macro_rules! surfaces {
    ($( $(#[$doc:meta])* $variant:ident($ty:ty), )*) => {
        /// Any built-in deposit surface.
        #[derive(Clone, Debug)]
        pub enum Surface {
            $( $(#[$doc])* $variant($ty), )*
        }

        macro_rules! each {
            ($self:expr, $s:ident => $body:expr) => {
                match $self { $( Surface::$variant($s) => $body, )* }
            };
        }

        // Every method, the provided ones too, so that each kind's own versions are used.
        impl DepositSurface for Surface {
            fn colliders(&self) -> Vec<Shape> { each!(self, s => s.colliders()) }
            #[inline]
            fn piece_of(&self, cell: u32) -> u32 { each!(self, s => s.piece_of(cell)) }
            fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> { each!(self, s => s.intersect(p0, p1)) }
            #[inline]
            fn receives(&self, piece: u32, point: DVec3, normal: DVec3) -> bool {
                each!(self, s => s.receives(piece, point, normal))
            }
            #[inline]
            fn cell_at(&self, piece: u32, point: DVec3) -> u32 { each!(self, s => s.cell_at(piece, point)) }
            #[inline]
            fn layer_contact(&self, p0: DVec3, p1: DVec3) -> Option<LayerContact> {
                each!(self, s => s.layer_contact(p0, p1))
            }
            #[inline]
            fn layer_clearance(&self, b: &Aabb, ceiling: f64) -> Clearance {
                each!(self, s => s.layer_clearance(b, ceiling))
            }
            #[inline]
            fn node_bound(&self, level: u32, col: u32, row: u32) -> f64 {
                each!(self, s => s.node_bound(level, col, row))
            }
            #[inline]
            fn normal(&self, cell: u32) -> DVec3 { each!(self, s => s.normal(cell)) }
            fn uniform_normal(&self) -> Option<DVec3> { each!(self, s => s.uniform_normal()) }
            fn point_above(&self, cell: u32, height: f64) -> DVec3 {
                each!(self, s => s.point_above(cell, height))
            }
            #[inline]
            fn thickness(&self) -> &[f64] { each!(self, s => s.thickness()) }
            fn mean_thickness(&self, cell: u32, radius: f64) -> f64 { each!(self, s => s.mean_thickness(cell, radius)) }
            fn hits(&self) -> &[u32] { each!(self, s => s.hits()) }
            #[inline]
            fn cell_area(&self, cell: u32) -> f64 { each!(self, s => s.cell_area(cell)) }
            fn area_of(&self, cells: &[u32]) -> f64 { each!(self, s => s.area_of(cells)) }
            #[inline]
            fn max_thickness(&self) -> f64 { each!(self, s => s.max_thickness()) }
            fn volume(&self) -> f64 { each!(self, s => s.volume()) }
            fn add_hits(&mut self, cell: u32, n: u32) { each!(self, s => s.add_hits(cell, n)) }
            fn footprint(&self, cell: u32, visit: &mut dyn FnMut(u32)) { each!(self, s => s.footprint(cell, visit)) }
            fn deposit(&mut self, cell: u32, volume: f64) { each!(self, s => s.deposit(cell, volume)) }
            fn remove(&mut self, cell: u32, volume: f64) -> f64 { each!(self, s => s.remove(cell, volume)) }
            fn neighbours(&self, cell: u32, visit: &mut dyn FnMut(u32, f64)) {
                each!(self, s => s.neighbours(cell, visit))
            }
            fn stencil(&self, cell: u32, visit: &mut dyn FnMut(Option<u32>, DVec3)) {
                each!(self, s => s.stencil(cell, visit))
            }
            fn spacing(&self, cell: u32) -> f64 { each!(self, s => s.spacing(cell)) }
            fn drop_bound(&self, cell: u32, up: DVec3) -> f64 { each!(self, s => s.drop_bound(cell, up)) }
            fn edge_distance(&self, cell: u32) -> f64 { each!(self, s => s.edge_distance(cell)) }
            fn add_thickness(&mut self, cell: u32, dt: f64) { each!(self, s => s.add_thickness(cell, dt)) }
            fn take_changed(&mut self) -> Vec<u32> { each!(self, s => s.take_changed()) }
            fn layout(&self) -> Layout { each!(self, s => s.layout()) }
            fn mesh(&self, lift: bool, max_cells: usize) -> SurfaceMesh { each!(self, s => s.mesh(lift, max_cells)) }
        }
    };
}

surfaces! {
    /// A rectangle with a regular heightfield.
    Rectangle(RectangleSurface),
    /// A cylindrical shell with a heightfield on its unrolled surface.
    Cylinder(CylinderSurface),
    /// A triangle mesh with a thickness per triangle.
    Mesh(MeshSurface),
}

impl Surface {
    /// The cells whose thickness changed since the last call, with the layer's identity (see
    /// [`HeightField::take_revised`]); `None` for a mesh, which has no heightfield.
    pub fn take_revised(&mut self) -> Option<(u64, Vec<u32>)> {
        match self {
            Surface::Rectangle(s) => Some(s.field.take_revised()),
            Surface::Cylinder(s) => Some(s.field.take_revised()),
            Surface::Mesh(_) => None,
        }
    }

    /// Gives the layer a new identity (see [`HeightField::forget_copies`]); nothing for a mesh.
    pub fn forget_copies(&mut self) {
        match self {
            Surface::Rectangle(s) => s.field.forget_copies(),
            Surface::Cylinder(s) => s.field.forget_copies(),
            Surface::Mesh(_) => {}
        }
    }

    /// Writes the deposit's state (what a run changes), for a checkpoint.
    pub(crate) fn save_state(&self, e: &mut crate::checkpoint::Enc) {
        match self {
            Surface::Rectangle(s) => s.field.save_state(e),
            Surface::Cylinder(s) => s.field.save_state(e),
            Surface::Mesh(s) => s.save_state(e),
        }
    }

    /// Reads what [`Surface::save_state`] wrote, over the same surface freshly built.
    pub(crate) fn load_state(
        &mut self,
        d: &mut crate::checkpoint::Dec<'_>,
    ) -> Result<(), crate::checkpoint::StateError> {
        match self {
            Surface::Rectangle(s) => s.field.load_state(d),
            Surface::Cylinder(s) => s.field.load_state(d),
            Surface::Mesh(s) => s.load_state(d),
        }
    }

    /// The rectangle, if this surface is one.
    pub fn as_rectangle(&self) -> Option<&RectangleSurface> {
        match self {
            Surface::Rectangle(r) => Some(r),
            _ => None,
        }
    }
}

/// What the deposit tests share.
#[cfg(test)]
pub(crate) mod testing {
    /// Uniform numbers in [0, 1) from a linear congruential generator seeded with `seed`.
    pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut x = seed;
        move || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::testing::uniform;
    use super::*;
    use crate::collision::{Face, Triangle};

    /// A surface that implements only the core of [`DepositSurface`], by handing each call to
    /// `S`: the provided methods run on their defaults.
    #[derive(Clone, Debug)]
    struct CoreOnly<S>(S);

    impl<S: DepositSurface> DepositSurface for CoreOnly<S> {
        fn colliders(&self) -> Vec<Shape> {
            self.0.colliders()
        }
        fn piece_of(&self, cell: u32) -> u32 {
            self.0.piece_of(cell)
        }
        fn cell_at(&self, piece: u32, point: DVec3) -> u32 {
            self.0.cell_at(piece, point)
        }
        fn normal(&self, cell: u32) -> DVec3 {
            self.0.normal(cell)
        }
        fn point_above(&self, cell: u32, height: f64) -> DVec3 {
            self.0.point_above(cell, height)
        }
        fn cell_area(&self, cell: u32) -> f64 {
            self.0.cell_area(cell)
        }
        fn neighbours(&self, cell: u32, visit: &mut dyn FnMut(u32, f64)) {
            self.0.neighbours(cell, visit);
        }
        fn stencil(&self, cell: u32, visit: &mut dyn FnMut(Option<u32>, DVec3)) {
            self.0.stencil(cell, visit);
        }
        fn edge_distance(&self, cell: u32) -> f64 {
            self.0.edge_distance(cell)
        }
        fn thickness(&self) -> &[f64] {
            self.0.thickness()
        }
        fn hits(&self) -> &[u32] {
            self.0.hits()
        }
        fn add_hits(&mut self, cell: u32, n: u32) {
            self.0.add_hits(cell, n);
        }
        fn add_thickness(&mut self, cell: u32, dt: f64) {
            self.0.add_thickness(cell, dt);
        }
        fn take_changed(&mut self) -> Vec<u32> {
            self.0.take_changed()
        }
        fn layer_contact(&self, p0: DVec3, p1: DVec3) -> Option<LayerContact> {
            self.0.layer_contact(p0, p1)
        }
        fn mesh(&self, lift: bool, max_cells: usize) -> SurfaceMesh {
            self.0.mesh(lift, max_cells)
        }
    }

    /// A corrugated sheet of 12 × 8 squares of 0.1 m, two triangles each, its height a sine
    /// of x (so that the normals vary from cell to cell), facing +z.
    fn sheet() -> MeshSurface {
        let p = |i: usize, j: usize| {
            let x = 0.1 * i as f64;
            DVec3::new(x, 0.1 * j as f64, 0.03 * (7.0 * x).sin())
        };
        let t = |a, b, c| Triangle::new(a, b, c).expect("a triangle");
        let mut triangles = Vec::new();
        for j in 0..8 {
            for i in 0..12 {
                triangles.push(t(p(i, j), p(i + 1, j), p(i + 1, j + 1)));
                triangles.push(t(p(i, j), p(i + 1, j + 1), p(i, j + 1)));
            }
        }
        MeshSurface::new(triangles).expect("a mesh")
    }

    /// The provided methods, run on the core alone, answer what the mesh answers, to the bit:
    /// a mesh needs nothing beyond the core, and overrides only where it is faster.
    #[test]
    fn the_defaults_over_the_core_answer_as_the_mesh_does() {
        let (mut mesh, mut next) = (sheet(), uniform(3));
        for _ in 0..300 {
            let cell = (next() * 192.0) as u32;
            mesh.deposit(cell, 1e-4 * next());
        }
        let mut core = CoreOnly(mesh.clone());
        let same = |a: f64, b: f64, what: &str| assert_eq!(a.to_bits(), b.to_bits(), "{what}: {a} {b}");
        same(core.max_thickness(), mesh.max_thickness(), "max");
        same(core.volume(), mesh.volume(), "volume");
        assert_eq!(core.layout(), mesh.layout());
        let cells: Vec<u32> = (0..192).step_by(7).collect();
        same(core.area_of(&cells), mesh.area_of(&cells), "area");
        let up = DVec3::new(0.3, -0.2, 0.9).normalize();
        for cell in 0..192 {
            same(core.spacing(cell), mesh.spacing(cell), "spacing");
            same(core.drop_bound(cell, up), mesh.drop_bound(cell, up), "drop");
            for radius in [0.0, 0.05, 0.12, 0.31] {
                same(core.mean_thickness(cell, radius), mesh.mean_thickness(cell, radius), "mean");
            }
        }
        let mut struck = 0;
        for _ in 0..500 {
            let p0 = DVec3::new(1.4 * next() - 0.1, next() - 0.1, 0.2 * next() - 0.05);
            let p1 = p0 + DVec3::new(0.4 * next() - 0.2, 0.4 * next() - 0.2, -0.3 * next());
            let hit = mesh.intersect(p0, p1);
            assert_eq!(core.intersect(p0, p1), hit, "{p0} → {p1}");
            if let Some(h) = hit {
                struck += 1;
                let piece = mesh.colliders().iter().position(|s| s.intersect(p0, p1) == Some(h));
                let piece = piece.expect("a piece") as u32;
                assert_eq!(core.receives(piece, h.point, h.normal), mesh.receives(piece, h.point, h.normal));
                assert_eq!(
                    core.receives(piece, h.point, -h.normal),
                    mesh.receives(piece, h.point, -h.normal)
                );
            }
        }
        assert!(struck > 100, "only {struck} paths struck the sheet");
        for _ in 0..200 {
            let cell = (next() * 192.0) as u32;
            let volume = 2e-4 * next();
            if next() < 0.5 {
                core.deposit(cell, volume);
                mesh.deposit(cell, volume);
            } else {
                same(core.remove(cell, volume), mesh.remove(cell, volume), "removed");
            }
        }
        assert!(core.thickness().iter().zip(mesh.thickness()).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(core.take_changed(), mesh.take_changed());
    }

    /// On a grid the defaults reach the grid's own answers by another road: the same to
    /// rounding (the volume, areas, the disc mean, the spacing, the drop), or to the bit where
    /// the road is the same (hits, receiving side, removals).
    #[test]
    fn the_defaults_over_the_core_agree_with_the_grid() {
        let face = Face::new(DVec3::ZERO, DVec3::new(0.0, -0.6, 0.8), DVec3::Z, [1.2, 0.8]);
        let (mut grid, mut next) = (RectangleSurface::new(face, 24, 16, 0.0), uniform(9));
        for cell in 0..384 {
            grid.add_thickness(cell, 1e-3 * next());
        }
        let mut core = CoreOnly(grid.clone());
        let close = |a: f64, b: f64, what: &str| {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-3), "{what}: {a} {b}")
        };
        close(core.volume(), grid.volume(), "volume");
        assert_eq!(core.max_thickness(), grid.max_thickness());
        let cells: Vec<u32> = (0..384).step_by(5).collect();
        close(core.area_of(&cells), grid.area_of(&cells), "area");
        for cell in (0..384).step_by(3) {
            close(core.spacing(cell), grid.spacing(cell), "spacing");
            close(core.drop_bound(cell, DVec3::Z), grid.drop_bound(cell, DVec3::Z), "drop");
            for radius in [0.0, 0.06, 0.17] {
                close(core.mean_thickness(cell, radius), grid.mean_thickness(cell, radius), "mean");
            }
        }
        let mut struck = 0;
        for _ in 0..200 {
            // From in front of the face (or beside it) to behind it, or short of it.
            let at = face.right * (1.4 * next() - 0.7) + face.up * (next() - 0.5);
            let p0 = at + face.normal * (0.05 + 0.2 * next());
            let p1 =
                p0 + DVec3::new(0.1 * next() - 0.05, 0.1 * next() - 0.05, 0.0) - face.normal * 0.4 * next();
            let hit = grid.intersect(p0, p1);
            assert_eq!(core.intersect(p0, p1), hit, "{p0} → {p1}");
            if let Some(h) = hit {
                struck += 1;
                assert_eq!(core.receives(0, h.point, h.normal), grid.receives(0, h.point, h.normal));
            }
        }
        assert!(struck > 60, "only {struck} paths struck the face");
        for cell in (0..384).step_by(11) {
            let volume = 1e-6 * next();
            assert_eq!(core.remove(cell, volume).to_bits(), grid.remove(cell, volume).to_bits());
        }
        assert!(core.thickness().iter().zip(grid.thickness()).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}
