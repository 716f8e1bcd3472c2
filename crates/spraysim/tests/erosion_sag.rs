//! Blasting erosion of a coating, and sag risk of a painted film.

use spraysim::deposit::DepositSurface;
use spraysim::scenario::scenes::wall;
use spraysim::{Metrics, Scenario, Simulation};

/// A wall under a `coating` m thick coat, blasted for 0.5 s from a nozzle 0.3 m away whose axis
/// makes `gamma_deg` with the wall, with a spray cone of `cone_deg`.
fn blast(gamma_deg: f64, model: &str, cone_deg: f64, coating: f64) -> (Simulation, Metrics) {
    let g = gamma_deg.to_radians();
    let text = format!(
        r#"
        [simulation]
        duration = 0.5
        [process]
        preset = "blasting"
        [process.erosion]
        model = "{model}"
        [process.impact]
        scatter_angle = 0.0
        [emitter]
        cone_angle = {cone_deg}
        [nozzle]
        position = [{x}, 0.0, {z}]
        axis = [{ax}, 0.0, {az}]
        {wall}
        "#,
        wall = wall().size(1.0, 1.0).resolution(100, 100).coating(coating),
        x = -0.3 * g.sin(),
        z = 1.0 + 0.3 * g.cos(),
        ax = g.sin(),
        az = -g.cos(),
    );
    let sc = Scenario::from_toml(&text, "blast").unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let m = sim.metrics();
    (sim, m)
}

#[test]
fn oblique_grit_erodes_far_more_than_square_grit_under_finnie() {
    // A parallel jet on bare steel: every first impact at the nozzle's angle.
    let (_, oblique) = blast(20.0, "finnie", 0.0, 0.0);
    let (_, square) = blast(90.0, "finnie", 0.0, 0.0);
    let depth = |m: &Metrics| m.targets[0].erosion.as_ref().expect("erosion on").mean_depth;
    // f(20°) ≈ 0.29 against f(90°) = 0: square impacts erode nothing.
    assert!(depth(&oblique) > 0.0);
    // Only gravity bends a square jet off 90° (by about 1e-4 rad), and f is quadratic there.
    assert!(depth(&square) < 1e-6 * depth(&oblique), "{} vs {}", depth(&square), depth(&oblique));
    // Oka: every grain removes g(γ) E90 m, so the two jets erode in the ratio of g, with the
    // exponents of steel's hardness (1.4 GPa).
    let (_, oka_oblique) = blast(20.0, "oka", 0.0, 0.0);
    let (_, oka_square) = blast(90.0, "oka", 0.0, 0.0);
    let steel = spraysim::process::erosion::Oka::for_hardness(1.4, 6.2e-8, 104.0, 326e-6, 0.19, 0.5e-3);
    let g = |deg: f64| spraysim::process::erosion::oka_g(deg.to_radians(), steel.n1, steel.n2, 1.4);
    let ratio = depth(&oka_oblique) / depth(&oka_square);
    assert!((ratio / (g(20.0) / g(90.0)) - 1.0).abs() < 0.01, "ratio {ratio} vs g {}", g(20.0) / g(90.0));
}

#[test]
fn a_coat_and_steel_wear_at_their_own_rates() {
    // The same grit stream onto bare steel and onto a coat too thick to blast through.
    let (steel_sim, steel) = blast(20.0, "finnie", 15.0, 0.0);
    let (coat_sim, coat) = blast(20.0, "finnie", 15.0, 0.01);
    let (steel_maps, coat_maps) = (
        steel_sim.targets()[0].erosion.as_ref().expect("erosion on"),
        coat_sim.targets()[0].erosion.as_ref().expect("erosion on"),
    );
    assert!(coat_maps.coating.iter().all(|&c| c > 0.0), "the coat was blasted through");
    assert!(coat_maps.substrate.iter().all(|&d| d == 0.0), "steel wore under its coat");
    // Finnie's law scales with each layer's constant: 2e-9 m³/J for a coat, 3e-11 for steel.
    let depth = |m: &Metrics| m.targets[0].erosion.as_ref().expect("erosion on").mean_depth;
    let ratio = depth(&coat) / depth(&steel);
    assert!((ratio / (2e-9 / 3e-11) - 1.0).abs() < 1e-9, "coat/steel depth ratio {ratio}");
    assert!(steel_maps.substrate.iter().any(|&d| d > 0.0));
}

