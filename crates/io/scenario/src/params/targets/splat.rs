//! A heightfield target's splat radius: the file's `splat_radius`, or, without one, the
//! smallest radius over which the particles a scenario is expected to deposit per cell add up
//! to [`PARTICLES_PER_SPLAT`] (see `crate::splat` for the estimate).

use serde::{Serialize, Serializer};
use spraysim_engine::deposit::footprint_cells;

/// The expected number of particles per splat footprint that a derived splat radius reaches at
/// least: fewer, and the film is a field of single-particle bumps rather than a layer.
pub const PARTICLES_PER_SPLAT: f64 = 10.0;

/// The widest splat, in cells of the grid's smaller side.
pub const MAX_SPLAT_CELLS: f64 = 32.0;

/// The radius over which each stuck particle's volume is spread, m, and whether the scenario
/// derived it (no `splat_radius` key) or the file gave it. Two are equal when their radii are:
/// a scenario written back with its derived radius reads back as the same scenario.
#[derive(Clone, Copy, Debug)]
pub struct SplatRadius {
    /// Radius, m (0: each particle's volume goes to the struck cell alone).
    pub radius: f64,
    /// True where the scenario derived the radius from the particles expected per cell.
    pub derived: bool,
    /// For a derived radius, the particles its footprint is expected to receive (below
    /// [`PARTICLES_PER_SPLAT`] only where the widest splat allowed cannot reach it).
    pub expected_particles: Option<f64>,
}

impl SplatRadius {
    /// The radius a file gives, m.
    pub(crate) fn given(radius: f64) -> SplatRadius {
        SplatRadius { radius, derived: false, expected_particles: None }
    }

    /// A radius the scenario derives once it is read whole (0 until then).
    pub(crate) fn to_derive() -> SplatRadius {
        SplatRadius { radius: 0.0, derived: true, expected_particles: None }
    }
}

impl PartialEq for SplatRadius {
    fn eq(&self, other: &SplatRadius) -> bool {
        self.radius == other.radius
    }
}

/// Written as its radius, m: a scenario written back states the radius it ran with.
impl Serialize for SplatRadius {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_f64(self.radius)
    }
}

/// The smallest radius, m, a whole number of cells of the smaller side of `cell` (`(dx, dy)`,
/// m), whose footprint holds at least [`PARTICLES_PER_SPLAT`] particles when each cell expects
/// `per_cell` of them; at most [`MAX_SPLAT_CELLS`] cells and `max_radius` (m), where those
/// cannot reach it. 0 when a cell alone expects enough, or nothing is expected at all. Also the
/// particles the footprint of that radius expects.
pub(crate) fn smallest_radius(cell: (f64, f64), per_cell: f64, max_radius: f64) -> (f64, f64) {
    let step = cell.0.min(cell.1);
    if !(per_cell > 0.0 && step > 0.0) {
        return (0.0, 0.0);
    }
    let expected = |r: f64| footprint_cells(cell, r) as f64 * per_cell;
    let mut radius = 0.0;
    for cells in 0..=MAX_SPLAT_CELLS as u32 {
        let r = f64::from(cells) * step;
        if r > max_radius {
            break;
        }
        radius = r;
        if expected(r) >= PARTICLES_PER_SPLAT {
            break;
        }
    }
    (radius, expected(radius))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smallest_radius_reaches_ten_particles_per_footprint() {
        let cell = (1e-3, 1e-3);
        // Ten or more per cell: the struck cell alone.
        assert_eq!(smallest_radius(cell, 12.0, 1.0), (0.0, 12.0));
        // 0.5 per cell needs 20 cells: 1 cell (1), 1 mm (5), 2 mm (13), 3 mm (29).
        assert_eq!(smallest_radius(cell, 0.5, 1.0), (3e-3, 14.5));
        assert!(footprint_cells(cell, 2e-3) as f64 * 0.5 < PARTICLES_PER_SPLAT);
        // Capped at 32 cells, and at the largest radius allowed, expecting fewer.
        assert_eq!(smallest_radius(cell, 1e-6, 1.0).0, 32e-3);
        assert!(smallest_radius(cell, 1e-6, 1.0).1 < PARTICLES_PER_SPLAT);
        assert_eq!(smallest_radius(cell, 1e-6, 5.5e-3).0, 5e-3);
        // Nothing expected: nothing to smooth.
        assert_eq!(smallest_radius(cell, 0.0, 1.0), (0.0, 0.0));
    }
}
