//! End-to-end physics checks on small scenes: conservation, layer volume, rebound statistics,
//! process behaviour.

use glam::DVec3;
use spraysim::deposit::DepositSurface;
use spraysim::emission::{Aperture, Direction, Emitter};
use spraysim::scenario::SHOTCRETE_REBOUND_POLYNOMIAL;
use spraysim::scenario::scenes::{bar, wall};
use spraysim::world::Role;
use spraysim::{Metrics, Scenario, Simulation};

fn scenario(text: &str) -> Scenario {
    Scenario::from_toml(text, "test").unwrap_or_else(|e| panic!("{e}"))
}

fn run(sc: &Scenario) -> Simulation {
    let mut sim = sc.build().unwrap_or_else(|e| panic!("{e}"));
    sim.run(|_| {});
    sim
}

/// Every emitted particle is in exactly one fate, by count exactly and by volume to rounding.
fn assert_conserved(m: &Metrics) {
    let total = m.fates.total();
    assert_eq!(total.count, m.emitted.count, "fates {:?} do not add up to {:?}", m.fates, m.emitted);
    assert!((total.volume - m.emitted.volume).abs() <= 1e-12 * m.emitted.volume);
}

/// Σ thickness × cell area equals the stuck volume on every target.
fn assert_layer_volumes(sim: &Simulation) {
    for (t, m) in sim.targets().iter().zip(&sim.metrics().targets) {
        let rel = (t.surface.volume() - m.stuck.volume).abs() / m.stuck.volume.max(1e-300);
        assert!(rel < 1e-6, "{}: layer {} m³ vs stuck {} m³", t.name, t.surface.volume(), m.stuck.volume);
    }
}

#[test]
fn default_scene_conserves_material_and_rebounds_like_shotcrete() {
    let sim = run(&Scenario::default_scene());
    let m = sim.metrics();
    assert_conserved(&m);
    assert_layer_volumes(&sim);
    assert_eq!(m.emitted.count, 20_000); // 10⁴ /s for 2 s
    let rr = m.rebound_ratio.expect("the wall was hit");
    assert!((0.05..=0.30).contains(&rr), "rebound ratio {rr}");
    // Rebound lands on the floor.
    let floor = &m.targets[1];
    assert_eq!(floor.role, Role::Collector);
    assert!(floor.stuck.count > 0);
}

/// Second moments of the wall's layer about its centroid, in cell units.
fn moments(t: &[f64], cols: usize) -> (f64, f64, f64, f64, f64) {
    let (mut m, mut mx, mut my) = (0.0, 0.0, 0.0);
    for (i, &v) in t.iter().enumerate() {
        let (x, y) = ((i % cols) as f64 + 0.5, (i / cols) as f64 + 0.5);
        m += v;
        mx += v * x;
        my += v * y;
    }
    let (cx, cy) = (mx / m, my / m);
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for (i, &v) in t.iter().enumerate() {
        let (x, y) = ((i % cols) as f64 + 0.5 - cx, (i / cols) as f64 + 0.5 - cy);
        sxx += v * x * x;
        syy += v * y * y;
        sxy += v * x * y;
    }
    (cx, cy, sxx / m, syy / m, sxy / m)
}

#[test]
fn default_spot_is_round_and_centred_on_the_aim_point() {
    let sim = run(&Scenario::default_scene());
    let wall = &sim.targets()[0].surface.as_rectangle().expect("a rectangle").field;
    let cols = wall.cols();
    let (cx, cy, sxx, syy, sxy) = moments(wall.thickness(), cols);
    // The nozzle aims at the wall's centre, cell (512, 512); gravity pulls the spot down by
    // g·t²/2 ≈ 8 mm ≈ 4 cells at 25 m/s over 1 m.
    assert!((cx - 512.0).abs() < 2.0, "centroid column {cx}");
    assert!((512.0 - cy) > 2.0 && (512.0 - cy) < 7.0, "centroid row {cy}");
    // Round: equal spread along both axes, no tilt.
    assert!((sxx / syy - 1.0).abs() < 0.1, "spread ratio {}", sxx / syy);
    assert!(sxy.abs() < 0.05 * sxx, "tilted spot");
}

