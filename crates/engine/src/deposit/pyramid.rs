//! A max-pyramid over a grid of thicknesses: level `k` holds, per block of `2ᵏ × 2ᵏ` cells,
//! an upper bound of their thickness, so the layer under any rectangle of cells is bounded
//! from at most four nodes, whatever the grid's resolution, and a cell that grows updates
//! only the nodes it overtakes.

use super::Nodes;
use crate::checkpoint::{Dec, Enc, StateError};

/// Upper bounds of a grid's cells by blocks of `2ᵏ × 2ᵏ` cells, `k ≥ 1` (level 0 is the grid
/// itself, which the pyramid does not hold). Bounds only grow: removals leave them standing.
#[derive(Clone, Debug, Default)]
pub(crate) struct MaxPyramid {
    /// `levels[k - 1]`: nodes of level `k`, row-major.
    levels: Vec<Vec<f64>>,
    /// Nodes per row of each level.
    cols: Vec<usize>,
    /// Columns of the grid.
    cols0: usize,
    /// The finest level [`MaxPyramid::max_in`] reads: the first whose nodes fit in
    /// [`CACHED_BYTES`].
    floor: usize,
}

/// Bytes of one level of bounds that stay in a core's cache while particles near the layer
/// look them up at random: on a 2048² grid the cells themselves (32 MB) miss at every lookup,
/// and blocks of 4 × 4 cells bound the layer nearly as tightly for a step's few millimetres.
const CACHED_BYTES: usize = 2 << 20;

impl MaxPyramid {
    /// An all-zero pyramid over `cols × rows` cells, up to the single root.
    pub(crate) fn new(cols: usize, rows: usize) -> MaxPyramid {
        let mut p = MaxPyramid { cols0: cols, ..MaxPyramid::default() };
        let (mut c, mut r) = (cols, rows);
        let fits = |c: usize, r: usize| c * r * std::mem::size_of::<f64>() <= CACHED_BYTES;
        while c > 1 || r > 1 {
            if !fits(c, r) {
                p.floor += 1;
            }
            (c, r) = (c.div_ceil(2), r.div_ceil(2));
            p.levels.push(vec![0.0; c * r]);
            p.cols.push(c);
        }
        p
    }

    /// Raises the bounds over cell `(col, row)` to at least `t` (m). Every node bounds its
    /// children, so the climb stops at the first that already does.
    #[inline]
    pub(crate) fn raise(&mut self, col: usize, row: usize, t: f64) {
        for (k, (level, &cols)) in self.levels.iter_mut().zip(&self.cols).enumerate() {
            let node = &mut level[(row >> (k + 1)) * cols + (col >> (k + 1))];
            if *node >= t {
                return;
            }
            *node = t;
        }
    }

    /// Levels above the grid: the root's level (0 for a single cell).
    #[inline]
    pub(crate) fn height(&self) -> usize {
        self.levels.len()
    }

    /// The bound of node `(col, row)` of level `k ≥ 1`.
    #[inline]
    pub(crate) fn node(&self, k: usize, col: usize, row: usize) -> f64 {
        self.levels[k - 1][row * self.cols[k - 1] + col]
    }

    /// An upper bound of the cells in columns `c0..=c1` and rows `r0..=r1` of `cells` (the
    /// grid the pyramid was made for, row-major): the up to 2 × 2 nodes of the lowest level,
    /// from the finest that fits in [`CACHED_BYTES`] up, that cover the rectangle with them.
    #[inline]
    pub(crate) fn max_in(&self, cells: &[f64], c: (usize, usize), r: (usize, usize)) -> f64 {
        self.max_over(cells, &self.cover(c, r, self.floor))
    }

    /// The largest bound of `nodes`.
    #[inline]
    pub(crate) fn max_over(&self, cells: &[f64], nodes: &Nodes) -> f64 {
        let mut top = 0.0_f64;
        for row in nodes.rows.0..=nodes.rows.1 {
            for col in nodes.cols.0..=nodes.cols.1 {
                top = top.max(self.bound(cells, nodes.level, col, row));
            }
        }
        top
    }

