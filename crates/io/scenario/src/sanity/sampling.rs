//! `sparse_sampling`: too few particles per cell for a readable map.
//!
//! The rule, before the run: the particles emitted while the spray axis meets a substrate
//! target (spawn rate × that time) spread over the area the spray covers on it — the spot of
//! the cone where the axis meets the surface (its radius: standoff × tan(half-angle) plus the
//! aperture's, stretched by the incidence), swept along the path — at most the target's
//! area. Divided by that area, times the area of one cell (or, for a target with a
//! `splat_radius`, of one splat, π r²), it gives the particles expected per cell (or splat);
//! below [`MIN_PER_CELL`], the map is spiky: mostly noise.

use super::poses::{Stretch, spraying_stretches};
use super::{Warning, WarningCode};
use crate::build::{emitter, nozzle_path};
use crate::params::{RasterChart, TargetShape, smallest_radius};
use crate::scenario::Scenario;
use glam::DVec3;
use spraysim_engine::collision::Primitive;
use spraysim_engine::deposit::footprint_cells;
use spraysim_engine::emission;
use spraysim_engine::world::Role;

/// Fewest particles per cell (or per splat) expected over the covered area for a map that
/// is not mostly noise.
pub const MIN_PER_CELL: f64 = 10.0;
/// How far along the axis a surface is looked for, m.
const LOOK_AHEAD: f64 = 1000.0;
/// Smallest cosine of the incidence taken to stretch the spot (about 75°).
const MIN_INCIDENCE_COSINE: f64 = 0.25;

/// What a target's map is expected to receive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// Particles emitted while the spray axis meets the target.
    pub particles: f64,
    /// Area the spray covers on it, m².
    pub covered_area: f64,
    /// Area over which one particle's deposit is counted: a cell's, or a splat's (π r²), m².
    pub footprint_area: f64,
}

impl Sampling {
    /// Particles expected per cell (or splat) over the covered area.
    pub fn per_footprint(&self) -> f64 {
        self.particles * self.footprint_area / self.covered_area
    }
}

/// The sampling of target `target` (its index) of `sc`, or `None` when the spray axis never
/// meets it.
pub fn estimate(sc: &Scenario, target: usize) -> Option<Sampling> {
    let path = nozzle_path(sc);
    estimate_over(sc, target, &spraying_stretches(&path, sc.simulation().duration))
}

fn estimate_over(sc: &Scenario, target: usize, stretches: &[Stretch]) -> Option<Sampling> {
    let t = sc.targets().get(target)?;
    let geometry = t.shape.as_dyn();
    let surface: Box<dyn Primitive> = match geometry.raster_chart()? {
        RasterChart::Face(f) => Box::new(f),
        RasterChart::Shell(c) => Box::new(c.shell),
    };
    let e = emitter(sc.emitter(), sc.process().flow_rate);
    let (half_wide, half_narrow) = match e.direction {
        emission::Direction::Fan { wide, narrow } => (0.5 * wide, 0.5 * narrow),
        _ => (e.cone_half_angle, e.cone_half_angle),
    };
    let aperture = match e.aperture {
        emission::Aperture::Point => 0.0,
        emission::Aperture::Circle { r } => r,
        emission::Aperture::Rectangle { hw, hh } => hw.min(hh),
        emission::Aperture::Annulus { r_out, .. } => r_out,
    };
    let (mut time, mut largest_spot, mut swept) = (0.0, 0.0_f64, 0.0);
    let mut previous: Option<(DVec3, f64)> = None;
    for s in stretches {
        let Some(hit) = surface.intersect(s.position, s.position + s.axis * LOOK_AHEAD) else {
            previous = None;
            continue;
        };
        let standoff = hit.t * LOOK_AHEAD;
        let stretch = 1.0 / s.axis.dot(hit.normal).abs().max(MIN_INCIDENCE_COSINE);
        let spot = std::f64::consts::PI
            * (standoff * half_wide.tan() + aperture)
            * (standoff * half_narrow.tan() + aperture)
            * stretch;
        let radius = (spot / std::f64::consts::PI).sqrt();
        if let Some((point, r)) = previous {
            swept += (radius + r) * hit.point.distance(point);
        }
        previous = Some((hit.point, radius));
        largest_spot = largest_spot.max(spot);
        time += s.times[1] - s.times[0];
    }
    if time <= 0.0 {
        return None;
    }
    let area = geometry.area();
    let splat = geometry.splat_radius();
    // A splat spreads over the whole cells whose centres lie within its radius, as the deposit
    // does (the radius a target derives is chosen on that count, so that it never warns of
    // itself); a surface without a grid over a disc.
    let footprint_area = match (splat > 0.0, t.shape.resolution()) {
        (true, Some([cols, rows])) => {
            let [width, height] = t.size();
            let cell = (width / f64::from(cols.max(1)), height / f64::from(rows.max(1)));
            footprint_cells(cell, splat) as f64 * cell.0 * cell.1
        }
        (true, None) => std::f64::consts::PI * splat * splat,
        (false, _) => area / geometry.cells().max(1) as f64,
    };
    Some(Sampling {
        particles: sc.emitter().spawn_rate * time,
        covered_area: (largest_spot + swept).min(area).max(f64::MIN_POSITIVE),
        footprint_area,
    })
}