#[test]
fn spawn_count_with_fractional_carry_is_exact() {
    let rate = 12_345.678;
    let e = Emitter {
        aperture: Aperture::Point,
        direction: Direction::UniformPolar,
        cone_half_angle: 0.1,
        speed: [1.0, 2.0],
        spawn_rate: rate,
        particle_volume: 1e-9,
        droplets: None,
    };
    let (mut n, mut carry) = (0, 0.0);
    for step in 1..=10_000u64 {
        n += e.spawn_count(3.7e-4, &mut carry);
        let expected = rate * 3.7e-4 * step as f64;
        assert!((n as f64 - expected).abs() < 1.0 + 1e-6, "after {step} steps: {n} vs {expected}");
    }
}

/// 2 × 10⁴ particles straight down onto a shotcrete plate tilted by `theta_deg`; `extra` goes
/// into `[process.impact]`.
fn tilted_face(theta_deg: f64, alpha: f64, extra: &str) -> Scenario {
    spraysim_validate::checks::tilted_plate(theta_deg, alpha, 2e4, 7, extra)
}

#[test]
fn rebound_fraction_at_fixed_angle_matches_alpha_times_curve() {
    use spraysim_validate::checks::rebound_fraction;
    for (theta, alpha) in [(0.0, 1.0), (30.0, 1.0), (45.0, 1.0), (45.0, 0.5), (55.0, 0.8)] {
        let r = rebound_fraction(theta, alpha, 2e4, 7, 0);
        assert!(r.conserved);
        // The curve, evaluated here independently of the engine's.
        let x: f64 = theta / 90.0;
        let pr: f64 = SHOTCRETE_REBOUND_POLYNOMIAL.iter().rev().fold(0.0, |a, c| a * x + c);
        let p = (alpha * pr.clamp(0.0, 1.0)).clamp(0.0, 1.0);
        assert!((r.expected - p).abs() < 1e-12, "{} vs {p}", r.expected);
        // 4.5 binomial standard deviations: a false alarm about once in 10⁵ runs.
        let tol = 4.5 * (p * (1.0 - p) / r.n as f64).sqrt();
        assert!((r.measured - p).abs() <= tol, "θ = {theta}°, α = {alpha}: {} vs {p} ± {tol}", r.measured);
    }
}

