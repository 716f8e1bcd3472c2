//! A regular grid of deposited thicknesses over a rectangle (a flat face, or a shell's unrolled
//! surface): its storage, and what keeps the stored bounds and block sums in step with it.
//!
//! The jobs on top of the storage live in the submodules: `splat` spreads a stuck particle's
//! volume over the cells around the struck one, `means` averages the layer over a disc (the
//! cushion under an impact), and `contact` marches a path into the layer and bounds the layer
//! under a box.

mod contact;
mod means;
mod splat;

pub use splat::footprint_cells;

use super::pyramid::MaxPyramid;
use super::sums::BlockSums;
use crate::checkpoint::{Dec, Enc, StateError};

/// A regular grid over a target face recording deposited thickness and impact counts.
///
/// Row index grows along the face's `up`, column index along its `right` (`up × normal`, the
/// viewer's right looking at the face from the spray side). Cell `(row, col)` is stored at
/// `row * cols + col`; row 0 is the bottom edge.
#[derive(Clone, Debug)]
pub struct HeightField {
    cols: usize,
    rows: usize,
    width: f64,
    height: f64,
    /// Area of one cell, m² (kept: metrics read it per cell).
    cell_area: f64,
    thickness: Vec<f64>,
    hits: Vec<u32>,
    /// Upper bound of the thickness, m (never lowered by removals).
    max_thickness: f64,
    /// Upper bounds of the thickness over blocks of every power-of-two size, m: bound the
    /// layer under a path without visiting its cells.
    bounds: MaxPyramid,
    /// Sums of the thickness over blocks of 2 × 2 to 8 × 8 cells: a mean over a wide disc
    /// visits blocks, not cells.
    sums: BlockSums,
    /// Cell offsets `(col, row)` of the deposit footprint.
    splat: Vec<(isize, isize)>,
    /// Half-width of the footprint in cells `(cols, rows)`, at least 1: the scale at which the
    /// layer's slope is measured (finer, the slope would be the deposit's speckle).
    reach: (usize, usize),
    /// The cells whose thickness changed since the last `take_changed`.
    changed: ChangedCells,
    /// Per cell, true where the surface is cut away (an opening); empty when none is.
    hole: Vec<bool>,
    /// The columns are periodic (a full turn of a shell).
    wrap: bool,
    /// The cells changed since a copy of the layer elsewhere (the GPU's) was last brought up to
    /// date.
    revised: Revised,
}

impl HeightField {
    /// An empty field over a `width × height` (m) face with `cols × rows` cells. Each stuck
    /// particle's volume is spread evenly over the cells whose centres lie within
    /// `splat_radius` (m) of the hit cell's centre (just the hit cell when that is 0).
    pub fn new(width: f64, height: f64, cols: usize, rows: usize, splat_radius: f64) -> Self {
        let (dx, dy) = (width / cols as f64, height / rows as f64);
        let (splat, (reach_x, reach_y)) = splat::footprint((dx, dy), splat_radius);
        HeightField {
            cols,
            rows,
            width,
            height,
            cell_area: (width / cols as f64) * (height / rows as f64),
            thickness: vec![0.0; cols * rows],
            hits: vec![0; cols * rows],
            max_thickness: 0.0,
            bounds: MaxPyramid::new(cols, rows),
            sums: BlockSums::new(cols, rows),
            reach: (reach_x.max(1) as usize, reach_y.max(1) as usize),
            splat,
            changed: ChangedCells::new(cols * rows),
            hole: Vec::new(),
            wrap: false,
            revised: Revised::new(cols * rows),
        }
    }

    /// Writes what deposition changes (thicknesses, impacts, bounds, changed cells).
    pub(crate) fn save_state(&self, e: &mut Enc) {
        e.list(&self.thickness, |e, &x| e.f64(x));
        e.list(&self.hits, |e, &x| e.u32(x));
        e.f64(self.max_thickness);
        self.bounds.save_state(e);
        e.list(&self.changed.0, |e, &x| e.u64(x));
    }

