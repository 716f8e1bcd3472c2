//! Cohesive failure against its analytic thresholds, and mass conservation through failure.

use glam::DVec3;
use spraysim::Simulation;
use spraysim::collision::Face;
use spraysim::deposit::RectangleSurface;
use spraysim::process::layer::{Strength, analyse};

const RHO: f64 = 2300.0;
const G: DVec3 = DVec3::new(0.0, 0.0, -9.81);
const S: Strength = Strength { tensile: 1500.0, shear: 5000.0, cohesion: 2000.0 };

/// A `size` m square face with outward `normal`, `cells` × `cells` cells.
fn face(normal: DVec3, size: f64, cells: usize) -> RectangleSurface {
    let up = if normal.cross(DVec3::Z).length() > 1e-9 { DVec3::Z } else { DVec3::X };
    RectangleSurface::new(Face::new(DVec3::ZERO, normal, up, [size, size]), cells, cells, 0.0)
}

fn uniform(t: f64, normal: DVec3) -> RectangleSurface {
    let mut r = face(normal, 1.0, 40);
    for c in 0..1600 {
        let area = r.field.cell_area();
        r.field.deposit(c, t * area);
    }
    r
}

fn fails(t: f64, normal: DVec3) -> bool {
    analyse(&uniform(t, normal), RHO, G, &S).regions.iter().any(|r| r.fails())
}

#[test]
fn uniform_layers_fail_at_the_analytic_thicknesses() {
    let ceiling = S.tensile / (RHO * 9.81);
    let wall = S.shear / (RHO * 9.81);
    assert!(!fails(ceiling * 0.999, -DVec3::Z) && fails(ceiling * 1.001, -DVec3::Z));
    assert!(!fails(wall * 0.999, -DVec3::X) && fails(wall * 1.001, -DVec3::X));
    assert!(!fails(10.0, DVec3::Z), "a floor never fails");
    // A ceiling fails at a thinner layer than a wall.
    assert!(ceiling < wall);
    // A face tilted 45° (an overhang) fails on the worse of pull-off and shear.
    let n = DVec3::new(-1.0, 0.0, -1.0).normalize();
    let tilted = (S.tensile / (RHO * 9.81 * 0.5f64.sqrt())).min(S.shear / (RHO * 9.81 * 0.5f64.sqrt()));
    assert!(!fails(tilted * 0.999, n) && fails(tilted * 1.001, n));
}

/// The analysis of a `size` m square ceiling of 2 cm cells carrying `base` m of layer, with a
/// square patch of `side` cells `patch` m thick at its centre.
fn ceiling_with_patch(size: f64, side: usize, patch: f64, base: f64) -> spraysim::process::layer::Analysis {
    let n = (size / 0.02).round() as usize;
    let mut f = face(-DVec3::Z, size, n);
    let lo = (n - side) / 2;
    for c in 0..(n * n) as u32 {
        let (r, col) = (c as usize / n, c as usize % n);
        let inside = (lo..lo + side).contains(&r) && (lo..lo + side).contains(&col);
        let area = f.field.cell_area();
        f.field.deposit(c, if inside { patch } else { base } * area);
    }
    analyse(&f, RHO, G, &S)
}

#[test]
fn small_patches_on_a_sound_layer_hang_on_and_large_ones_fall() {
    // 6 cm of 80 mm on 20 mm: 1.1 N of excess, 9.6 N across its edge, 6.7 N of spare adhesion
    // in the first ring around it.
    let small = ceiling_with_patch(2.0, 3, 0.08, 0.02);
    assert_eq!(small.regions.len(), 1);
    assert!(!small.regions[0].fails(), "a 6 cm patch is held by the layer around it: {:?}", small.regions[0]);
    // 80 cm of 80 mm on 20 mm: 195 N of excess against 128 N across its edge.
    let large = ceiling_with_patch(2.0, 40, 0.08, 0.02);
    let r = &large.regions[0];
    assert!(
        r.fails() && r.cells.len() == 1600,
        "an 80 cm patch falls: {} N against {} N",
        r.driving,
        r.holding
    );
    assert!((r.holding - 2000.0 * 3.2 * 0.02).abs() < 1e-9 * 128.0, "{} N", r.holding);
}

