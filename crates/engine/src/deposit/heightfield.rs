//! A regular grid of deposited thicknesses over a rectangle: splatting, the layer's slope, and
//! where a path enters the layer.

use super::pyramid::MaxPyramid;
use super::sums::{BlockSums, MEAN_SPAN, SUM_LEVELS};
use super::{Chart, Nodes};
use crate::checkpoint::{Dec, Enc, StateError};
use glam::DVec3;

/// Pyramid level at which the layer march first tries to skip samples: blocks of 16 × 16
/// cells. It climbs a level after each skip and descends after each failed attempt.
const SKIP_LEVEL: usize = 4;

/// Pyramid level whose blocks (16 × 16 cells) bound where the layer march starts.
const START_LEVEL: usize = 4;

/// Lowest level the march skips at (runs of 7 samples: fewer are not worth the look).
const SKIP_FLOOR: usize = 2;

/// Clearance above the blocks' maximum required to skip, m: far above the rounding of the
/// heights, so that no skipped sample could have tested inside.
const SKIP_MARGIN: f64 = 1e-9;

/// Lowest pyramid level whose nodes sleeping flights watch (blocks of 4 × 4 cells): the bound
/// under a flight close to the layer stays tight, and a single cell's growth wakes only the
/// flights over its block.
const WATCH_LEVEL: usize = 2;

use super::LayerContact;

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
}