    /// Reads what [`HeightField::save_state`] wrote, over a field of the same size.
    pub(crate) fn load_state(&mut self, d: &mut Dec<'_>) -> Result<(), StateError> {
        let n = self.thickness.len();
        self.thickness = d.list_of(n, "a heightfield's thickness", 8, Dec::f64)?;
        self.hits = d.list_of(n, "a heightfield's impacts", 4, Dec::u32)?;
        self.max_thickness = d.f64()?;
        self.bounds.load_state(d)?;
        self.changed.0 = d.list_of(self.changed.0.len(), "a heightfield's changes", 8, Dec::u64)?;
        // A copy of the layer elsewhere no longer holds this one.
        self.revised = Revised::new(n);
        // Made afresh from the thicknesses, exactly as they were kept.
        self.refresh_sums((0, self.cols - 1), (0, self.rows - 1));
        Ok(())
    }

    /// Marks the cells cut away (one flag per cell): they receive no deposit, count in no mean,
    /// and a layer never stands in them.
    pub fn set_holes(&mut self, hole: Vec<bool>) {
        debug_assert_eq!(hole.len(), self.thickness.len());
        self.hole = if hole.iter().any(|&h| h) { hole } else { Vec::new() };
        self.sums.recount(&self.hole);
        // Holes count as empty: sums over a layer already laid change.
        if self.max_thickness > 0.0 {
            self.refresh_sums((0, self.cols - 1), (0, self.rows - 1));
        }
    }

    /// Makes the columns periodic (`true`): column `cols` is column 0 again, as on a full turn
    /// of a shell, for the splat, means, gradients and neighbours.
    pub fn set_wrap(&mut self, wrap: bool) {
        self.wrap = wrap;
    }

    /// The column `c` stands for: itself inside the grid, the one it wraps round to on a
    /// periodic grid, or `None` beyond an edge.
    #[inline]
    pub fn column(&self, c: isize) -> Option<usize> {
        column_of(c, self.cols, self.wrap)
    }

    /// True if `cell` is cut away.
    #[inline]
    pub fn is_hole(&self, cell: u32) -> bool {
        self.hole.get(cell as usize).copied().unwrap_or(false)
    }