/// Regression: a region was held by cohesion over its own thickness along its edge, so a thick
/// lump hung from a thin rim (a 1.5 L static shot hung 0.26 m deep from a ceiling).
#[test]
fn a_thick_lump_does_not_hang_from_a_thin_rim() {
    // 6 cm of 200 mm on 10 mm: 10.8 N of excess; the rim passes on 2000 Pa × 0.24 m × 0.01 m
    // (it would have held 48 N with the lump's own thickness).
    let lump = ceiling_with_patch(2.0, 3, 0.2, 0.01);
    let r = &lump.regions[0];
    assert!(r.fails(), "{r:?}");
    assert!((r.holding - 2000.0 * 0.24 * 0.01).abs() < 1e-9, "{r:?}");
}

#[test]
fn the_load_must_end_in_spare_adhesion() {
    // 6 cm of 80 mm on 66 mm, a layer 11 Pa short of pulling off itself. Its 1.1 N of excess
    // crosses the rim (32 N), but a 20 cm ceiling has only 0.4 N of adhesion to spare.
    let small_ceiling = ceiling_with_patch(0.2, 3, 0.08, 0.066);
    assert!(small_ceiling.regions[0].fails(), "{:?}", small_ceiling.regions[0]);
    // A 2 m ceiling has 40 N.
    let large_ceiling = ceiling_with_patch(2.0, 3, 0.08, 0.066);
    assert!(!large_ceiling.regions[0].fails(), "{:?}", large_ceiling.regions[0]);
}

/// The validation module's sprayed face at 10⁵ particles/s, run to the end.
fn sprayed(
    normal: [f64; 3],
    up: [f64; 3],
    center: [f64; 3],
    flow: f64,
    duration: f64,
    interval: f64,
) -> Simulation {
    let sc = spraysim_validate::checks::sprayed_face(normal, up, center, flow, duration, interval, 1e5);
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    sim
}

/// Build-up rate of the layer on the face, m/s: the face catches (0.5/0.7)² of the flow.
fn build_up(flow: f64) -> f64 {
    flow * (0.5f64 / 0.7).powi(2) / 0.25
}

fn assert_balanced(sim: &Simulation) {
    let b = sim.metrics().volume_balance;
    assert!(b.residual.abs() <= 1e-6 * b.emitted, "{b:?}");
}

#[test]
fn a_sprayed_ceiling_fails_near_the_pull_off_thickness_and_conserves_mass() {
    let (flow, interval) = (4.9e-3, 0.1); // 10 mm/s on the face: 1 mm per analysis
    let sim = sprayed([0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], flow, 9.0, interval);
    let m = sim.metrics();
    assert_balanced(&sim);
    let first = m.failures.events.first().expect("the ceiling must fail");
    let critical = 1500.0 / (RHO * 9.81);
    // The face's mean thickness when it failed.
    let at_failure = build_up(flow) * first.time;
    // Within one interval's build-up plus the layer's particle noise (a few per cent).
    let tol = build_up(flow) * interval + 0.03 * critical;
    assert!((at_failure - critical).abs() < tol, "failed at {at_failure} m, analytic {critical} m");
    assert!(first.area > 0.1, "a large region falls: {first:?}");
    // The fallen material lands on the floor.
    let floor = &m.targets[1];
    assert!(floor.received.volume > 0.9 * first.volume, "{:?}", floor.received);
    assert_eq!(m.failures.released.count, m.targets[0].detached.count);
}

#[test]
fn a_sprayed_wall_fails_near_the_shear_thickness_and_a_floor_never() {
    let (flow, interval) = (2e-2, 0.05); // 40 mm/s on the face: 2 mm per analysis
    let sim = sprayed([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 0.0, 1.0], flow, 7.0, interval);
    let m = sim.metrics();
    assert_balanced(&sim);
    let first = m.failures.events.first().expect("the wall must fail");
    let critical = 5000.0 / (RHO * 9.81);
    let at_failure = build_up(flow) * first.time;
    let tol = build_up(flow) * interval + 0.03 * critical;
    assert!(
        (at_failure - critical).abs() < tol,
        "failed at {at_failure} m ({first:?}), analytic {critical} m"
    );
    let floor = sprayed([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0], flow, 7.0, interval);
    let fm = floor.metrics();
    assert!(fm.failures.events.is_empty(), "a floor failed: {:?}", fm.failures.events.first());
    assert!(
        fm.targets[0].thickness.mean > 0.5 * 2.0 * critical,
        "the floor layer grew past the wall's limit"
    );
    assert_balanced(&floor);
}
