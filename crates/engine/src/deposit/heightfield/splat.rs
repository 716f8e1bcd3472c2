//! Splatting: a stuck particle's volume spread evenly over the cells of a footprint around
//! the struck cell, conserving it exactly (up to rounding), at the edges, beside openings and
//! round the seam of a periodic grid.

use super::{HeightField, column_of};

/// The deposit footprint on cells of `(dx, dy)` (m): the cell offsets `(col, row)` whose centres
/// lie within `radius` (m) of the struck cell's centre (the struck cell always), and its
/// half-width in whole cells `(cols, rows)`, 0 where `radius` is below a cell.
pub(super) fn footprint((dx, dy): (f64, f64), radius: f64) -> (Vec<(isize, isize)>, (isize, isize)) {
    let reach_x = (radius / dx).floor() as isize;
    let reach_y = (radius / dy).floor() as isize;
    let mut splat = Vec::new();
    for j in -reach_y..=reach_y {
        for i in -reach_x..=reach_x {
            let (x, y) = (i as f64 * dx, j as f64 * dy);
            if x * x + y * y <= radius * radius || (i == 0 && j == 0) {
                splat.push((i, j));
            }
        }
    }
    (splat, (reach_x, reach_y))
}

impl HeightField {
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
