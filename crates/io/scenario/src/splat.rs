//! The splat radius a heightfield target gets without a `splat_radius` key: derived from the
//! particles the scenario is expected to lay on each of its cells.
//!
//! The nozzle's path is sampled over the run. At each sample where it sprays and its axis meets
//! the target's surface (on the receiving side, with the spot overlapping the target), the spot
//! is a disc on the unrolled surface: its radius is the standoff (along the axis) times the tangent
//! of the cone's half-angle, plus the aperture's radius (a fan's two angles give the disc of the
//! same area as its ellipse). The covered area is the union of those discs (the spot where the
//! nozzle stands still, the swept band of a raster or path); the particles are the spawn rate
//! times the time spent spraying at the target. Their ratio is the particles expected per cell,
//! and the radius is the smallest whole number of cells whose footprint expects at least
//! [`PARTICLES_PER_SPLAT`](crate::params::PARTICLES_PER_SPLAT) of them, at most 32 cells and half
//! the target's smaller side. A target the nozzle never points at expects the run's particles
//! spread over its whole area.

use crate::build::nozzle_path;
use crate::params::{Aperture, DirectionLaw, RasterChart, TargetParams, smallest_radius};
use crate::scenario::Scenario;
use glam::DVec3;
use spraysim_engine::deposit::Chart;
use spraysim_engine::emission::NozzlePath;

/// A spot on a target's unrolled surface: the centre `(u, v)` and the radius, m.
type Spot = (f64, f64, f64);

/// Samples of the nozzle's path over the run, at most.
const PATH_SAMPLES: f64 = 2000.0;

/// Cells of the coarse grid the covered area is counted on, along its longer side.
const AREA_GRID: f64 = 256.0;

/// The radius, m, each target without a `splat_radius` key spreads a particle over, and the
/// particles its footprint expects, in the scenario's target order (`None` for a target that
/// gives one, or has no heightfield).
pub(crate) fn derived_radii(sc: &Scenario) -> Vec<Option<(f64, f64)>> {
    let path = nozzle_path(sc);
    sc.targets().iter().map(|t| derived_radius(sc, &path, t)).collect()
}

/// The radius target `t` gets, m, if it is to be derived, and the particles its footprint
/// expects.
fn derived_radius(sc: &Scenario, path: &NozzlePath, t: &TargetParams) -> Option<(f64, f64)> {
    t.shape.splat_radius().filter(|s| s.derived)?;
    let [cols, rows] = t.shape.resolution()?;
    let size = t.size();
    let cell = (size[0] / f64::from(cols), size[1] / f64::from(rows));
    let (particles, area) = match t.shape.as_dyn().raster_chart() {
        Some(RasterChart::Face(f)) => spray_on(sc, path, &f, size),
        Some(RasterChart::Shell(c)) => spray_on(sc, path, &c, size),
        None => None,
    }
    .unwrap_or_else(|| (sc.emitter().spawn_rate * spraying_time(sc, path), size[0] * size[1]));
    // A jet without spread (a zero cone from a point) still covers the cell it strikes.
    let per_cell = particles * cell.0 * cell.1 / area.max(cell.0 * cell.1);
    Some(smallest_radius(cell, per_cell, size[0].min(size[1]) / 2.0))
}

/// The times the path is sampled at, s, and the interval each stands for, s.
fn samples(sc: &Scenario) -> (Vec<f64>, f64) {
    let s = sc.simulation();
    let n = (s.duration / s.dt).ceil().clamp(1.0, PATH_SAMPLES);
    let step = s.duration / n;
    ((0..n as u32).map(|k| (f64::from(k) + 0.5) * step).collect(), step)
}

/// How long the nozzle sprays during the run, s.
fn spraying_time(sc: &Scenario, path: &NozzlePath) -> f64 {
    let (times, step) = samples(sc);
    times.iter().filter(|&&t| path.at(t).1).count() as f64 * step
}

/// The particles expected on the surface `chart` of a target of `size` (m) and the area they
/// cover, m²; `None` when the nozzle never sprays at it.
fn spray_on(sc: &Scenario, path: &NozzlePath, chart: &impl Chart, size: [f64; 2]) -> Option<(f64, f64)> {
    let (times, step) = samples(sc);
    let (tan_wide, tan_narrow, aperture) = spot_shape(sc);
    let mut spots: Vec<Spot> = Vec::new();
    let mut time_at_target = 0.0;
    let mut last: Option<(DVec3, DVec3, Option<Spot>)> = None;
    for t in times {
        let (frame, spraying) = path.at(t);
        if !spraying {
            continue;
        }
        let spot = match last {
            Some((p, a, spot)) if p == frame.position && a == frame.axis => spot,
            _ => axis_hit(chart, frame.position, frame.axis).map(|(u, v, standoff)| {
                let radius = ((standoff * tan_wide + aperture) * (standoff * tan_narrow + aperture)).sqrt();
                (u, v, radius)
            }),
        };
        last = Some((frame.position, frame.axis, spot));
        let Some((u, v, r)) =
            spot.filter(|&(u, v, r)| u.abs() < size[0] / 2.0 + r && v.abs() < size[1] / 2.0 + r)
        else {
            continue;
        };
        time_at_target += step;
        // A spot that barely moved adds nothing to the union.
        let moved = |&(u0, v0, r0): &Spot| (u - u0).hypot(v - v0) > r / 8.0 || (r - r0).abs() > r / 100.0;
        if spots.last().is_none_or(moved) {
            spots.push((u, v, r));
        }
    }
    (time_at_target > 0.0).then(|| (sc.emitter().spawn_rate * time_at_target, union_area(&spots)))
}