    /// True if a point `h` (m) above the bare surface over `cell` lies in the layer: the cell
    /// is solid and its thickness reaches `h`.
    #[inline]
    fn holds(&self, cell: u32, h: f64) -> bool {
        h <= self.thickness[cell as usize] && !self.is_hole(cell)
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Cell size `(along the width, along the height)`, m.
    pub fn cell_size(&self) -> (f64, f64) {
        (self.width / self.cols as f64, self.height / self.rows as f64)
    }

    /// Cell offsets `(col, row)` of the deposit footprint around a struck cell, the struck cell
    /// `(0, 0)` among them (see [`HeightField::footprint`]).
    pub fn splat_offsets(&self) -> &[(isize, isize)] {
        &self.splat
    }

    /// True if the columns are periodic (a full turn of a shell).
    pub fn wraps(&self) -> bool {
        self.wrap
    }

    /// Removes up to `volume` (m³) from `cell`; returns the volume removed.
    pub fn remove(&mut self, cell: u32, volume: f64) -> f64 {
        let area = self.cell_area();
        let t = &mut self.thickness[cell as usize];
        let take = (volume / area).min(*t);
        *t -= take;
        self.mark(cell as usize);
        self.refresh_cell(cell as usize);
        take * area
    }

    /// Adds `dt` (m, negative to remove) to `cell`'s thickness, never below 0, keeping the
    /// bounds of the thickness up to date.
    pub fn add(&mut self, cell: u32, dt: f64) {
        let c = cell as usize;
        let t = (self.thickness[c] + dt).max(0.0);
        self.thickness[c] = t;
        self.raise_bounds(c, t);
        self.mark(c);
        self.refresh_cell(c);
    }

    /// Brings the block sums over cell `c` up to date.
    fn refresh_cell(&mut self, c: usize) {
        let (col, row) = (c % self.cols, c / self.cols);
        self.refresh_sums((col, col), (row, row));
    }

    /// Brings the block sums over columns `cols` and rows `rows` (inclusive) up to date.
    fn refresh_sums(&mut self, cols: (usize, usize), rows: (usize, usize)) {
        self.sums.refresh(&self.thickness, &self.hole, cols, rows);
    }

    /// Raises the bounds of the thickness (the largest, and the pyramid's over cell `c`) to
    /// `t` (m), cell `c`'s thickness now.
    fn raise_bounds(&mut self, c: usize, t: f64) {
        self.max_thickness = self.max_thickness.max(t);
        self.bounds.raise(c % self.cols, c / self.cols, t);
    }

    /// Marks cell `c` changed, for the layer stages and for copies of the layer.
    #[inline]
    fn mark(&mut self, c: usize) {
        self.changed.mark(c);
        self.revised.cells.mark(c);
    }

    /// The cells whose thickness changed since the last call, ascending, with the layer's
    /// identity: a copy of the layer elsewhere (the GPU's) that holds this identity is brought
    /// up to date by these cells; one that holds another must copy the whole layer. A new field,
    /// a clone and a restored one each have an identity of their own.
    pub fn take_revised(&mut self) -> (u64, Vec<u32>) {
        (self.revised.identity, self.revised.cells.take())
    }

    /// Gives the layer a new identity, so that no copy made before (a GPU's) is brought up to
    /// date by later changes: the next copy is made whole.
    pub fn forget_copies(&mut self) {
        self.revised = Revised::new(self.thickness.len());
    }

    /// The cells whose thickness changed since the last call, ascending.
    pub fn take_changed(&mut self) -> Vec<u32> {
        self.changed.take()
    }

    /// In-face coordinates `(along right, along up)` of a cell's centre, m from the face's centre.
    pub fn cell_center(&self, cell: u32) -> (f64, f64) {
        let (dx, dy) = self.cell_size();
        let (row, col) = (cell as usize / self.cols, cell as usize % self.cols);
        ((col as f64 + 0.5) * dx - self.width / 2.0, (row as f64 + 0.5) * dy - self.height / 2.0)
    }

    /// Area of one cell, m².
    #[inline]
    pub fn cell_area(&self) -> f64 {
        self.cell_area
    }

    /// Thickness per cell, m, row-major from the bottom row.
    pub fn thickness(&self) -> &[f64] {
        &self.thickness
    }

    /// Impacts per cell (stuck or rebounded), row-major from the bottom row.
    pub fn hits(&self) -> &[u32] {
        &self.hits
    }

    /// Cell index of in-face coordinates `(u, v)` (m from the face centre along right and up),
    /// clamped to the grid so that hits on the very edge land in the edge cells.
    #[inline]
    pub fn cell_at(&self, u: f64, v: f64) -> u32 {
        // Clamped to ≥ 0 first, so that truncation is a floor.
        let col = ((((u / self.width) + 0.5) * self.cols as f64).max(0.0) as usize).min(self.cols - 1);
        let row = ((((v / self.height) + 0.5) * self.rows as f64).max(0.0) as usize).min(self.rows - 1);
        (row * self.cols + col) as u32
    }

    /// Counts one impact in `cell`.
    pub fn add_hits(&mut self, cell: u32, n: u32) {
        let h = &mut self.hits[cell as usize];
        *h = h.saturating_add(n);
    }

    /// An upper bound of every cell's thickness, m.
    pub fn max_thickness(&self) -> f64 {
        self.max_thickness
    }

    /// Σ thickness × cell area: the volume held by the field, m³.
    pub fn volume(&self) -> f64 {
        self.thickness.iter().sum::<f64>() * self.cell_area()
    }
}

/// Column `c` of a grid of `cols` columns: itself inside, wrapped round when `wrap`, or `None`.
#[inline]
fn column_of(c: isize, cols: usize, wrap: bool) -> Option<usize> {
    let n = cols as isize;
    if (0..n).contains(&c) {
        Some(c as usize)
    } else if wrap {
        Some(c.rem_euclid(n) as usize)
    } else {
        None
    }
}

/// A set of cells, one bit each: the cells whose thickness changed since the layer stages last
/// asked, so that slump and cohesion look only there.
#[derive(Clone, Debug)]
pub(crate) struct ChangedCells(pub(crate) Vec<u64>);

impl ChangedCells {
    /// An empty set over `cells` cells.
    pub(crate) fn new(cells: usize) -> ChangedCells {
        ChangedCells(vec![0; cells.div_ceil(64)])
    }