#[test]
fn forced_and_suppressed_rebound_curves() {
    let always = run(&tilted_face(10.0, 1.0, r#"rebound_model = "always""#)).metrics();
    assert_eq!(always.rebound_ratio, Some(1.0));
    let never = run(&tilted_face(80.0, 1.0, r#"rebound_model = "never""#)).metrics();
    assert_eq!(never.rebound_ratio, Some(0.0));
}

#[test]
fn rebound_speed_is_restitution_times_impact_speed() {
    use rand::SeedableRng;
    use spraysim::process::rebound::AlwaysRebound;
    use spraysim::process::{ImpactModel, Outcome};
    let model = ImpactModel {
        alpha: 1.0,
        rebound: std::sync::Arc::new(AlwaysRebound),
        restitution: 0.7,
        scatter: 15f64.to_radians(),
        rest_speed: 0.0,
        rest_max_slope: 0.0,
        cushion_radius: 0.0,
    };
    let n = DVec3::new(0.0, 0.3, 1.0).normalize();
    let v = DVec3::new(3.0, -1.0, -20.0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    let specular = (v - 2.0 * v.dot(n) * n).normalize();
    let mut max_angle: f64 = 0.0;
    for _ in 0..20_000 {
        let Outcome::Rebound(out) = model.resolve(&ImpactModel::site(v, n, None, 0.0, false), &mut rng)
        else {
            panic!("forced rebound stuck")
        };
        assert!((out.length() - 0.7 * v.length()).abs() < 1e-9 * v.length());
        assert!(out.dot(n) >= 0.0, "scattered into the surface");
        max_angle = max_angle.max(out.normalize().dot(specular).clamp(-1.0, 1.0).acos());
    }
    // Scatter fills its cone and stays inside it.
    assert!(
        max_angle <= 15f64.to_radians() + 1e-9 && max_angle > 14f64.to_radians(),
        "max scatter {max_angle}"
    );
}

/// A preset sprayed at a 1.5 m panel over a collector floor for 0.3 s, with `extra` TOML.
fn panel(preset: &str, extra: &str) -> Scenario {
    spraysim_validate::checks::panel_scene(preset, 0.3, extra)
}

#[test]
fn painting_leaves_no_rebound() {
    let sim = run(&panel("painting", ""));
    let m = sim.metrics();
    assert_conserved(&m);
    assert_layer_volumes(&sim);
    assert_eq!(m.rebound_ratio, Some(0.0));
    let p = &m.targets[0];
    assert_eq!(p.hits, p.stuck.count, "every impact on the panel sticks");
    assert_eq!(m.targets[1].hits, 0, "nothing reaches the floor");
    // All but what is still in the air has landed on the panel.
    let landed = m.targets[0].stuck.volume / (m.emitted.volume - m.fates.in_flight.volume);
    assert!((landed - 1.0).abs() < 1e-9, "landed share {landed}");
    assert!(m.transfer_efficiency.expect("emitted") > 0.9);
}

#[test]
fn blasting_leaves_nothing_stuck_on_the_substrate() {
    let sim = run(&panel("blasting", ""));
    let m = sim.metrics();
    assert_conserved(&m);
    let wall = &m.targets[0];
    assert!(wall.hits > 1000);
    assert_eq!(wall.stuck.count, 0);
    assert_eq!(wall.layer_volume, 0.0);
    assert_eq!(m.rebound_ratio, Some(1.0));
    assert_eq!(m.transfer_efficiency, Some(0.0));
}

#[test]
fn particles_never_end_a_step_inside_a_solid() {
    // Grit blasted at a sphere, a box and a bar in front of a wall: thousands of rebounds.
    let obstacles = format!(
        r#"
        [[obstacle]]
        name = "ball"
        shape = "sphere"
        center = [-0.1, 0.05, 1.0]
        radius = 0.04
        [[obstacle]]
        name = "block"
        shape = "box"
        center = [-0.1, -0.08, 1.02]
        size = [0.05, 0.06, 0.08]
        x_axis = [1.0, 1.0, 0.0]
        {}"#,
        bar("bar", [-0.05, -0.5, 0.97], [-0.05, 0.5, 0.97], 0.01),
    );
    let sc = panel("blasting", &obstacles);
    let mut sim = sc.build().expect("valid");
    let mut checked = 0usize;
    while !sim.is_finished() {
        sim.step();
        for (p, _, _) in sim.in_flight() {
            checked += 1;
            for s in sim.scene().surfaces() {
                assert!(!spraysim::collision::Primitive::contains(&s.shape, p), "inside {:?} at {p}", s.kind);
            }
        }
    }
    let m = sim.metrics();
    assert_conserved(&m);
    assert!(m.obstacles.iter().all(|o| o.hits > 0), "{:?}", m.obstacles);
    assert!(checked > 100_000);
}

#[test]
fn particles_that_hit_nothing_are_overspray_whether_they_leave_the_domain_or_expire() {
    let up = scenario(
        r#"
        [simulation]
        duration = 0.5
        [process]
        max_lifetime = 0.2
        [nozzle]
        axis = [0.0, 0.0, 1.0]
        [emitter]
        speed = [1.0, 1.0]
        "#,
    );
    let m = run(&up).metrics();
    assert_conserved(&m);
    // Thrown up at 1 m/s: in 0.2 s nothing leaves the default domain; all expire or fly, and
    // having struck nothing, those that expire are overspray.
    assert_eq!(m.fates.left_domain.count + m.fates.expired.count, 0);
    assert!(m.fates.overspray.count > 0);
    assert_eq!(m.fates.overspray.count + m.fates.in_flight.count, m.emitted.count);
    let fast =
        scenario("[simulation]\nduration = 0.5\n[domain]\nmin = [-2.0, -1.0, 0.0]\nmax = [0.0, 1.0, 2.0]\n");
    let m = run(&fast).metrics();
    assert_conserved(&m);
    // The wall lies on the domain's edge: every particle leaves before it strikes anything.
    assert!(m.fates.overspray.count > 0);
    assert_eq!(m.fates.left_domain.count + m.fates.expired.count, 0);
}

#[test]
fn waypoints_move_the_spot_and_switch_the_spray() {
    let sc = scenario(&format!(
        r#"
        [simulation]
        duration = 1.0
        [emitter]
        spawn_rate = 20000.0
        [[nozzle.waypoints]]
        time = 0.0
        position = [-1.0, 0.5, 1.0]
        axis = [1.0, 0.0, 0.0]
        [[nozzle.waypoints]]
        time = 0.5
        position = [-1.0, -0.5, 1.0]
        axis = [1.0, 0.0, 0.0]
        spray = false
        {wall}
        "#,
        wall = wall().resolution(200, 200),
    ));
    let sim = run(&sc);
    let m = sim.metrics();
    // Spraying only during the first half second.
    assert_eq!(m.emitted.count, 10_000);
    // The pass runs from y = +0.5 (column 50) to y = −0.5 (column 150): right = up × normal = −y.
    let t = sim.targets()[0].surface.thickness();
    let column_sum = |c: usize| (0..200).map(|r| t[r * 200 + c]).sum::<f64>();
    assert!(column_sum(60) > 0.0 && column_sum(100) > 0.0 && column_sum(140) > 0.0);
    assert_eq!(column_sum(20), 0.0);
    assert_eq!(column_sum(180), 0.0);
}

/// Forward Euler and the exact (closed-form, lazily stepped) integrator describe the same
/// physics: fates, rebound ratio, where the impacts land and how thick the layer grows agree
/// within the spread of the particles' random draws.
fn assert_integrators_agree(e: &Simulation, x: &Simulation) {
    let (me, mx) = (e.metrics(), x.metrics());
    for m in [&me, &mx] {
        assert_conserved(m);
    }
    assert_layer_volumes(e);
    assert_layer_volumes(x);
    let n = me.emitted.count as f64;
    assert_eq!(me.emitted.count, mx.emitted.count, "the nozzle emits the same particles");
    // Shares of the emitted particles: binomial spread, 5 standard deviations.
    let shares = |m: &Metrics| {
        let mut v: Vec<(String, f64)> =
            m.targets.iter().map(|t| (format!("stuck on {}", t.name), t.stuck.count as f64 / n)).collect();
        v.push(("rebound ratio".into(), m.rebound_ratio.unwrap_or(0.0)));
        v.push(("on obstacles".into(), m.fates.stuck_on_obstacles.count as f64 / n));
        v.push(("left the domain".into(), m.fates.left_domain.count as f64 / n));
        v.push(("in flight".into(), m.fates.in_flight.count as f64 / n));
        v
    };
    for ((name, a), (_, b)) in shares(&me).into_iter().zip(shares(&mx)) {
        let p = (a + b) / 2.0;
        let tol = 5.0 * (2.0 * p * (1.0 - p) / n).sqrt() + 1e-9;
        assert!((a - b).abs() <= tol, "{name}: Euler {a} vs exact {b} (± {tol})");
    }
    // Profiles of the first target in 16 bands across and 16 along: impact counts (Poisson;
    // twice the variance for particles that strike more than once), and deposited volume in
    // particles (Poisson in the stuck count).
    use spraysim::deposit::{DepositSurface, Layout};
    let volume = me.emitted.volume / n;
    let (te, tx) = (&e.targets()[0].surface, &x.targets()[0].surface);
    let Layout::Grid { rows, cols, .. } = te.layout() else { panic!("the first target is a grid") };
    let bands = |s: &spraysim::deposit::Surface, by_column: bool| {
        let (mut hits, mut layer) = ([0.0; 16], [0.0; 16]);
        for k in 0..rows * cols {
            let b = if by_column { (k % cols) * 16 / cols } else { (k / cols) * 16 / rows };
            hits[b] += f64::from(s.hits()[k]);
            layer[b] += s.thickness()[k] * s.cell_area(k as u32) / volume;
        }
        (hits, layer)
    };
    for by_column in [true, false] {
        let ((he, ve), (hx, vx)) = (bands(te, by_column), bands(tx, by_column));
        for k in 0..16 {
            let tol = 5.0 * (2.0 * (he[k] + hx[k])).sqrt() + 1.0;
            assert!(
                (he[k] - hx[k]).abs() <= tol,
                "impacts, band {k} (columns: {by_column}): {} vs {}",
                he[k],
                hx[k]
            );
            let tol = 5.0 * (ve[k] + vx[k]).sqrt() + 1.0;
            assert!(
                (ve[k] - vx[k]).abs() <= tol,
                "layer, band {k} (columns: {by_column}): {} vs {}",
                ve[k],
                vx[k]
            );
        }
    }
    // Thickness statistics: the mean follows the stuck count; the spread of the cells (CV)
    // within a tenth.
    let (se, sx) = (&me.targets[0].thickness, &mx.targets[0].thickness);
    let stuck = me.targets[0].stuck.count.max(1) as f64;
    let tol = 5.0 * (2.0 / stuck).sqrt() * se.mean.max(sx.mean) + 1e-12;
    assert!(
        (se.mean - sx.mean).abs() <= tol,
        "mean thickness: Euler {} vs exact {} (± {tol})",
        se.mean,
        sx.mean
    );
    assert!(
        (se.cv - sx.cv).abs() <= 0.1 * se.cv.max(sx.cv) + 1e-9,
        "thickness CV: Euler {} vs exact {}",
        se.cv,
        sx.cv
    );
}

#[test]
fn euler_and_exact_agree_within_statistical_tolerance_on_the_reference_scene() {
    use spraysim::motion::Integrator;
    use spraysim_bench::ReferenceScene;
    let run_with = |integrator| {
        let sc = ReferenceScene {
            spawn_rate: 2e5,
            duration: 0.5,
            resolution: 256,
            integrator,
            ..ReferenceScene::default()
        }
        .scenario()
        .expect("the reference scene is valid");
        run(&sc)
    };
    assert_integrators_agree(&run_with(Integrator::Euler), &run_with(Integrator::Exact));
}

#[test]
fn euler_and_exact_agree_within_statistical_tolerance_for_every_process() {
    for preset in ["shotcrete", "painting", "blasting"] {
        let sc = panel(preset, "").with("simulation.duration", 0.5).expect("valid");
        let exact = sc.with("simulation.integrator", "exact").expect("valid");
        assert_integrators_agree(&run(&sc), &run(&exact));
    }
}

#[test]
fn the_impact_log_samples_the_requested_share_of_impacts() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for (share, tol) in [(1.0, 0.0), (0.25, 0.02)] {
        let sc = (panel("shotcrete", "").with("output.impact_log", share))
            .and_then(|sc| sc.with("simulation.duration", 0.5))
            .expect("valid");
        let sim = run(&sc);
        let m = sim.metrics();
        let hits: u64 =
            m.targets.iter().map(|t| t.hits).sum::<u64>() + m.obstacles.iter().map(|o| o.hits).sum::<u64>();
        let logged = sim.impact_log();
        let got = logged.len() as f64 / hits as f64;
        assert!((got - share).abs() <= tol, "logged {got} of the impacts, asked {share}");
        if share == 1.0 {
            let stuck = logged.iter().filter(|i| i.stuck).count() as u64;
            assert_eq!(stuck, m.targets.iter().map(|t| t.stuck.count + t.stuck_on_back.count).sum::<u64>());
            // Impacts lie on their surfaces, with velocities against the normal.
            assert!(logged.iter().all(|i| i.velocity.dot(i.normal) <= 0.0 && i.time <= m.time));
            let files = spraysim::output::write_outputs(&sim, &sc, &tmp.path().join("log")).expect("written");
            let csv = std::fs::read_to_string(tmp.path().join("log/impacts.csv")).expect("impact log");
            assert_eq!(csv.lines().count(), logged.len() + 1);
            assert!(
                csv.starts_with(
                    "time_s,x_m,y_m,z_m,nx,ny,nz,vx_m_s,vy_m_s,vz_m_s,surface,outcome,eroded_m3\n"
                )
            );
            assert!(csv.contains(",panel,stuck,") && csv.contains(",panel,rebounded,") && files.len() > 5);
        }
    }
}