/// Tangents of the spot's half-angles across its two axes and the aperture's radius, m.
fn spot_shape(sc: &Scenario) -> (f64, f64, f64) {
    let e = sc.emitter();
    let aperture = match e.aperture {
        Aperture::Point => 0.0,
        Aperture::Circle { diameter } => diameter / 2.0,
        Aperture::Rectangle { width, height } => (width * height / std::f64::consts::PI).sqrt(),
        Aperture::Annulus { outer_diameter, .. } => outer_diameter / 2.0,
    };
    let half_tan = |full: f64| (full / 2.0).to_radians().tan();
    match e.direction {
        DirectionLaw::Fan { fan_wide_angle, fan_narrow_angle } => {
            (half_tan(fan_wide_angle), half_tan(fan_narrow_angle), aperture)
        }
        _ => (half_tan(e.cone_angle()), half_tan(e.cone_angle()), aperture),
    }
}

/// Where the ray from `p` along `axis` first meets the surface `chart` from its receiving
/// side: `(u, v)` on the unrolled surface, m, and the distance along the ray, m.
fn axis_hit(chart: &impl Chart, p: DVec3, axis: DVec3) -> Option<(f64, f64, f64)> {
    let a = axis.normalize_or_zero();
    let height = |t: f64| chart.local(p + a * t).2;
    if a == DVec3::ZERO || height(0.0) <= 0.0 {
        return None;
    }
    // March out to well past the surface's far side, then halve the step that crosses it.
    let (w, h) = chart.size();
    let reach = 4.0 * (chart.point(0.0, 0.0, 0.0) - p).length() + w.hypot(h);
    let steps = if chart.uniform_normal().is_some() { 1 } else { 400 };
    let dt = reach / f64::from(steps);
    let (mut lo, mut hi) = (0.0, None);
    for k in 1..=steps {
        let t = f64::from(k) * dt;
        if height(t) <= 0.0 {
            hi = Some(t);
            break;
        }
        lo = t;
    }
    let mut hi = hi?;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if height(mid) > 0.0 { lo = mid } else { hi = mid }
    }
    let (u, v, _) = chart.local(p + a * hi);
    Some((u, v, hi))
}

/// The area of the union of discs `(u, v, radius)` (m), counted on a grid of about
/// [`AREA_GRID`] cells along the longer side of their bounds, m².
fn union_area(spots: &[Spot]) -> f64 {
    if let [(_, _, r)] = spots {
        return std::f64::consts::PI * r * r;
    }
    let (mut lo, mut hi) = ((f64::INFINITY, f64::INFINITY), (f64::NEG_INFINITY, f64::NEG_INFINITY));
    for &(u, v, r) in spots {
        lo = (lo.0.min(u - r), lo.1.min(v - r));
        hi = (hi.0.max(u + r), hi.1.max(v + r));
    }
    let g = (hi.0 - lo.0).max(hi.1 - lo.1) / AREA_GRID;
    if g.is_nan() || g <= 0.0 {
        return 0.0;
    }
    let (cols, rows) = (((hi.0 - lo.0) / g).ceil() as usize + 1, ((hi.1 - lo.1) / g).ceil() as usize + 1);
    let mut covered = vec![false; cols * rows];
    for &(u, v, r) in spots {
        let (c0, c1) = (((u - r - lo.0) / g).floor().max(0.0) as usize, ((u + r - lo.0) / g).ceil() as usize);
        let (r0, r1) = (((v - r - lo.1) / g).floor().max(0.0) as usize, ((v + r - lo.1) / g).ceil() as usize);
        for row in r0..r1.min(rows) {
            for col in c0..c1.min(cols) {
                let (x, y) = (lo.0 + (col as f64 + 0.5) * g, lo.1 + (row as f64 + 0.5) * g);
                if (x - u).hypot(y - v) <= r {
                    covered[row * cols + col] = true;
                }
            }
        }
    }
    covered.iter().filter(|&&c| c).count() as f64 * g * g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_union_of_discs_counts_overlaps_once() {
        let one = union_area(&[(0.0, 0.0, 0.1)]);
        assert!((one / (std::f64::consts::PI * 0.01) - 1.0).abs() < 1e-12, "{one}");
        let twice = union_area(&[(0.0, 0.0, 0.1), (0.0, 0.0, 0.1)]);
        assert!((twice / one - 1.0).abs() < 0.01, "{twice}");
        // Two discs apart cover twice one; a band swept 1 m long covers 2 r × 1 m plus a disc.
        let apart = union_area(&[(0.0, 0.0, 0.1), (1.0, 0.0, 0.1)]);
        assert!((apart / (2.0 * std::f64::consts::PI * 0.01) - 1.0).abs() < 0.02, "{apart}");
        let band: Vec<_> = (0..=100).map(|k| (f64::from(k) * 0.01, 0.0, 0.1)).collect();
        let swept = union_area(&band);
        assert!((swept / (0.2 + std::f64::consts::PI * 0.01) - 1.0).abs() < 0.02, "{swept}");
    }
}
