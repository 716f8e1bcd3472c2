//! Sums of a grid's thicknesses over blocks of `2ᵏ × 2ᵏ` cells, for means over wide discs: the
//! layer under an impact is averaged over a disc of fixed size in metres (the cushion radius),
//! which covers ever more cells as the grid gets finer. Over blocks, the work of a mean stays
//! bounded whatever the resolution.
//!
//! Each sum is recomputed from its children (cells, or the level below) in a fixed order
//! whenever one of them changes, never accumulated: a sum depends only on the thicknesses as
//! they stand, so a restored checkpoint reproduces it bit for bit.

/// Levels kept: blocks of up to 8 × 8 cells.
pub(crate) const SUM_LEVELS: usize = 3;

/// Widest radius, in cells (or in blocks of the level used), that a mean visits one by one;
/// wider discs use the first level at which they are at most this many blocks wide.
pub(crate) const MEAN_SPAN: usize = 12;

/// One level: per block, the sum of its cells' thicknesses (m) and, on a grid with holes, how
/// many cells it holds that are not holes (without holes, the count follows from the grid's
/// size: a simulation set up afresh counts nothing).
#[derive(Clone, Debug, Default)]
struct Level {
    cols: usize,
    rows: usize,
    sum: Vec<f64>,
    cells: Vec<u16>,
}

/// Block sums of levels `1..=SUM_LEVELS` over a `cols × rows` grid.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockSums {
    cols: usize,
    rows: usize,
    /// `levels[k - 1]`: blocks of `2ᵏ × 2ᵏ` cells, row-major.
    levels: Vec<Level>,
}

/// A view of one level of the sums.
pub(crate) struct Blocks<'a> {
    /// Side of a block, cells.
    pub side: usize,
    /// Blocks per row.
    pub cols: usize,
    /// Sum of the thickness over each block's cells, m.
    pub sum: &'a [f64],
    /// Cells of each block that are not holes; empty when the grid has no holes.
    counts: &'a [u16],
    /// Columns and rows of the grid.
    grid: (usize, usize),
}

impl Blocks<'_> {
    /// Cells of block `(col, row)` that are not holes.
    #[inline]
    pub fn cells(&self, col: usize, row: usize) -> u32 {
        match self.counts.get(row * self.cols + col) {
            Some(&n) => u32::from(n),
            None => {
                let (c, r) = (self.grid.0 - col * self.side, self.grid.1 - row * self.side);
                (c.min(self.side) * r.min(self.side)) as u32
            }
        }
    }
}

impl BlockSums {
    /// All-zero sums over an empty `cols × rows` grid without holes.
    pub(crate) fn new(cols: usize, rows: usize) -> BlockSums {
        let mut sums = BlockSums { cols, rows, levels: Vec::new() };
        let (mut c, mut r) = (cols, rows);
        for _ in 0..SUM_LEVELS {
            (c, r) = (c.div_ceil(2), r.div_ceil(2));
            sums.levels.push(Level { cols: c, rows: r, sum: vec![0.0; c * r], cells: Vec::new() });
        }
        sums
    }

    /// Counts every block's cells again, with `hole` (one flag per cell, or empty for none).
    pub(crate) fn recount(&mut self, hole: &[bool]) {
        if hole.is_empty() {
            self.levels.iter_mut().for_each(|l| l.cells = Vec::new());
            return;
        }
        let (cols, rows) = (self.cols, self.rows);
        let open = |c: usize| !hole.get(c).copied().unwrap_or(false);
        let mut below: Vec<u16> = (0..cols * rows).map(|c| u16::from(open(c))).collect();
        let (mut bc, mut br) = (cols, rows);
        for level in &mut self.levels {
            level.cells = (0..level.rows * level.cols)
                .map(|k| children(k % level.cols, k / level.cols, bc, br).map(|i| below[i]).sum())
                .collect();
            below.clone_from(&level.cells);
            (bc, br) = (level.cols, level.rows);
        }
    }