/// The warnings for the substrate targets (every target when none is one) whose maps are
/// expected to be spiky.
pub(super) fn check(sc: &Scenario, stretches: &[Stretch]) -> Vec<Warning> {
    let substrates = sc.targets().iter().any(|t| t.role == Role::Substrate);
    let mut warnings = Vec::new();
    for (i, t) in sc.targets().iter().enumerate() {
        if substrates && t.role != Role::Substrate {
            continue;
        }
        let Some(s) = estimate_over(sc, i, stretches) else { continue };
        let per = s.per_footprint();
        if per >= MIN_PER_CELL || s.particles <= 0.0 {
            continue;
        }
        let splat = t.shape.as_dyn().splat_radius();
        // The splat radius that reaches the minimum: counted in whole cells as the deposit
        // spreads it (within the largest a target allows), or as a disc without a grid.
        let needed_splat = match t.shape.resolution() {
            Some([cols, rows]) => {
                let [width, height] = t.size();
                let cell = (width / f64::from(cols.max(1)), height / f64::from(rows.max(1)));
                let per_cell = s.particles * cell.0 * cell.1 / s.covered_area;
                smallest_radius(cell, per_cell, width.min(height) / 2.0).0
            }
            None => (MIN_PER_CELL * s.covered_area / (std::f64::consts::PI * s.particles)).sqrt(),
        };
        let needed_rate = sc.emitter().spawn_rate * MIN_PER_CELL / per;
        let coarser = match &t.shape {
            TargetShape::Rectangle(r) if splat <= 0.0 => Some(r.resolution),
            TargetShape::Cylinder(c) if splat <= 0.0 => Some(c.resolution),
            _ => None,
        }
        .map(|[cols, rows]| {
            let f = (per / MIN_PER_CELL).sqrt();
            let scaled = |n: u32| (f64::from(n) * f).floor().max(1.0) as u32;
            format!(", or coarsen target[{i}].resolution to about [{}, {}]", scaled(cols), scaled(rows))
        });
        let per_what = if splat > 0.0 { "splat (splat_radius)" } else { "cell" };
        warnings.push(Warning {
            code: WarningCode::SparseSampling,
            message: format!(
                "target `{}` is expected to receive about {per:.2} particles per {per_what} over the {:.3} m² \
                 the spray covers ({:.3e} particles), fewer than {MIN_PER_CELL}: its maps will be spiky; set \
                 target[{i}].splat_radius to about {:.3} m, or emitter.spawn_rate to about {:.3e}/s{}",
                t.name,
                s.covered_area,
                s.particles,
                needed_splat,
                needed_rate,
                coarser.unwrap_or_default()
            ),
            key: format!("target[{i}].splat_radius"),
        });
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sanity::tests::through;

    fn warnings(sc: &Scenario) -> Vec<Warning> {
        let path = nozzle_path(sc);
        check(sc, &spraying_stretches(&path, sc.simulation().duration))
    }

    #[test]
    fn a_derived_splat_radius_never_warns_of_itself() {
        // The default wall without its splat radius, at resolutions whose derived radius is 1,
        // 2 and more cells (where a disc of the radius and the cells it covers differ most).
        let line = "splat_radius = 0.008          # m: each particle spreads over a 16 mm patch\n";
        assert!(crate::DEFAULT_SCENE.contains(line));
        for n in [200, 300, 450, 550, 700, 1024, 1500] {
            let text = crate::DEFAULT_SCENE.replacen(line, "", 1).replacen(
                "resolution = [1024, 1024]",
                &format!("resolution = [{n}, {n}]"),
                1,
            );
            let sc = Scenario::from_toml(&text, "wall.toml").expect("valid");
            let radius = sc.targets()[0].shape.splat_radius().expect("a heightfield").radius;
            let sparse = warnings(&sc).into_iter().filter(|w| w.code == WarningCode::SparseSampling);
            assert_eq!(sparse.count(), 0, "{n}² cells, derived radius {radius} m");
        }
    }

    #[test]
    fn the_default_wall_covers_its_spot_with_enough_particles_per_splat() {
        let sc = Scenario::default_scene();
        let s = estimate(&sc, 0).expect("the axis meets the wall");
        // 18° cone from 1 m: a spot of radius tan 9° m plus the aperture's 25 mm, 2 s at 10⁴/s.
        let spot = std::f64::consts::PI * (9f64.to_radians().tan() + 0.025).powi(2);
        assert!((s.covered_area / spot - 1.0).abs() < 1e-9, "{s:?} vs {spot}");
        assert!((s.particles - 2e4).abs() < 1.0, "{s:?}");
        // The cells within 8 mm (4.1 cells) of a cell's centre, on 2 m / 1024 cells: 49 of them,
        // 7 % short of the disc's area.
        let cell = 2.0 / 1024.0;
        let cells = spraysim_engine::deposit::footprint_cells((cell, cell), 0.008) as f64;
        assert!((s.footprint_area - cells * cell * cell).abs() < 1e-12, "{s:?}");
        assert_eq!(cells, 49.0);
        assert!(s.per_footprint() > MIN_PER_CELL, "{s:?}");
        assert_eq!(warnings(&sc), vec![]);
        // The floor is a collector: not judged.
        assert_eq!(estimate(&sc, 1), None);
    }

    #[test]
    fn without_its_splat_the_wall_is_sparse_and_the_fixes_are_named() {
        let sc = Scenario::default_scene().with("target[0].splat_radius", 0.0).expect("valid");
        let w = warnings(&sc);
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].code, WarningCode::SparseSampling);
        assert_eq!(w[0].key, "target[0].splat_radius");
        for fix in ["target[0].splat_radius", "emitter.spawn_rate", "target[0].resolution"] {
            assert!(w[0].message.contains(fix), "{}", w[0].message);
        }
        // The suggested splat radius gives the minimum.
        let s = estimate(&sc, 0).expect("met");
        let cell = 2.0 / 1024.0;
        let (r, _) = smallest_radius((cell, cell), s.particles * cell * cell / s.covered_area, 1.0);
        assert!(w[0].message.contains(&format!("splat_radius to about {r:.3} m")), "{}", w[0].message);
        let fixed = sc.with("target[0].splat_radius", r).expect("valid");
        assert_eq!(warnings(&fixed), vec![]);
    }

    #[test]
    fn a_moving_nozzle_spreads_the_same_particles_over_a_wider_band() {
        let still = estimate(&Scenario::default_scene(), 0).expect("met");
        let moving = estimate(&through([-1.0, -0.8, 1.0], [-1.0, 0.8, 1.0], None), 0).expect("met");
        // A 1.6 m band about 0.32 m wide, besides the spot.
        let band = 1.6 * 2.0 * 9f64.to_radians().tan();
        assert!(moving.covered_area > still.covered_area + 0.8 * band, "{moving:?}");
        assert!(moving.covered_area < still.covered_area + 1.3 * band, "{moving:?}");
    }
}