    /// Adds cell `c` to the set.
    #[inline]
    pub(crate) fn mark(&mut self, c: usize) {
        self.0[c / 64] |= 1 << (c % 64);
    }

    /// The cells marked, ascending, leaving the set empty.
    pub(crate) fn take(&mut self) -> Vec<u32> {
        let mut out = Vec::new();
        for (w, word) in self.0.iter_mut().enumerate() {
            let mut bits = std::mem::take(word);
            while bits != 0 {
                out.push((w * 64) as u32 + bits.trailing_zeros());
                bits &= bits - 1;
            }
        }
        out
    }
}

/// The cells changed since a copy of the layer was last brought up to date, and the identity
/// of the layer they are changes of (see [`HeightField::take_revised`]). Not part of the state:
/// it prints as nothing, and a clone takes a new identity.
struct Revised {
    identity: u64,
    cells: ChangedCells,
}

impl Revised {
    /// No cell changed, under a new identity.
    fn new(cells: usize) -> Revised {
        static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        Revised {
            identity: NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed),
            cells: ChangedCells::new(cells),
        }
    }
}

impl Clone for Revised {
    fn clone(&self) -> Revised {
        Revised::new(64 * self.cells.0.len())
    }
}

impl std::fmt::Debug for Revised {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("_")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deposit::sums::SUM_LEVELS;

    #[test]
    fn cells_grow_right_and_up_from_the_bottom_left() {
        let f = HeightField::new(2.0, 1.0, 4, 2, 0.0);
        assert_eq!(f.cell_at(-0.99, -0.49), 0);
        assert_eq!(f.cell_at(0.99, -0.49), 3);
        assert_eq!(f.cell_at(-0.99, 0.49), 4);
        assert_eq!(f.cell_at(1.0, 0.5), 7, "the far edge belongs to the last cell");
        assert_eq!(f.cell_at(-0.1, 0.1), 5);
    }
    /// Deposits, additions and removals, round the seam of a periodic grid and beside holes,
    /// keep every block sum equal to the sum made afresh from the cells.
    #[test]
    fn the_block_sums_follow_every_change_of_the_layer() {
        let (cols, rows) = (48, 20);
        let mut f = HeightField::new(0.48, 0.2, cols, rows, 0.03);
        f.set_wrap(true);
        f.set_holes((0..cols * rows).map(|c| c % 11 == 2).collect());
        for (k, &cell) in [0u32, 47, 500, 959, 24, 13].iter().enumerate() {
            f.deposit(cell, 1e-7 * (k + 1) as f64);
        }
        f.add(30, 2e-3);
        f.remove(47, 1e-8);
        f.add(500, -1e-3);
        let mut fresh = BlockSums::new(cols, rows);
        fresh.recount(&f.hole);
        fresh.refresh(&f.thickness, &f.hole, (0, cols - 1), (0, rows - 1));
        for k in 1..=SUM_LEVELS {
            assert_eq!(f.sums.level(k).sum, fresh.level(k).sum, "level {k}");
            let (a, b) = (f.sums.level(k), fresh.level(k));
            for at in 0..a.sum.len() {
                assert_eq!(a.cells(at % a.cols, at / a.cols), b.cells(at % b.cols, at / b.cols), "level {k}");
            }
        }
    }
}