impl HeightField {
    /// An empty field over a `width × height` (m) face with `cols × rows` cells. Each stuck
    /// particle's volume is spread evenly over the cells whose centres lie within
    /// `splat_radius` (m) of the hit cell's centre (just the hit cell when that is 0).
    pub fn new(width: f64, height: f64, cols: usize, rows: usize, splat_radius: f64) -> Self {
        let (dx, dy) = (width / cols as f64, height / rows as f64);
        let reach_x = (splat_radius / dx).floor() as isize;
        let reach_y = (splat_radius / dy).floor() as isize;
        let mut splat = Vec::new();
        for j in -reach_y..=reach_y {
            for i in -reach_x..=reach_x {
                let (x, y) = (i as f64 * dx, j as f64 * dy);
                if x * x + y * y <= splat_radius * splat_radius || (i == 0 && j == 0) {
                    splat.push((i, j));
                }
            }
        }
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

    fn raise_bounds(&mut self, c: usize, t: f64) {
        self.max_thickness = self.max_thickness.max(t);
        self.bounds.raise(c % self.cols, c / self.cols, t);
    }

    #[inline]
    fn mark(&mut self, c: usize) {
        self.changed.mark(c);
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
    pub fn add_hit(&mut self, cell: u32) {
        let h = &mut self.hits[cell as usize];
        *h = h.saturating_add(1);
    }

    /// Deposits `volume` (m³) centred on `cell`. The volume is shared evenly over the splat
    /// footprint's cells inside the grid, so Σ thickness × cell area grows by exactly `volume`
    /// (up to rounding), at the edges too.
    pub fn deposit(&mut self, cell: u32, volume: f64) {
        let (cols, rows) = (self.cols as isize, self.rows as isize);
        let (row, col) = (cell as isize / cols, cell as isize % cols);
        // The struck cell always takes its share (it is never a hole when struck).
        let hole = std::mem::take(&mut self.hole);
        let (ncols, wrap) = (self.cols, self.wrap);
        let target = |i: isize, j: isize| {
            let c = column_of(col + i, ncols, wrap).filter(|_| (0..rows).contains(&(row + j)))?;
            let k = (row + j) as usize * ncols + c;
            ((i, j) == (0, 0) || !hole.get(k).copied().unwrap_or(false)).then_some(k)
        };
        let n = self.splat.iter().filter(|&&(i, j)| target(i, j).is_some()).count();
        let added = volume / (n as f64 * self.cell_area());
        // The block sums are brought up to date once over the footprint's rectangle, or cell by
        // cell where it wraps round a periodic grid.
        let wraps = wrap && self.splat.iter().any(|&(i, _)| !(0..cols).contains(&(col + i)));
        let (mut lo, mut hi) = ((usize::MAX, usize::MAX), (0, 0));
        for k in 0..self.splat.len() {
            let (i, j) = self.splat[k];
            let Some(c) = target(i, j) else { continue };
            self.thickness[c] += added;
            self.raise_bounds(c, self.thickness[c]);
            self.mark(c);
            let (cc, cr) = (c % ncols, c / ncols);
            if wraps {
                self.sums.refresh(&self.thickness, &hole, (cc, cc), (cr, cr));
            }
            (lo, hi) = ((lo.0.min(cc), lo.1.min(cr)), (hi.0.max(cc), hi.1.max(cr)));
        }
        self.hole = hole;
        if !wraps && lo.0 <= hi.0 {
            self.refresh_sums((lo.0, hi.0), (lo.1, hi.1));
        }
    }

    /// Mean thickness over the cells whose centres lie within `radius` (m) of `cell`'s (all
    /// cells have the same area; holes do not count), m.
    ///
    /// A disc more than 12 cells wide in radius is averaged over blocks instead (of 2 × 2 cells
    /// and up, the first size at which it is at most 12 blocks wide): the blocks whose centres
    /// lie within `radius`, each weighed by its cells. The disc's rim moves by at most half a
    /// block, and the work no longer grows with the resolution.
    pub fn mean_around(&self, cell: u32, radius: f64) -> f64 {
        let (dx, dy) = self.cell_size();
        let (rx, ry) = ((radius / dx).floor() as isize, (radius / dy).floor() as isize);
        if rx == 0 && ry == 0 {
            return self.thickness[cell as usize];
        }
        let span = rx.max(ry) as usize;
        if span > MEAN_SPAN {
            let k = (1..=SUM_LEVELS).find(|&k| span >> k <= MEAN_SPAN).unwrap_or(SUM_LEVELS);
            // Whole blocks only round a periodic grid, and at most one turn of them.
            let side = 1 << k;
            if !self.wrap || (self.cols.is_multiple_of(side) && 2 * rx as usize + 2 * side < self.cols) {
                return self.block_mean(cell, radius, (rx, ry), k);
            }
        }
        let (cols, rows) = (self.cols as isize, self.rows as isize);
        let (row, col) = (cell as isize / cols, cell as isize % cols);
        let (mut sum, mut n) = (0.0, 0.0);
        // At most one full turn of a periodic grid, each column once.
        let rx = rx.min((cols - 1) / 2);
        let inside = |k: isize, y: f64| {
            let x = k as f64 * dx;
            x * x + y * y <= radius * radius
        };
        for j in (row - ry).max(0)..=(row + ry).min(rows - 1) {
            let y = (j - row) as f64 * dy;
            // The test is monotone in |i − col| (rounding is), so the row's cells in the disc
            // are those within `half` columns of `col`: found once, not cell by cell.
            let mut half = rx;
            while half >= 0 && !inside(half, y) {
                half -= 1;
            }
            // A row beyond the radius (its offset in whole cells can overshoot it).
            if half < 0 {
                continue;
            }
            let start = j as usize * self.cols;
            if !self.wrap && self.hole.is_empty() {
                // In the same order as below, so the sum is the same to the bit.
                let (first, last) = ((col - half).max(0) as usize, (col + half).min(cols - 1) as usize);
                for &t in &self.thickness[start + first..=start + last] {
                    sum += t;
                }
                // Exact: a whole count far below 2⁵³.
                n += (last - first + 1) as f64;
                continue;
            }
            for i in col - half..=col + half {
                let Some(ci) = self.column(i) else { continue };
                let c = start + ci;
                if !self.is_hole(c as u32) {
                    sum += self.thickness[c];
                    n += 1.0;
                }
            }
        }
        if n > 0.0 { sum / n } else { 0.0 }
    }

    /// [`HeightField::mean_around`] over the blocks of level `k` of the sums; `(rx, ry)` is the
    /// radius in whole cells along each axis.
    fn block_mean(&self, cell: u32, radius: f64, (rx, ry): (isize, isize), k: usize) -> f64 {
        let b = self.sums.level(k);
        let (dx, dy) = self.cell_size();
        let (row, col) = ((cell as usize / self.cols) as isize, (cell as usize % self.cols) as isize);
        let side = b.side as isize;
        // A block's centre, in cells from the grid's corner: its cells' centres' mean.
        let centre = |n: isize| (n * side) as f64 + 0.5 * (side - 1) as f64;
        let (mut sum, mut n) = (0.0, 0u32);
        for j in ((row - ry).max(0) >> k)..=((row + ry).min(self.rows as isize - 1) >> k) {
            let y = (centre(j) - row as f64) * dy;
            for i in (col - rx).div_euclid(side)..=(col + rx).div_euclid(side) {
                let Some(bi) = column_of(i, b.cols, self.wrap) else { continue };
                let x = (centre(i) - col as f64) * dx;
                if x * x + y * y <= radius * radius {
                    let at = j as usize * b.cols + bi;
                    sum += b.sum[at];
                    n += b.cells(bi, j as usize);
                }
            }
        }
        if n > 0 { sum / f64::from(n) } else { 0.0 }
    }

    /// An upper bound of every cell's thickness, m.
    pub fn max_thickness(&self) -> f64 {
        self.max_thickness
    }

    /// Thickness gradient `(∂t/∂u, ∂t/∂v)` at a cell, dimensionless: central differences
    /// across the deposit footprint (one-sided at the edges).
    pub fn gradient(&self, cell: u32) -> (f64, f64) {
        let (dx, dy) = self.cell_size();
        let (row, col) = (cell as usize / self.cols, cell as usize % self.cols);
        let at = |r: usize, c: usize| self.thickness[r * self.cols + c];
        let (r0, r1) = (row.saturating_sub(self.reach.1), (row + self.reach.1).min(self.rows - 1));
        let reach = self.reach.0.min((self.cols - 1) / 2) as isize;
        let (lo, hi) = (col as isize - reach, col as isize + reach);
        // Clamped to the grid, or across the seam of a periodic one.
        let c0 = self.column(lo).map_or((0, 0), |c| (c, lo));
        let c1 = self.column(hi).map_or((self.cols - 1, self.cols as isize - 1), |c| (c, hi));
        let span = (c1.1 - c0.1) as f64;
        let gu = if span > 0.0 { (at(row, c1.0) - at(row, c0.0)) / (span * dx) } else { 0.0 };
        let gv = if r1 > r0 { (at(r1, col) - at(r0, col)) / ((r1 - r0) as f64 * dy) } else { 0.0 };
        (gu, gv)
    }

    /// The nodes of the bounds (blocks of 4 × 4 cells or larger, or the root of a smaller field)
    /// that cover the cells under the rectangle `u` × `v` (m, in-face coordinates, clamped to
    /// the field), and the largest of their bounds, m.
    pub fn nodes_under(&self, u: (f64, f64), v: (f64, f64)) -> (Nodes, f64) {
        let (a, b) = (self.cell_at(u.0, v.0) as usize, self.cell_at(u.1, v.1) as usize);
        let ((c0, r0), (c1, r1)) = ((a % self.cols, a / self.cols), (b % self.cols, b / self.cols));
        let nodes = self.bounds.cover((c0, c1), (r0, r1), WATCH_LEVEL);
        (nodes, self.bounds.max_over(&self.thickness, &nodes))
    }

    /// An upper bound of the thickness over node `(col, row)` of level `level` of the bounds
    /// (blocks of `2ˡᵉᵛᵉˡ` cells; level 0: the cell), m.
    pub fn node_bound(&self, level: u32, col: u32, row: u32) -> f64 {
        self.bounds.bound(&self.thickness, level, col, row)
    }

    /// Column and row of the cell under `p`.
    #[inline]
    fn cell_of(&self, chart: &impl Chart, p: DVec3) -> (usize, usize) {
        let (u, v, _) = chart.local(p);
        let cell = self.cell_at(u, v) as usize;
        (cell % self.cols, cell / self.cols)
    }

    /// The segment's footprint: the columns and the rows of cells between its ends.
    fn footprint(&self, chart: &impl Chart, p0: DVec3, p1: DVec3) -> ((usize, usize), (usize, usize)) {
        let ((c0, r0), (c1, r1)) = (self.cell_of(chart, p0), self.cell_of(chart, p1));
        ((c0.min(c1), c0.max(c1)), (r0.min(r1), r0.max(r1)))
    }

    /// Largest bound over the 3 × 3 nodes of pyramid level `k` (blocks of `2ᵏ` cells) around
    /// the one under `p`, m.
    fn max_around(&self, chart: &impl Chart, p: DVec3, k: usize) -> f64 {
        let (c, r) = self.cell_of(chart, p);
        let (r, c) = (r >> k, c >> k);
        let (rr, cc) = ((self.rows - 1) >> k, (self.cols - 1) >> k);
        let mut top = 0.0_f64;
        for row in r.saturating_sub(1)..=(r + 1).min(rr) {
            for col in c.saturating_sub(1)..=(c + 1).min(cc) {
                top = top.max(self.bounds.node(k, col, row));
            }
        }
        top
    }

    /// Largest bound over the blocks of [`START_LEVEL`] (or the whole grid, if smaller) that
    /// hold cells of columns `cols` and rows `rows`, m.
    fn blocks_over(&self, cols: (usize, usize), rows: (usize, usize)) -> f64 {
        let height = self.bounds.height();
        if height < START_LEVEL {
            // A grid smaller than a block: its root (or its single cell) bounds it all.
            return if height == 0 { self.max_thickness } else { self.bounds.node(height, 0, 0) };
        }
        let mut top = 0.0_f64;
        for r in rows.0 >> START_LEVEL..=rows.1 >> START_LEVEL {
            for c in cols.0 >> START_LEVEL..=cols.1 >> START_LEVEL {
                top = top.max(self.bounds.node(START_LEVEL, c, r));
            }
        }
        top
    }

    /// Where the segment `p0 → p1` first enters the layer on the receiving side of the bare
    /// surface that `chart` unrolls this field onto. The layer is the surface raised by each
    /// cell's thickness; a segment that starts inside it enters only after leaving it. `None`
    /// if it does not enter before reaching the bare surface.
    #[inline]
    pub fn layer_contact(&self, chart: &impl Chart, p0: DVec3, p1: DVec3) -> Option<LayerContact> {
        let h0 = chart.local(p0).2;
        let h1 = chart.local(p1).2;
        // Most paths pass well above the thickest cell or behind the surface: that answer is
        // inlined, the search is not.
        if self.max_thickness <= 0.0 || h0 <= 0.0 || h0.min(h1) - chart.sag(p0, p1) > self.max_thickness {
            return None;
        }
        self.layer_contact_near(chart, (p0, p1), (h0, h1), true)
    }

    /// [`HeightField::layer_contact`] for a path that reaches below the thickest cell, with
    /// `h0` and `h1` its heights above the surface at its ends, m; `skip` lets the march pass
    /// over runs of samples above the layer (the answer is the same either way).
    #[inline(never)]
    fn layer_contact_near(
        &self,
        chart: &impl Chart,
        (p0, p1): (DVec3, DVec3),
        (h0, h1): (f64, f64),
        skip: bool,
    ) -> Option<LayerContact> {
        let sag = chart.sag(p0, p1);
        let (cols, rows) = self.footprint(chart, p0, p1);
        if h0.min(h1) - sag > self.bounds.max_in(&self.thickness, cols, rows) {
            return None;
        }
        // The thickest layer under the segment, from the blocks of 16 × 16 cells its footprint
        // covers: where the march starts (a tighter bound would move its samples).
        let top = self.blocks_over(cols, rows);
        // The part of the segment within the slab between the surface and (just above) the
        // thickest cell, so that a segment from above starts outside the layer even over its
        // peak. On a curved surface the chord may dip by `sag` between its ends: the whole
        // segment is searched then.
        let roof = top * (1.0 + 1e-9);
        let s_start = if h0 > roof && sag == 0.0 { (h0 - roof) / (h0 - h1) } else { 0.0 };
        let s_end = if h1 < 0.0 && sag == 0.0 { h0 / (h0 - h1) } else { 1.0 };
        // The column over the point at fraction `s`, if it lies over the surface.
        let column = |s: f64| -> Option<(u32, f64)> {
            let (u, v, h) = chart.local(p0.lerp(p1, s));
            chart.covers(u, v).then(|| (self.cell_at(u, v), h))
        };
        // On a flat surface the slab already ends at the surface; a curved one's search runs
        // on, and a point behind the surface is not in the layer.
        let inside = |s: f64| -> Option<u32> {
            let (cell, h) = column(s)?;
            let behind = sag > 0.0 && h < 0.0;
            (!behind && self.holds(cell, h)).then_some(cell)
        };
        // March at half a cell along the surface.
        let (dx, dy) = self.cell_size();
        let span = chart.along(p0, p1) * (s_end - s_start);
        let n = ((span / (0.5 * dx.min(dy))).ceil() as usize).clamp(1, 1 << 16);
        // Skipping relies on steps of at most half a cell, which the clamp of `n` could break.
        let fine = span <= n as f64 * 0.5 * dx.min(dy) && sag == 0.0;
        let sample = |k: usize| s_start + (s_end - s_start) * k as f64 / n as f64;
        let height = |s: f64| chart.local(p0.lerp(p1, s)).2;
        let mut was_inside = inside(s_start).is_some();
        let mut prev = s_start;
        let mut k = 1;
        let mut level = SKIP_LEVEL.min(self.bounds.height());
        while k <= n {
            let s = sample(k);
            // Skip a run of samples above the layer of the pyramid's nodes around this one: all
            // would test outside. A run of `2ᵏ⁺¹ − 1` samples half a cell apart stays within the
            // 3 × 3 nodes of level `k` around its first, and on a flat face its ends bound it.
            let run = ((2usize << level) - 1).min(n - k);
            if skip && fine && !was_inside && level >= SKIP_FLOOR && run >= 4 {
                let bound = self.max_around(chart, p0.lerp(p1, s), level) + SKIP_MARGIN;
                if height(s) > bound && height(sample(k + run)) > bound {
                    prev = sample(k + run);
                    k += run + 1;
                    level = (level + 1).min(self.bounds.height());
                    continue;
                }
                level -= 1;
            }
            let now = inside(s).is_some();
            if now && !was_inside {
                let (a, b) = self.entry(chart, (p0, p1), (prev, s), |m| inside(m).is_some());
                // `b` stays inside throughout the bisection.
                let entered = inside(b)?;
                // Through the side of a taller column, the material settles in the column the
                // particle came down (as in ballistic deposition); stacking it on the taller one
                // would let every column that gets ahead catch its neighbours' flux and grow
                // into a needle.
                let cell = column(a).map_or(entered, |(c, _)| c);
                return Some(self.contact(chart, p0.lerp(p1, b), b, entered, cell));
            }
            was_inside = now;
            prev = s;
            k += 1;
        }
        None
    }

    /// Narrows `[a, b]` of the path `p0 → p1`, `a` outside the layer and `b` inside (as
    /// `inside` says), to an entry (see [`bisect`]): by [`HeightField::entry_flat`] on a flat
    /// surface, else (or where that fails) by bisecting with `inside` itself.
    fn entry(
        &self,
        chart: &impl Chart,
        path: (DVec3, DVec3),
        (a, b): (f64, f64),
        inside: impl Fn(f64) -> bool,
    ) -> (f64, f64) {
        self.entry_flat(chart, path, (a, b), &inside).unwrap_or_else(|| bisect(a, b, inside))
    }

    /// [`HeightField::entry`] on a flat surface, where the in-face coordinates and the height
    /// are affine along the path: the halvings interpolate them instead of mapping each point
    /// into the chart. The ends found are checked with `inside`; `None` where rounding makes
    /// the two disagree there, or the surface is curved. Where `[a, b]` holds several entries
    /// (past a hole, into a neighbouring column) the two bisections may settle on different
    /// ones: the contact is then another true entry within the same half cell.
    fn entry_flat(
        &self,
        chart: &impl Chart,
        (p0, p1): (DVec3, DVec3),
        (a, b): (f64, f64),
        inside: impl Fn(f64) -> bool,
    ) -> Option<(f64, f64)> {
        chart.uniform_normal()?;
        let (l0, l1) = (DVec3::from(chart.local(p0)), DVec3::from(chart.local(p1)));
        let d = l1 - l0;
        // The cell over the point at fraction `m`, if the surface covers it, and the point's
        // height above the bare surface.
        let column = |m: f64| {
            let l = l0 + d * m;
            (chart.covers(l.x, l.y).then(|| self.cell_at(l.x, l.y)), l.z)
        };
        let (mut a, mut b) = (a, b);
        let (mut over_a, mut over_b) = (column(a).0, column(b).0);
        for halving in 0..BISECTIONS {
            // Each interpolated in-face coordinate is monotone along the path, and so is the
            // column (or row) it falls in; the points the surface covers form one stretch of
            // it. Once both ends lie over one covered cell, so does every point between them,
            // and only the height is left to compare.
            if let (Some(ca), Some(cb)) = (over_a, over_b)
                && ca == cb
            {
                let (solid, top) = (!self.is_hole(ca), self.thickness[ca as usize]);
                for _ in halving..BISECTIONS {
                    let m = 0.5 * (a + b);
                    let held = solid & ((l0.z + d.z * m) <= top);
                    (a, b) = if held { (a, m) } else { (m, b) };
                }
                break;
            }
            let m = 0.5 * (a + b);
            let (cell, h) = column(m);
            if cell.is_some_and(|c| self.holds(c, h)) {
                (b, over_b) = (m, cell);
            } else {
                (a, over_a) = (m, cell);
            }
        }
        (!inside(a) && inside(b)).then_some((a, b))
    }

    /// The contact at `point` (fraction `s` of the path), entering cell `entered` and settling
    /// in `cell`: its normal is the layer's, from the thickness gradient.
    fn contact(&self, chart: &impl Chart, point: DVec3, s: f64, entered: u32, cell: u32) -> LayerContact {
        let (gu, gv) = self.gradient(entered);
        let (u, v, _) = chart.local(point);
        let (n, right, up) = chart.frame(u, v);
        let normal = (n - right * gu - up * gv).normalize();
        LayerContact { s, point, normal, cell }
    }

    /// Σ thickness × cell area: the volume held by the field, m³.
    pub fn volume(&self) -> f64 {
        self.thickness.iter().sum::<f64>() * self.cell_area()
    }
}

/// Halvings that narrow a path's entry into the layer.
const BISECTIONS: usize = 32;

/// Narrows `[a, b]`, with `a` outside and `b` inside, to the entry by [`BISECTIONS`] halvings;
/// returns the last outside and inside fractions.
fn bisect(mut a: f64, mut b: f64, inside: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..BISECTIONS {
        let m = 0.5 * (a + b);
        if inside(m) {
            b = m;
        } else {
            a = m;
        }
    }
    (a, b)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Face;

    /// Uniform numbers in [0, 1) from a linear congruential generator seeded with `seed`.
    fn uniform(mut x: u64) -> impl FnMut() -> f64 {
        move || {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Whether the point at fraction `s` of the path `p0 → p1` lies in `f`'s layer on `face`,
    /// each point mapped into the chart as the march maps it.
    fn inside_of(f: &HeightField, face: Face, p0: DVec3, p1: DVec3) -> impl Fn(f64) -> bool + '_ {
        move |s: f64| {
            let (u, v, h) = Chart::local(&face, p0.lerp(p1, s));
            let cell = f.cell_at(u, v);
            Chart::covers(&face, u, v) && f.holds(cell, h)
        }
    }

    #[test]
    fn cells_grow_right_and_up_from_the_bottom_left() {
        let f = HeightField::new(2.0, 1.0, 4, 2, 0.0);
        assert_eq!(f.cell_at(-0.99, -0.49), 0);
        assert_eq!(f.cell_at(0.99, -0.49), 3);
        assert_eq!(f.cell_at(-0.99, 0.49), 4);
        assert_eq!(f.cell_at(1.0, 0.5), 7, "the far edge belongs to the last cell");
        assert_eq!(f.cell_at(-0.1, 0.1), 5);
    }

    /// The pyramid lets the march skip runs of samples; skipping must find the very contact
    /// the full march finds, on a rough layer, for steep and grazing paths alike.
    #[test]
    fn skipping_over_the_pyramid_finds_the_same_contact_as_the_full_march() {
        let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
        let mut f = HeightField::new(1.0, 1.0, 300, 200, 0.004);
        let mut next = uniform(7);
        // Sparse tall spikes over a thin film: most of the path lies just above the film.
        for _ in 0..3000 {
            let cell = (next() * 60_000.0) as u32;
            f.deposit(cell, 2e-9 * next());
        }
        for _ in 0..40 {
            let cell = (next() * 60_000.0) as u32;
            f.deposit(cell, 2e-7 * next());
        }
        let (mut met, top) = (0, f.max_thickness());
        for _ in 0..4000 {
            let p0 = DVec3::new(next() - 0.5, next() - 0.5, top * (0.5 + 2.0 * next()));
            let p1 = DVec3::new(next() - 0.5, next() - 0.5, top * (1.5 * next() - 0.3));
            let (h0, h1) = (p0.z, p1.z);
            if h0 <= 0.0 {
                continue;
            }
            let fast = f.layer_contact_near(&face, (p0, p1), (h0, h1), true);
            assert_eq!(fast, f.layer_contact_near(&face, (p0, p1), (h0, h1), false), "{p0} → {p1}");
            met += usize::from(fast.is_some());
        }
        assert!(met > 100, "only {met} contacts");
    }

    /// On a flat face the entry into the layer is narrowed over interpolated coordinates: on a
    /// rough layer with holes, it must be accepted by the path's own test (outside before,
    /// inside after) nearly always, and then agree with the plain bisection nearly always
    /// (where a half cell holds several entries the two may settle on different ones).
    #[test]
    fn the_entry_on_a_flat_face_is_the_bisection_of_the_path_itself() {
        let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
        let mut f = HeightField::new(1.0, 1.0, 200, 100, 0.0);
        f.set_holes((0..20_000).map(|c| c % 13 == 5).collect());
        let mut next = uniform(11);
        for c in 0..20_000 {
            f.add(c, 1e-3 * (0.2 + next()));
        }
        let (mut tried, mut accepted, mut same) = (0, 0, 0);
        while tried < 3000 {
            let p0 = DVec3::new(next() - 0.5, next() - 0.5, 2e-3 + 1e-2 * next());
            let p1 = DVec3::new(next() - 0.5, next() - 0.5, 1e-4);
            let inside = inside_of(&f, face, p0, p1);
            if inside(0.0) || !inside(1.0) {
                continue;
            }
            tried += 1;
            let Some((a, b)) = f.entry_flat(&face, (p0, p1), (0.0, 1.0), &inside) else { continue };
            accepted += 1;
            assert!(!inside(a) && inside(b) && b - a < 1e-9, "{p0} → {p1}: {a} {b}");
            same += usize::from((a, b) == bisect(0.0, 1.0, &inside));
        }
        assert!(accepted > 2950, "only {accepted} of {tried} interpolated entries accepted");
        assert!(same > 2900, "only {same} of {tried} entries as the plain bisection finds them");
    }

    /// Once both ends of the bracket lie over one cell, the flat narrowing compares heights
    /// only: it must return, to the bit, what halving with every midpoint mapped to its cell
    /// returns, over long and short brackets, across holes, edges and cell borders.
    #[test]
    fn narrowing_within_one_cell_finds_the_bracket_of_the_full_bisection() {
        let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [1.0, 1.0]);
        let mut f = HeightField::new(1.0, 1.0, 50, 40, 0.0);
        f.set_holes((0..2000).map(|c| c % 7 == 3).collect());
        let mut next = uniform(5);
        for c in 0..2000 {
            f.add(c, 1e-2 * (0.2 + next()));
        }
        let (mut compared, mut found) = (0, 0);
        for k in 0..20_000 {
            // Paths over the face and past its edges, steep and grazing.
            let p0 = DVec3::new(1.2 * (next() - 0.5), 1.2 * (next() - 0.5), 2e-2 * next());
            let p1 = p0 + DVec3::new(0.1 * (next() - 0.5), 0.1 * (next() - 0.5), -2e-2 * next());
            let inside = inside_of(&f, face, p0, p1);
            let (l0, l1) = (DVec3::from(Chart::local(&face, p0)), DVec3::from(Chart::local(&face, p1)));
            let mapped = |m: f64| {
                let l = l0 + (l1 - l0) * m;
                Chart::covers(&face, l.x, l.y) && f.holds(f.cell_at(l.x, l.y), l.z)
            };
            // Whole paths, and brackets of a fiftieth of one (a cell or so).
            let (a, b) = if k % 2 == 0 {
                (0.0, 1.0)
            } else {
                let a = 0.98 * next();
                (a, a + 0.02)
            };
            let (ea, eb) = bisect(a, b, mapped);
            // The bracket itself, before the path's own test accepts it (which hides any
            // difference over a hole: neither end is inside there).
            if ea != eb {
                let raw = f.entry_flat(&face, (p0, p1), (a, b), |s| s == eb);
                assert_eq!(raw, Some((ea, eb)), "{p0} → {p1} over [{a}, {b}]");
            }
            let plain = (!inside(ea) && inside(eb)).then_some((ea, eb));
            assert_eq!(f.entry_flat(&face, (p0, p1), (a, b), inside), plain, "{p0} → {p1} over [{a}, {b}]");
            compared += 1;
            found += usize::from(plain.is_some());
        }
        assert!(found > compared / 20, "only {found} entries in {compared} brackets");
    }

    /// The disc mean by brute force over cells, holes left out.
    fn cell_mean(f: &HeightField, cell: u32, radius: f64) -> f64 {
        let (dx, dy) = f.cell_size();
        let (row, col) = ((cell as usize / f.cols) as isize, (cell as usize % f.cols) as isize);
        let (mut sum, mut n) = (0.0, 0.0);
        for c in 0..f.thickness.len() {
            let (j, i) = ((c / f.cols) as isize, (c % f.cols) as isize);
            let di = if f.wrap { (i - col).rem_euclid(f.cols as isize) } else { i - col };
            let di = if f.wrap && di > f.cols as isize / 2 { di - f.cols as isize } else { di };
            let (x, y) = (di as f64 * dx, (j - row) as f64 * dy);
            if x * x + y * y <= radius * radius && !f.is_hole(c as u32) {
                sum += f.thickness[c];
                n += 1.0;
            }
        }
        sum / n
    }

    /// The disc mean over cells, cell by cell in row-major order (the order the engine sums
    /// in), each tested against the disc: the reference the row-span sum must match to the bit.
    fn ordered_mean(f: &HeightField, cell: u32, radius: f64) -> f64 {
        let (dx, dy) = f.cell_size();
        let (cols, rows) = (f.cols as isize, f.rows as isize);
        let (row, col) = (cell as isize / cols, cell as isize % cols);
        let (rx, ry) = ((radius / dx).floor() as isize, (radius / dy).floor() as isize);
        let rx = rx.min((cols - 1) / 2);
        let (mut sum, mut n) = (0.0, 0.0);
        for j in (row - ry).max(0)..=(row + ry).min(rows - 1) {
            for i in col - rx..=col + rx {
                let Some(ci) = f.column(i) else { continue };
                let (x, y) = ((i - col) as f64 * dx, (j - row) as f64 * dy);
                let c = j as usize * f.cols + ci;
                if x * x + y * y <= radius * radius && !f.is_hole(c as u32) {
                    sum += f.thickness[c];
                    n += 1.0;
                }
            }
        }
        if n > 0.0 { sum / n } else { 0.0 }
    }

    /// Regression for the row-span disc mean (the cushion under every impact): on a rough
    /// layer, flat or periodic, with and without holes, at radii that put cells exactly on the
    /// rim, it equals the cell-by-cell mean to the bit, at the edges and round the seam.
    #[test]
    fn the_disc_mean_by_rows_is_the_cell_by_cell_mean_to_the_bit() {
        let (cols, rows) = (61, 37);
        let mut noise = 0x9E37_79B9_7F4A_7C15_u64;
        for (wrap, holes) in [(false, false), (false, true), (true, false), (true, true)] {
            let mut f = HeightField::new(0.61, 0.37, cols, rows, 0.0); // 10 mm cells
            f.set_wrap(wrap);
            if holes {
                f.set_holes((0..cols * rows).map(|c| c % 7 == 3).collect());
            }
            for c in 0..cols * rows {
                noise ^= noise << 13;
                noise ^= noise >> 7;
                noise ^= noise << 17;
                f.add(c as u32, (noise >> 11) as f64 / (1u64 << 53) as f64 * 1e-2);
            }
            // 0.05 and 0.1 put cells on the rim (3-4-5 and 6-8-10 triangles), where rounding decides.
            for radius in [0.012, 0.03, 0.05, 0.0734, 0.1] {
                for c in [0, 30, cols - 1, 18 * cols, 18 * cols + 30, cols * rows - 1, 36 * cols + 2] {
                    let (m, want) = (f.mean_around(c as u32, radius), ordered_mean(&f, c as u32, radius));
                    assert_eq!(
                        m.to_bits(),
                        want.to_bits(),
                        "wrap {wrap}, holes {holes}, r {radius}, cell {c}"
                    );
                }
            }
        }
    }

    /// Regression: a row whose offset in whole cells overshoots the radius (4 mm cells, 36 mm:
    /// nine rows of 4 mm make 36.000000000000004 mm) holds no cell of the disc, at the grid's
    /// edge too, where its span would start before the first column.
    #[test]
    fn a_row_beyond_the_radius_adds_nothing_to_the_disc_mean() {
        let (side, cols) = (0.4, 100);
        let (radius, dy) = (0.036, side / cols as f64);
        assert!(9.0 * dy > radius && (radius / dy).floor() == 9.0, "the outer rows must overshoot");
        let mut f = HeightField::new(side, side, cols, cols, 0.0);
        for c in 0..cols * cols {
            f.add(c as u32, 1e-4 * (c % 17) as f64);
        }
        for c in [0, 10 * cols, 50 * cols, 99 * cols, 50 * cols + 99, 50 * cols + 50] {
            let (m, want) = (f.mean_around(c as u32, radius), ordered_mean(&f, c as u32, radius));
            assert_eq!(m.to_bits(), want.to_bits(), "cell {c}: {m} against {want}");
        }
    }

    /// A disc 20 cells wide in radius is averaged over 2 × 2 blocks: on a uniform layer with
    /// holes it gives the layer exactly, and on a sloping one it moves the mean from the mean
    /// over cells (whose disc is centred) by no more than the slope over half a cell.
    #[test]
    fn a_wide_mean_over_blocks_agrees_with_the_mean_over_cells() {
        for wrap in [false, true] {
            let (cols, rows) = (160, 90);
            let mut f = HeightField::new(0.4, 0.225, cols, rows, 0.0); // 2.5 mm cells
            f.set_wrap(wrap);
            f.set_holes((0..cols * rows).map(|c| (c / cols) % 17 == 4 && c % 5 == 0).collect());
            let radius = 0.05;
            for c in 0..cols * rows {
                f.add(c as u32, 1e-3);
            }
            let probes = [0, 77, 5 * cols + 3, 45 * cols + 80, 89 * cols + 159, 30 * cols + 158];
            for &c in &probes {
                let (m, want) = (f.mean_around(c as u32, radius), cell_mean(&f, c as u32, radius));
                assert!((m - 1e-3).abs() < 1e-15 && (want - 1e-3).abs() < 1e-15, "uniform, {c}: {m} {want}");
            }
            // A slope of 0.02 along both axes (periodic along the columns on a wrapped grid).
            let slope = 0.02;
            for c in 0..cols * rows {
                let (i, j) = ((c % cols) as f64, (c / cols) as f64);
                let u = if wrap {
                    0.4 / std::f64::consts::TAU * (std::f64::consts::TAU * i / cols as f64).sin()
                } else {
                    i * 2.5e-3
                };
                f.add(c as u32, slope * (u + j * 2.5e-3));
            }
            for &c in &probes {
                let (m, want) = (f.mean_around(c as u32, radius), cell_mean(&f, c as u32, radius));
                // A block's centre lies half a cell (1.25 mm) from the centre of its cells nearest
                // the disc's centre.
                assert!((m - want).abs() <= slope * 1.25e-3, "wrap {wrap}, cell {c}: {m} against {want}");
            }
        }
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

    #[test]
    fn splat_conserves_volume_everywhere_and_spreads_in_the_interior() {
        let mut f = HeightField::new(1.0, 1.0, 100, 100, 0.03);
        for cell in [0, 99, 5050, 9999, 150] {
            f.deposit(cell, 1e-6);
        }
        assert!((f.volume() - 5e-6).abs() < 1e-18);
        // Interior splat: the cells within 3 cell widths, 29 of them, share it evenly.
        let mut g = HeightField::new(1.0, 1.0, 100, 100, 0.03);
        g.deposit(5050, 29e-4 * 1e-4);
        let touched: Vec<f64> = g.thickness().iter().copied().filter(|&t| t > 0.0).collect();
        assert_eq!(touched.len(), 29);
        assert!(touched.iter().all(|&t| (t - 1e-4).abs() < 1e-15));
    }
}
