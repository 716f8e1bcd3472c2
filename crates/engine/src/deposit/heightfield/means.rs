//! Disc means of the layer: the mean thickness over the cells around one, the cushion an
//! impact lands on. Narrow discs are summed cell by cell in row spans; wide ones over the
//! block sums, so that the work does not grow with the resolution.

use super::{HeightField, column_of};
use crate::deposit::sums::{MEAN_SPAN, SUM_LEVELS};

impl HeightField {
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
