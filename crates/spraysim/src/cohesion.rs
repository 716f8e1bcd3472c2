//! Cohesive failure of a deposited layer (the paper's "cells that exceed local support
//! thresholds are flagged and clustered into connected regions").
//!
//! Each cell's self-weight per area, ρ g t, is resolved against the face's orientation into a
//! pull-off stress (the part of gravity along the face's outward normal) and a shear stress (the
//! part along the face). A cell is over-loaded when either exceeds the adhesive strength of the
//! layer on the substrate. Over-loaded cells are clustered into 8-connected regions. A region
//! fails when the load its substrate cannot carry, Σ A · max(σ − f_t, τ − f_s), exceeds what the
//! intact layer around it can hold: cohesion × Σ (boundary edge length × thickness) over edges
//! to neighbouring cells that carry material and are not in the region. Large patches therefore
//! fall while small ones hang on, a uniform layer on a ceiling fails once ρ g t > f_t, on a wall
//! once ρ g t > f_s, and a floor never fails.

use crate::heightfield::HeightField;
use glam::DVec3;

/// Strengths of a fresh layer, Pa.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Strength {
    /// Adhesive tensile (pull-off) strength, Pa.
    pub tensile: f64,
    /// Adhesive shear strength, Pa.
    pub shear: f64,
    /// Cohesion of the layer along a region's boundary, Pa.
    pub cohesion: f64,
}

/// One connected over-loaded region.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// Cell indices (row-major from the bottom row).
    pub cells: Vec<u32>,
    /// Load the substrate cannot carry, N.
    pub driving: f64,
    /// Load the surrounding layer can hold, N.
    pub holding: f64,
}

impl Region {
    /// True if the region falls off.
    pub fn fails(&self) -> bool {
        self.driving > self.holding
    }
}

/// Over-loaded regions of one heightfield.
#[derive(Clone, Debug, Default)]
pub struct Analysis {
    /// Regions, in order of their first cell.
    pub regions: Vec<Region>,
    /// Over-loaded cells in total.
    pub overloaded_cells: usize,
}

/// Pull-off and shear stress per metre of thickness on a face with outward unit `normal`, Pa/m.
pub fn stress_per_thickness(density: f64, gravity: DVec3, normal: DVec3) -> (f64, f64) {
    let g = gravity.length();
    if g == 0.0 {
        return (0.0, 0.0);
    }
    let down = gravity / g;
    let pull = down.dot(normal).max(0.0);
    let shear = (down - normal * down.dot(normal)).length();
    (density * g * pull, density * g * shear)
}

/// Finds the over-loaded regions of `field` on a face with outward unit `normal`.
pub fn analyse(field: &HeightField, normal: DVec3, density: f64, gravity: DVec3, s: &Strength) -> Analysis {
    let (pull, shear) = stress_per_thickness(density, gravity, normal);
    let t = field.thickness();
    let (cols, rows) = (field.cols(), field.rows());
    let over = |i: usize| t[i] * pull > s.tensile || t[i] * shear > s.shear;
    let mut label = vec![u32::MAX; t.len()];
    let mut out = Analysis::default();
    let (dx, dy) = field.cell_size();
    let area = dx * dy;
    let mut stack = Vec::new();
    for start in 0..t.len() {
        if label[start] != u32::MAX || !over(start) {
            continue;
        }
        let id = out.regions.len() as u32;
        let mut cells = Vec::new();
        label[start] = id;
        stack.push(start);
        while let Some(c) = stack.pop() {
            cells.push(c as u32);
            let (r, col) = ((c / cols) as isize, (c % cols) as isize);
            for (di, dj) in [(-1, -1), (-1, 0), (-1, 1), (0, -1), (0, 1), (1, -1), (1, 0), (1, 1)] {
                let (rr, cc) = (r + di, col + dj);
                if rr < 0 || cc < 0 || rr >= rows as isize || cc >= cols as isize {
                    continue;
                }
                let n = rr as usize * cols + cc as usize;
                if label[n] == u32::MAX && over(n) {
                    label[n] = id;
                    stack.push(n);
                }
            }
        }
        cells.sort_unstable();
        out.overloaded_cells += cells.len();
        let mut driving = 0.0;
        let mut holding = 0.0;
        for &c in &cells {
            let c = c as usize;
            driving += area * (t[c] * pull - s.tensile).max(t[c] * shear - s.shear).max(0.0);
            let (r, col) = (c / cols, c % cols);
            // Edges to intact, material-carrying cells hold the region by cohesion.
            let mut hold = |n: usize, edge: f64| {
                if label[n] != id && t[n] > 0.0 {
                    holding += s.cohesion * edge * t[c];
                }
            };
            if col > 0 {
                hold(c - 1, dy);
            }
            if col + 1 < cols {
                hold(c + 1, dy);
            }
            if r > 0 {
                hold(c - cols, dx);
            }
            if r + 1 < rows {
                hold(c + cols, dx);
            }
        }
        out.regions.push(Region { cells, driving, holding });
    }
    out
}