    /// The up to 2 × 2 nodes of the lowest level from `lowest` up (or the root's, if lower)
    /// that cover columns `c0..=c1` and rows `r0..=r1`.
    #[inline]
    pub(crate) fn cover(&self, (c0, c1): (usize, usize), (r0, r1): (usize, usize), lowest: usize) -> Nodes {
        let mut k = lowest.min(self.height());
        while (c1 >> k) - (c0 >> k) > 1 || (r1 >> k) - (r0 >> k) > 1 {
            k += 1;
        }
        let span = |(a, b): (usize, usize)| ((a >> k) as u32, (b >> k) as u32);
        let stride = if k == 0 { self.cols0 } else { self.cols[k - 1] } as u32;
        Nodes { level: k as u32, cols: span((c0, c1)), rows: span((r0, r1)), stride }
    }

    /// The bound of node `(col, row)` of level `k` over `cells` (the grid; level 0: the cell
    /// itself);
    /// infinite for a node outside the pyramid, which bounds nothing.
    #[inline]
    pub(crate) fn bound(&self, cells: &[f64], k: u32, col: u32, row: u32) -> f64 {
        let (k, col, row) = (k as usize, col as usize, row as usize);
        let (level, cols): (&[f64], usize) = match k {
            0 => (cells, self.cols0),
            _ => match self.levels.get(k - 1) {
                Some(l) => (l, self.cols[k - 1]),
                None => return f64::INFINITY,
            },
        };
        if col >= cols {
            return f64::INFINITY;
        }
        level.get(row * cols + col).copied().unwrap_or(f64::INFINITY)
    }

    /// Writes every level.
    pub(crate) fn save_state(&self, e: &mut Enc) {
        for level in &self.levels {
            e.list(level, |e, &x| e.f64(x));
        }
    }

    /// Reads what [`MaxPyramid::save_state`] wrote, over a pyramid of the same size.
    pub(crate) fn load_state(&mut self, d: &mut Dec<'_>) -> Result<(), StateError> {
        for level in &mut self.levels {
            *level = d.list_of(level.len(), "a heightfield's bounds", 8, Dec::f64)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_rectangle_is_bounded_tightly_enough_and_never_below_a_cell() {
        // 37 × 21 cells: odd sizes, so partial blocks at the edges are exercised.
        let (cols, rows) = (37, 21);
        let mut cells = vec![0.0; cols * rows];
        let mut p = MaxPyramid::new(cols, rows);
        let mut x: u64 = 12345;
        for _ in 0..400 {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let c = (x >> 33) as usize % cells.len();
            cells[c] += ((x >> 11) % 1000) as f64 * 1e-6;
            p.raise(c % cols, c / cols, cells[c]);
        }
        for (c0, c1, r0, r1) in [(0, 36, 0, 20), (3, 3, 5, 5), (5, 17, 2, 9), (30, 36, 19, 20), (8, 9, 0, 20)]
        {
            let exact =
                (r0..=r1).flat_map(|r| (c0..=c1).map(move |c| (r, c))).map(|(r, c)| cells[r * cols + c]);
            let exact = exact.fold(0.0_f64, f64::max);
            let bound = p.max_in(&cells, (c0, c1), (r0, r1));
            assert!(bound >= exact, "{bound} < {exact}");
            // The nodes used cover at most twice the rectangle along each axis plus a block:
            // the bound is the exact maximum over that region.
            assert!(bound <= cells.iter().copied().fold(0.0, f64::max));
        }
        // A single cell is answered from the grid itself.
        assert_eq!(p.max_in(&cells, (4, 4), (7, 7)), cells[7 * cols + 4]);
    }

    /// A grid whose cells do not fit in the cache is bounded from blocks of the first level
    /// that does (4 × 4 cells at 2048², 2 × 2 at 1024²), a small one from its cells; either
    /// bound holds.
    #[test]
    fn a_grid_too_big_for_the_cache_is_bounded_from_coarser_blocks() {
        for (side, block) in [(2048, 4), (1024, 2), (256, 1)] {
            let mut cells = vec![0.0; side * side];
            let mut p = MaxPyramid::new(side, side);
            // One tall cell, and a lower one in the same 2 × 2 (and 4 × 4) block.
            for (c, r, t) in [(100, 56, 0.02), (101, 57, 0.01)] {
                cells[r * side + c] = t;
                p.raise(c, r, t);
            }
            let bound = p.max_in(&cells, (101, 101), (57, 57));
            let expected = if block == 1 { 0.01 } else { 0.02 };
            assert_eq!(bound, expected, "{side}²: blocks of {block}");
            assert_eq!(p.max_in(&cells, (200, 200), (200, 200)), 0.0);
        }
    }
}
