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
mod pyramid;
mod sums;

pub use chart::{Chart, ShellChart};
pub use grid::{CylinderSurface, GridSurface, RectangleSurface};
pub use heightfield::HeightField;
pub use mesh::{MeshError, MeshSurface};
pub use openings::Opening;

use crate::collision::{Aabb, Hit, Shape};
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
    /// Level.
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
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
        /// Cell size `(width, height)`, m.
        cell: (f64, f64),
        /// What the columns and the rows run along.
        axes: [MapAxis; 2],
    },
    /// Cells without a grid (a mesh's triangles), one value each.
    Cells {
        /// Cells.
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

/// A surface that collects deposit. Cells are numbered `0..cells()`; thickness is volume per
/// area of the bare surface, m.
pub trait DepositSurface: Send + Sync + std::fmt::Debug {
    /// The bare surface as collision shapes, its pieces: one for a heightfield, a triangle per
    /// cell for a mesh.
    fn colliders(&self) -> Vec<Shape>;

    /// The piece of [`DepositSurface::colliders`] that `cell` lies on.
    fn piece_of(&self, cell: u32) -> u32;

    /// Where the segment `p0 → p1` first meets the bare surface.
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit>;

    /// True if a hit at `point` on `piece` whose normal (facing the incoming particle) is
    /// `normal` strikes the receiving side.
    fn receives(&self, piece: u32, point: DVec3, normal: DVec3) -> bool;

    /// The cell under a point on `piece` of the bare surface (clamped to the surface).
    fn cell_at(&self, piece: u32, point: DVec3) -> u32;

    /// Where the segment `p0 → p1` first enters the deposited layer on the receiving side.
    fn layer_contact(&self, p0: DVec3, p1: DVec3) -> Option<LayerContact>;

    /// How the box `b` stands to the deposited layer: what a flight inside `b` needs to know
    /// to sleep over the layer (see [`Clearance`]); a box wholly higher than `ceiling` (m) above
    /// the bare surface may be answered [`Clearance::Above`], without the nodes under it.
    /// Surfaces that cannot bound their layer under a box cheaply answer
    /// [`Clearance::Unknown`], and the particle is stepped.
    fn layer_clearance(&self, b: &Aabb, ceiling: f64) -> Clearance {
        let _ = (b, ceiling);
        Clearance::Unknown
    }

    /// An upper bound of the thickness over node `(col, row)` of level `level` of the
    /// surface's bounds (see [`Clearance::Over`]), m.
    fn node_bound(&self, level: u32, col: u32, row: u32) -> f64 {
        let _ = (level, col, row);
        f64::INFINITY
    }

    /// Unit normal of the bare surface at `cell`, towards the receiving side.
    fn normal(&self, cell: u32) -> DVec3;

    /// The normal shared by every cell, for flat surfaces.
    fn uniform_normal(&self) -> Option<DVec3> {
        None
    }

    /// The point `height` (m) in front of the bare surface at the centre of `cell`.
    fn point_above(&self, cell: u32, height: f64) -> DVec3;

    /// Thickness per cell, m. Its storage is allocated with the surface and written in place,
    /// so it keeps its address for the surface's life (bindings view it without a copy).
    fn thickness(&self) -> &[f64];

    /// Mean thickness over the cells whose centres lie within `radius` (m) of `cell`'s, weighted
    /// by area (`cell`'s own thickness when `radius` is below a cell), m.
    fn mean_thickness(&self, cell: u32, radius: f64) -> f64;

    /// Impacts per cell (stuck or rebounded); stored in place like [`DepositSurface::thickness`].
    fn hits(&self) -> &[u32];

    /// Area of `cell` on the bare surface, m².
    fn cell_area(&self, cell: u32) -> f64;

    /// Total area of `cells`, m².
    fn area_of(&self, cells: &[u32]) -> f64 {
        cells.iter().map(|&c| self.cell_area(c)).sum()
    }

    /// An upper bound of every cell's thickness, m.
    fn max_thickness(&self) -> f64;

    /// Σ thickness × area: the volume held, m³.
    fn volume(&self) -> f64;

    /// Counts one impact in `cell`.
    fn add_hit(&mut self, cell: u32);

    /// Deposits `volume` (m³) centred on `cell`, conserving it exactly (up to rounding).
    fn deposit(&mut self, cell: u32, volume: f64);

    /// Removes up to `volume` (m³) from `cell`; returns the volume removed.
    fn remove(&mut self, cell: u32, volume: f64) -> f64;

    /// Calls `visit(neighbour, shared edge length in m)` for each cell that touches `cell`:
    /// first the ones sharing an edge, then the ones sharing only a corner (length 0).
    fn neighbours(&self, cell: u32, visit: &mut dyn FnMut(u32, f64));

    /// Calls `visit(neighbour, centre)` for each cell around `cell` that material can flow to,
    /// with the centre (m, on the bare surface) of that cell, or, past an edge that does not
    /// hold the layer, of where it would be (`None`: material flowing there leaves the surface).
    fn stencil(&self, cell: u32, visit: &mut dyn FnMut(Option<u32>, DVec3));

    /// The smallest distance between the centres of `cell` and of a cell in its stencil, m. The
    /// surface is flat over a stencil: the drop from `cell` to a neighbour per metre between
    /// them is at most the sine of the surface's tilt there.
    fn spacing(&self, cell: u32) -> f64;

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

    /// Distance from `cell`'s centre to the nearest edge of the surface or of an opening,
    /// along the surface, m.
    fn edge_distance(&self, cell: u32) -> f64;

    /// Adds `dt` (m, negative to remove) to `cell`'s thickness, never below 0.
    fn add_thickness(&mut self, cell: u32, dt: f64);

    /// The cells whose thickness changed since the last call, ascending.
    fn take_changed(&mut self) -> Vec<u32>;

    /// How the cells are laid out.
    fn layout(&self) -> Layout;

    /// A triangle mesh of the surface, its vertices raised by the layer when `lift`; grids
    /// are averaged down by a whole factor so that the mesh has at most about `max_cells` cells.
    fn mesh(&self, lift: bool, max_cells: usize) -> SurfaceMesh;
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
            fn add_hit(&mut self, cell: u32) { each!(self, s => s.add_hit(cell)) }
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
