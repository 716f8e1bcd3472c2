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

/// How many cells the deposit footprint of `radius` (m) on cells of `(dx, dy)` (m) spans in
/// the interior of a grid: the struck cell and those whose centres lie within `radius` of its
/// centre (1 where `radius` is below a cell).
pub fn footprint_cells(cell: (f64, f64), radius: f64) -> usize {
    footprint(cell, radius).0.len()
}

impl HeightField {
    /// Calls `visit` with `cell`, then each other cell of the splat footprint around it that
    /// lies inside the grid and is not cut away, in the footprint's fixed order: the cells a
    /// deposit struck at `cell` is shared among, evenly.
    pub fn footprint(&self, cell: u32, visit: &mut dyn FnMut(u32)) {
        let (cols, rows) = (self.cols as isize, self.rows as isize);
        let (row, col) = (cell as isize / cols, cell as isize % cols);
        // The struck cell always takes its share (it is never a hole when struck), first.
        visit(cell);
        for &(i, j) in self.splat.iter().filter(|&&o| o != (0, 0)) {
            let Some(c) = column_of(col + i, self.cols, self.wrap).filter(|_| (0..rows).contains(&(row + j)))
            else {
                continue;
            };
            let k = (row + j) as usize * self.cols + c;
            if !self.hole.get(k).copied().unwrap_or(false) {
                visit(k as u32);
            }
        }
    }

    /// Deposits `volume` (m³) centred on `cell`: shared evenly over its
    /// [footprint](Self::footprint), so Σ thickness × cell area grows by exactly `volume` (up to
    /// rounding), at the edges too.
    pub fn deposit(&mut self, cell: u32, volume: f64) {
        let mut cells = Vec::with_capacity(self.splat.len());
        self.footprint(cell, &mut |c| cells.push(c));
        let added = volume / (cells.len() as f64 * self.cell_area());
        for c in cells {
            self.add(c, added);
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
