//! A regular grid of deposited thicknesses over a rectangle: splatting, the layer's slope, and
//! where a path enters the layer.

use super::Chart;
use crate::checkpoint::{Dec, Enc, StateError};
use glam::DVec3;

/// Side of the blocks whose maximum thickness is kept, cells.
const BLOCK: usize = 16;

/// Samples of the layer march skipped at once above low blocks. The march steps at most half a
/// cell along the face, so `2 BLOCK − 1` steps move less than one block: the samples skipped
/// stay within the 3 × 3 blocks around the first.
const SKIP_RUN: usize = 2 * BLOCK - 1;

/// Clearance above the blocks' maximum required to skip, m: far above the rounding of the
/// heights, so that no skipped sample could have tested inside.
const SKIP_MARGIN: f64 = 1e-9;

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
    thickness: Vec<f64>,
    hits: Vec<u32>,
    /// Upper bound of the thickness, m (never lowered by removals).
    max_thickness: f64,
    /// Upper bound of the thickness per block of `BLOCK × BLOCK` cells, m: bounds the layer
    /// under a segment without visiting its cells.
    block_max: Vec<f64>,
    /// Blocks per row.
    block_cols: usize,
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
            thickness: vec![0.0; cols * rows],
            hits: vec![0; cols * rows],
            max_thickness: 0.0,
            block_max: vec![0.0; cols.div_ceil(BLOCK) * rows.div_ceil(BLOCK)],
            block_cols: cols.div_ceil(BLOCK),
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
        e.list(&self.block_max, |e, &x| e.f64(x));
        e.list(&self.changed.0, |e, &x| e.u64(x));
    }

    /// Reads what [`HeightField::save_state`] wrote, over a field of the same size.
    pub(crate) fn load_state(&mut self, d: &mut Dec<'_>) -> Result<(), StateError> {
        let n = self.thickness.len();
        self.thickness = d.list_of(n, "a heightfield's thickness", 8, Dec::f64)?;
        self.hits = d.list_of(n, "a heightfield's impacts", 4, Dec::u32)?;
        self.max_thickness = d.f64()?;
        self.block_max = d.list_of(self.block_max.len(), "a heightfield's blocks", 8, Dec::f64)?;
        self.changed.0 = d.list_of(self.changed.0.len(), "a heightfield's changes", 8, Dec::u64)?;
        Ok(())
    }

    /// Marks the cells cut away (one flag per cell): they receive no deposit, count in no mean,
    /// and a layer never stands in them.
    pub fn set_holes(&mut self, hole: Vec<bool>) {
        debug_assert_eq!(hole.len(), self.thickness.len());
        self.hole = if hole.iter().any(|&h| h) { hole } else { Vec::new() };
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
    }

    fn raise_bounds(&mut self, c: usize, t: f64) {
        self.max_thickness = self.max_thickness.max(t);
        let b = &mut self.block_max[((c / self.cols) / BLOCK) * self.block_cols + (c % self.cols) / BLOCK];
        *b = b.max(t);
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
    pub fn cell_area(&self) -> f64 {
        (self.width / self.cols as f64) * (self.height / self.rows as f64)
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
        for k in 0..self.splat.len() {
            let (i, j) = self.splat[k];
            let Some(c) = target(i, j) else { continue };
            self.thickness[c] += added;
            self.raise_bounds(c, self.thickness[c]);
            self.mark(c);
        }
        self.hole = hole;
    }

    /// Mean thickness over the cells whose centres lie within `radius` (m) of `cell`'s (all
    /// cells have the same area; holes do not count), m.
    pub fn mean_around(&self, cell: u32, radius: f64) -> f64 {
        let (dx, dy) = self.cell_size();
        let (rx, ry) = ((radius / dx).floor() as isize, (radius / dy).floor() as isize);
        if rx == 0 && ry == 0 {
            return self.thickness[cell as usize];
        }
        let (cols, rows) = (self.cols as isize, self.rows as isize);
        let (row, col) = (cell as isize / cols, cell as isize % cols);
        let (mut sum, mut n) = (0.0, 0.0);
        // At most one full turn of a periodic grid, each column once.
        let rx = rx.min((cols - 1) / 2);
        for j in (row - ry).max(0)..=(row + ry).min(rows - 1) {
            for i in col - rx..=col + rx {
                let Some(ci) = self.column(i) else { continue };
                let (x, y) = ((i - col) as f64 * dx, (j - row) as f64 * dy);
                let c = j as usize * self.cols + ci;
                if x * x + y * y <= radius * radius && !self.is_hole(c as u32) {
                    sum += self.thickness[c];
                    n += 1.0;
                }
            }
        }
        if n > 0.0 { sum / n } else { 0.0 }
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

    /// Largest block maximum over the 3 × 3 blocks around the one under `p`, m.
    fn block_max_around(&self, chart: &impl Chart, p: DVec3) -> f64 {
        let (u, v, _) = chart.local(p);
        let cell = self.cell_at(u, v) as usize;
        let (r, c) = ((cell / self.cols) / BLOCK, (cell % self.cols) / BLOCK);
        let block_rows = self.block_max.len() / self.block_cols;
        let mut top = 0.0_f64;
        for rr in r.saturating_sub(1)..=(r + 1).min(block_rows - 1) {
            for cc in c.saturating_sub(1)..=(c + 1).min(self.block_cols - 1) {
                top = top.max(self.block_max[rr * self.block_cols + cc]);
            }
        }
        top
    }

    /// Largest block maximum over the blocks that the segment's footprint touches, m.
    fn block_max_under(&self, chart: &impl Chart, p0: DVec3, p1: DVec3) -> f64 {
        let block = |p: DVec3| {
            let (u, v, _) = chart.local(p);
            let cell = self.cell_at(u, v) as usize;
            ((cell / self.cols) / BLOCK, (cell % self.cols) / BLOCK)
        };
        let ((r0, c0), (r1, c1)) = (block(p0), block(p1));
        let mut top = 0.0_f64;
        for r in r0.min(r1)..=r0.max(r1) {
            for c in c0.min(c1)..=c0.max(c1) {
                top = top.max(self.block_max[r * self.block_cols + c]);
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
        self.layer_contact_near(chart, p0, p1, h0, h1)
    }

    /// [`HeightField::layer_contact`] for a path that reaches below the thickest cell, with
    /// `h0` and `h1` its heights above the surface at its ends, m.
    #[inline(never)]
    fn layer_contact_near(
        &self,
        chart: &impl Chart,
        p0: DVec3,
        p1: DVec3,
        h0: f64,
        h1: f64,
    ) -> Option<LayerContact> {
        // The thickest layer under the segment, from the blocks its footprint covers.
        let top = self.block_max_under(chart, p0, p1);
        let sag = chart.sag(p0, p1);
        if h0.min(h1) - sag > top {
            return None;
        }
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
            (h <= self.thickness[cell as usize] && !behind && !self.is_hole(cell)).then_some(cell)
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
        while k <= n {
            let s = sample(k);
            // Skip a run of samples that all pass above the layer of the blocks around this one:
            // they would all test outside, so the march finds the same entry, only sooner.
            let run = SKIP_RUN.min(n - k);
            if fine && !was_inside && run >= 4 {
                let bound = self.block_max_around(chart, p0.lerp(p1, s)) + SKIP_MARGIN;
                if height(s) > bound && height(sample(k + run)) > bound {
                    prev = sample(k + run);
                    k += run + 1;
                    continue;
                }
            }
            let now = inside(s).is_some();
            if now && !was_inside {
                let (a, b) = bisect(prev, s, |m| inside(m).is_some());
                // `b` stays inside throughout the bisection.
                let entered = inside(b)?;
                let (gu, gv) = self.gradient(entered);
                let (u, v, _) = chart.local(p0.lerp(p1, b));
                let (n, right, up) = chart.frame(u, v);
                let normal = (n - right * gu - up * gv).normalize();
                // Through the side of a taller column, the material settles in the column the
                // particle came down (as in ballistic deposition); stacking it on the taller one
                // would let every column that gets ahead catch its neighbours' flux and grow
                // into a needle.
                let cell = column(a).map_or(entered, |(c, _)| c);
                return Some(LayerContact { s: b, point: p0.lerp(p1, b), normal, cell });
            }
            was_inside = now;
            prev = s;
            k += 1;
        }
        None
    }

    /// Σ thickness × cell area: the volume held by the field, m³.
    pub fn volume(&self) -> f64 {
        self.thickness.iter().sum::<f64>() * self.cell_area()
    }
}

/// Narrows `[a, b]`, with `a` outside and `b` inside, to the entry by 32 halvings; returns the
/// last outside and inside fractions.
fn bisect(mut a: f64, mut b: f64, inside: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..32 {
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

    #[test]
    fn cells_grow_right_and_up_from_the_bottom_left() {
        let f = HeightField::new(2.0, 1.0, 4, 2, 0.0);
        assert_eq!(f.cell_at(-0.99, -0.49), 0);
        assert_eq!(f.cell_at(0.99, -0.49), 3);
        assert_eq!(f.cell_at(-0.99, 0.49), 4);
        assert_eq!(f.cell_at(1.0, 0.5), 7, "the far edge belongs to the last cell");
        assert_eq!(f.cell_at(-0.1, 0.1), 5);
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
