//! Calibration recovers the emitter parameters that made a profile.

use spraysim::Scenario;
use spraysim::scenario::DirectionLaw;
use spraysim_calibrate::{CalibrationSettings, FitParam, MeasuredProfile, calibrate};

/// Shotcrete preset nozzle 1 m above a floor, spraying down for 0.1 s at `rate` particles/s.
fn floor_scene(mu: f64, sigma: f64, seed: u64, rate: f64) -> Scenario {
    Scenario::from_toml(
        &format!(
            r#"
            [simulation]
            duration = 0.2
            dt = 0.01
            seed = {seed}
            integrator = "exact"
            [process]
            preset = "shotcrete"
            [process.impact]
            rebound_model = "never"
            [emitter]
            mu = {mu}
            sigma = {sigma}
            spawn_rate = {rate}
            [[nozzle.waypoints]]
            time = 0.0
            position = [0.0, 0.0, 1.0]
            axis = [0.0, 0.0, -1.0]
            [[nozzle.waypoints]]
            time = 0.1
            position = [0.0, 0.0, 1.0]
            axis = [0.0, 0.0, -1.0]
            spray = false
            [[target]]
            name = "floor"
            center = [0.0, 0.0, 0.0]
            normal = [0.0, 0.0, 1.0]
            up = [0.0, 1.0, 0.0]
            size = [0.4, 0.4]
            resolution = [200, 200]
            "#
        ),
        "floor",
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The radial profile of a run, as a measured-profile CSV in mm.
fn synthetic_profile(sc: &Scenario) -> MeasuredProfile {
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let field = &sim.targets()[0].surface.as_rectangle().expect("a rectangle").field;
    let radii: Vec<f64> = (0..20).map(|i| 0.0025 + 0.005 * i as f64).collect();
    let sampler = spraysim_calibrate::ProfileSampler::new(
        field,
        &radii,
        spraysim_calibrate::ProfileShape::Radial,
        (0.0, 0.0),
        0.0,
    )
    .expect("bins");
    let mut csv = String::from("# synthetic\nradius [mm],thickness [mm]\n");
    for (r, t) in radii.iter().zip(sampler.sample(field.thickness())) {
        csv.push_str(&format!("{},{}\n", r * 1e3, t * 1e3));
    }
    MeasuredProfile::from_csv(&csv, "synthetic.csv").expect("parses")
}

#[test]
fn calibration_recovers_mu_and_sigma_from_a_synthetic_profile() {
    let (mu, sigma) = (0.255, 0.102);
    let measured = synthetic_profile(&floor_scene(mu, sigma, 11, 3e5));
    // Start far off, with another seed: the fit sees the sampling noise of both runs (3 × 10⁴
    // particles each). Over five seeds of the "measurement" the fits scattered by about 0.002
    // in μ and 0.003 in σ around (0.256, 0.106); σ comes out a little high because the
    // 20-point profile averages out the narrowest core. The bounds are several of those spreads.
    let start = floor_scene(0.45, 0.2, 1, 3e5);
    let settings = CalibrationSettings { tolerance: 1e-4, ..CalibrationSettings::default() };
    let mut seen = 0;
    let cal = calibrate(&start, &measured, &settings, |_| seen += 1).expect("calibrates");
    eprintln!("fitted {:?}, {:?}, {} evaluations", cal.fitted, cal.errors, cal.evaluations);
    assert_eq!(cal.params, vec![FitParam::Mu, FitParam::Sigma]);
    assert_eq!(seen, cal.evaluations);
    assert!((cal.fitted[0] - mu).abs() < 0.012, "μ = {}", cal.fitted[0]);
    assert!((cal.fitted[1] - sigma).abs() < 0.02, "σ = {}", cal.fitted[1]);
    // The paper's three measures, in % of the peak: its fit reached 5, 3 and 2.8 on real data.
    assert!(
        cal.errors.max_abs < 0.06 && cal.errors.rms < 0.03 && cal.errors.mean_abs < 0.02,
        "{:?}",
        cal.errors
    );
    assert!(cal.initial_errors.rms > 0.2, "the start was not far off: {:?}", cal.initial_errors);
    // The fitted scenario carries the values.
    let DirectionLaw::TruncatedNormal { mu, sigma, .. } = cal.scenario.emitter().direction else {
        panic!("the fitted scenario keeps its direction law");
    };
    assert_eq!((mu, sigma), (cal.fitted[0], cal.fitted[1]));
}

#[test]
fn calibrating_a_run_that_deposits_nothing_is_an_error() {
    // The example's nozzle turned to point straight up, away from its target.
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let sc = Scenario::from_path(&root.join("calibrate.toml"))
        .and_then(|s| {
            s.with_all(&[
                ("nozzle.waypoints[0].axis".into(), [0.0, 0.0, 1.0].into()),
                ("nozzle.waypoints[1].axis".into(), [0.0, 0.0, 1.0].into()),
                ("emitter.spawn_rate".into(), 2e4.into()),
            ])
        })
        .expect("valid");
    let measured = MeasuredProfile::from_path(&root.join("profile.csv")).expect("profile");
    let settings = CalibrationSettings { threads: 1, ..Default::default() };
    let Err(e) = calibrate(&sc, &measured, &settings, |_| {}) else {
        panic!("a fit of nothing reported as a result")
    };
    assert!(e.to_string().contains("nothing to fit"), "{e}");
}