    /// Recomputes every block over the cells of columns `cols` and rows `rows` (inclusive) from
    /// `thickness` (holes, flagged in `hole` or not at all when it is empty, count as 0).
    pub(crate) fn refresh(
        &mut self,
        thickness: &[f64],
        hole: &[bool],
        cols: (usize, usize),
        rows: (usize, usize),
    ) {
        let cell = |k: usize| if hole.get(k).copied().unwrap_or(false) { 0.0 } else { thickness[k] };
        let (mut bc, mut br) = (self.cols, self.rows);
        for k in 0..self.levels.len() {
            let (lower, upper) = self.levels.split_at_mut(k);
            let level = &mut upper[0];
            let s = k + 1;
            for r in rows.0 >> s..=rows.1 >> s {
                for c in cols.0 >> s..=cols.1 >> s {
                    let parts = children(c, r, bc, br);
                    level.sum[r * level.cols + c] = match lower.last() {
                        None => parts.map(cell).sum(),
                        Some(below) => parts.map(|i| below.sum[i]).sum(),
                    };
                }
            }
            (bc, br) = (level.cols, level.rows);
        }
    }

    /// Level `k` (`1..=SUM_LEVELS`).
    pub(crate) fn level(&self, k: usize) -> Blocks<'_> {
        let l = &self.levels[k - 1];
        Blocks { side: 1 << k, cols: l.cols, sum: &l.sum, counts: &l.cells, grid: (self.cols, self.rows) }
    }
}

/// The indices, row-major in a `cols × rows` grid, of the up to 2 × 2 children of block
/// `(c, r)` of the level above it.
fn children(c: usize, r: usize, cols: usize, rows: usize) -> impl Iterator<Item = usize> {
    (2 * r..(2 * r + 2).min(rows))
        .flat_map(move |j| (2 * c..(2 * c + 2).min(cols)).map(move |i| j * cols + i))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every block sums exactly its non-hole cells, and a refresh of part of the grid leaves it
    /// equal to sums made afresh, on a grid whose sides are not powers of two.
    #[test]
    fn blocks_sum_their_cells_after_any_refresh() {
        let (cols, rows) = (13, 10);
        let hole: Vec<bool> = (0..cols * rows).map(|c| c % 7 == 3).collect();
        let mut t: Vec<f64> = (0..cols * rows).map(|c| (c as f64 * 0.37).sin().abs() * 1e-3).collect();
        let mut sums = BlockSums::new(cols, rows);
        sums.recount(&hole);
        sums.refresh(&t, &hole, (0, cols - 1), (0, rows - 1));
        t[5 * cols + 6] += 2e-3;
        sums.refresh(&t, &hole, (6, 6), (5, 5));
        let mut fresh = BlockSums::new(cols, rows);
        fresh.recount(&hole);
        fresh.refresh(&t, &hole, (0, cols - 1), (0, rows - 1));
        for k in 1..=SUM_LEVELS {
            let (a, b) = (sums.level(k), fresh.level(k));
            assert_eq!(a.sum, b.sum, "level {k}");
            for r in 0..a.sum.len() / a.cols {
                for c in 0..a.cols {
                    let side = a.side;
                    let inside = |i: usize| {
                        (c * side..((c + 1) * side).min(cols)).contains(&(i % cols))
                            && (r * side..((r + 1) * side).min(rows)).contains(&(i / cols))
                    };
                    let open: Vec<usize> = (0..cols * rows).filter(|&i| inside(i) && !hole[i]).collect();
                    let want: f64 = open.iter().map(|&i| t[i]).sum();
                    assert!((a.sum[r * a.cols + c] - want).abs() <= 1e-15, "level {k} block ({c}, {r})");
                    assert_eq!(a.cells(c, r) as usize, open.len());
                    let full = (c * side..((c + 1) * side).min(cols)).len()
                        * (r * side..((r + 1) * side).min(rows)).len();
                    assert_eq!(
                        BlockSums::new(cols, rows).level(k).cells(c, r) as usize,
                        full,
                        "without holes"
                    );
                }
            }
        }
    }
}