#[test]
fn the_coating_goes_first_where_erosion_is_strongest() {
    let (sim, m) = blast(20.0, "finnie", 15.0, 0.00005);
    let wall = &sim.targets()[0];
    let maps = wall.erosion.as_ref().expect("erosion on");
    let cleaned = m.targets[0].erosion.as_ref().and_then(|e| e.cleaned_fraction).expect("coated");
    assert!(cleaned > 0.0 && cleaned < 0.5, "cleaned share {cleaned}");
    // Every cleaned cell has been eroded at least as deep as any cell still coated.
    let cells = || 0..maps.coating.len();
    let deepest_coated =
        cells().filter(|&c| maps.coating[c] > 0.0).map(|c| maps.eroded(c)).fold(0.0, f64::max);
    let shallowest_clean =
        cells().filter(|&c| maps.coating[c] <= 0.0).map(|c| maps.eroded(c)).fold(f64::INFINITY, f64::min);
    assert!(shallowest_clean >= deepest_coated && shallowest_clean >= 0.00005);
    // Steel wears only where the coat is gone, and there it has.
    assert!(cells().all(|c| maps.substrate[c] == 0.0 || maps.coating[c] == 0.0));
    assert!(cells().any(|c| maps.substrate[c] > 0.0), "no steel wore under the cleaned cells");
    // Nothing deposits, and the coating never goes below zero.
    assert_eq!(wall.surface.volume(), 0.0);
    assert!(maps.coating.iter().all(|&c| (0.0..=0.00005).contains(&c)));
    assert!(m.targets[0].hits_per_cm2 > 0.0);
}

fn paint(normal: [f64; 3], up: [f64; 3], extra: &str) -> Metrics {
    let n = glam::DVec3::from_array(normal);
    let nozzle = glam::DVec3::new(0.0, 0.0, 1.0) + n * 0.25;
    let text = format!(
        r#"
        [simulation]
        duration = 1.0
        gravity = [0.0, 0.0, 0.0]
        [process]
        preset = "painting"
        {extra}
        [nozzle]
        position = {:?}
        axis = {:?}
        [[target]]
        name = "panel"
        center = [0.0, 0.0, 1.0]
        normal = {normal:?}
        up = {up:?}
        size = [1.0, 1.0]
        resolution = [100, 100]
        splat_radius = 0.01
        "#,
        nozzle.to_array(),
        (-n).to_array()
    );
    let sc = Scenario::from_toml(&text, "paint").unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    sim.metrics()
}

#[test]
fn a_thick_wet_film_sags_on_a_wall_but_not_on_a_floor() {
    // Gravity off while spraying, so both films come out the same; only the face's tilt differs.
    let wall = paint([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], "");
    let floor = paint([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], "");
    assert!(wall.targets[0].thickness.max > 120e-6, "the film must exceed the threshold somewhere");
    let risk = |m: &Metrics| m.targets[0].sag_risk_fraction.expect("sag on");
    assert!(risk(&wall) > 0.0);
    assert_eq!(risk(&floor), 0.0);
    assert!((wall.targets[0].thickness.max - floor.targets[0].thickness.max).abs() < 1e-12);
}

#[test]
fn dripping_caps_the_film_near_the_sag_limit_and_keeps_the_volume() {
    let wall = paint([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], "drip_interval = 0.05");
    let floor = paint([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], "drip_interval = 0.05");
    let dripped = wall.failures.dripped.volume;
    assert!(dripped > 0.0);
    assert_eq!(floor.failures.dripped.volume, 0.0, "a floor does not drip");
    // After the last pass the film exceeds 120 µm by at most what a 0.05 s interval adds.
    let undripped = paint([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], "");
    assert!(wall.targets[0].thickness.max < undripped.targets[0].thickness.max);
    assert!(wall.targets[0].thickness.max < 120e-6 + 0.05 * undripped.targets[0].thickness.max);
    // Every drop is accounted for.
    let b = &wall.volume_balance;
    assert!(b.residual.abs() <= 1e-6 * b.emitted, "{b:?}");
    assert!((wall.failures.released.volume - dripped).abs() <= 1e-6 * dripped);
}
