//! Deposition and impact statistics against closed forms (physics-notes, "Analytic checks").

use glam::DVec3;
use spraysim::{Scenario, Simulation};

/// Point nozzle at height `h` spraying straight down, uniformly over the solid angle of a cone
/// of half-angle `half_deg`, without gravity, onto a floor that keeps everything.
fn cone_scene(h: f64, half_deg: f64, direction: &str) -> Scenario {
    Scenario::from_toml(
        &format!(
            r#"
            [simulation]
            duration = 0.2
            gravity = [0.0, 0.0, 0.0]
            [process.impact]
            rebound_model = "never"
            [emitter]
            shape = "point"
            direction = "{direction}"
            cone_angle = {cone}
            speed = [50.0, 50.0]
            spawn_rate = 2000000.0
            # Spray for 0.15 s; by 0.2 s everything has landed.
            [[nozzle.waypoints]]
            time = 0.0
            position = [0.0, 0.0, {h}]
            axis = [0.0, 0.0, -1.0]
            [[nozzle.waypoints]]
            time = 0.15
            position = [0.0, 0.0, {h}]
            axis = [0.0, 0.0, -1.0]
            spray = false
            [[target]]
            name = "floor"
            center = [0.0, 0.0, 0.0]
            normal = [0.0, 0.0, 1.0]
            up = [1.0, 0.0, 0.0]
            size = [0.8, 0.8]
            resolution = [160, 160]
            "#,
            cone = 2.0 * half_deg
        ),
        "cone",
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// χ² of the annulus-averaged thickness against t(r) = V cos³θ / (2π (1 − cos θc) h²), with
/// each annulus's Poisson error; also returns the number of annuli.
fn cone_chi2(direction: &str) -> (f64, usize) {
    let (h, half) = (0.5_f64, 30.0_f64);
    let mut sim = Simulation::new(&cone_scene(h, half, direction)).expect("valid");
    sim.run(|_| {});
    let m = sim.metrics();
    let floor = &sim.targets()[0];
    // Everything lands: the absolute volume is the emitted volume.
    assert_eq!(m.fates.in_flight.count, 0);
    assert_eq!(floor.stuck.count, m.emitted.count);
    let v = floor.stuck.volume;
    let n = m.emitted.count as f64;
    let cos_c = half.to_radians().cos();
    let law = |r: f64| {
        let c = (h / (h * h + r * r).sqrt()).powi(3);
        v * c / (2.0 * std::f64::consts::PI * (1.0 - cos_c) * h * h)
    };
    let (cols, cell) = (160usize, 0.8 / 160.0);
    let width = 0.02;
    let r_edge = h * half.to_radians().tan();
    // Annuli clear of the cone's edge by two cells.
    let bins = ((r_edge - 2.0 * cell) / width) as usize;
    let (mut sum, mut model) = (vec![0.0; bins], vec![0.0; bins]);
    for (i, &t) in floor.field.thickness().iter().enumerate() {
        let (x, y) = (((i % cols) as f64 + 0.5) * cell - 0.4, ((i / cols) as f64 + 0.5) * cell - 0.4);
        let r = x.hypot(y);
        let k = (r / width) as usize;
        if k < bins {
            sum[k] += t;
            model[k] += law(r);
        }
    }
    let mut chi2 = 0.0;
    for k in 0..bins {
        // Particles expected in the annulus: its share of the cone's solid angle.
        let theta = |r: f64| (r / h).atan();
        let (a, b) = (theta(k as f64 * width), theta((k + 1) as f64 * width));
        let expected = n * (a.cos() - b.cos()) / (1.0 - cos_c);
        let sigma = model[k] / expected.sqrt();
        chi2 += ((sum[k] - model[k]) / sigma).powi(2);
    }
    (chi2, bins)
}

#[test]
fn a_cone_onto_a_plane_follows_the_cos3_law_in_shape_and_volume() {
    let (chi2, dof) = cone_chi2("uniform_solid_angle");
    // χ² with `dof` degrees of freedom: mean dof, sd √(2 dof); 5 sd is a false alarm about
    // once in 10⁵ runs.
    let limit = dof as f64 + 5.0 * (2.0 * dof as f64).sqrt();
    eprintln!("cone χ² = {chi2:.1} over {dof} annuli");
    assert!(chi2 < limit, "χ² = {chi2} over {dof} annuli (limit {limit})");
    // Uniform in polar angle concentrates at the axis: the same test rejects it.
    let (wrong, _) = cone_chi2("uniform_polar");
    assert!(wrong > 10.0 * limit, "uniform_polar passed the cos³ law: χ² = {wrong}");
}

#[test]
fn scatter_angles_are_uniform_over_the_scatter_cone() {
    use rand::SeedableRng;
    use spraysim::impact::{ImpactModel, Outcome, ReboundCurve};
    let half = 30f64.to_radians();
    let model = ImpactModel {
        alpha: 1.0,
        curve: ReboundCurve::Always,
        restitution: 0.5,
        scatter: half,
        rest_speed: 0.0,
        rest_max_slope: 0.0,
        cushion_factor: 1.0,
        cushion_thickness: 0.0,
    };
    // Normal incidence: the specular direction is the normal, the cone stays off the surface.
    let (n, v) = (DVec3::Z, DVec3::new(0.0, 0.0, -10.0));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    const BINS: usize = 20;
    const N: usize = 100_000;
    let mut hist = [0usize; BINS];
    let mut mean_speed = 0.0;
    for _ in 0..N {
        let Outcome::Rebound(out) = model.resolve(v, n, None, &mut rng) else { panic!("forced rebound") };
        mean_speed += out.length() / N as f64;
        // Uniform over the cap's solid angle: 1 − cos ψ is uniform on [0, 1 − cos(half)].
        let u = (1.0 - out.normalize().z) / (1.0 - half.cos());
        hist[((u * BINS as f64) as usize).min(BINS - 1)] += 1;
    }
    let expected = N as f64 / BINS as f64;
    let chi2: f64 = hist.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
    assert!(chi2 < 50.0, "χ² = {chi2} (19 degrees of freedom)");
    assert!((mean_speed - 5.0).abs() < 1e-9, "mean rebound speed {mean_speed}");
}
