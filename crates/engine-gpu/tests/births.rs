//! The newborns the `born` kernel samples on the GPU against the engine's own draws of the same
//! births: the aperture's points, the directions within the cone or fan, the speeds and the
//! nozzle's own velocity, in each batch's frame, for every aperture and direction law, by
//! two-sample Kolmogorov–Smirnov tests; and each newborn's id and birth step exactly.

mod common;

use glam::DVec3;
use spraysim_engine::emission::{Aperture, Direction, Emitter, NozzleFrame};
use spraysim_engine::motion::Integrator;
use spraysim_engine::particles::Particle;
use spraysim_engine::pipeline::{Births, FlightJob};
use spraysim_engine::{Simulation, SimulationConfig};

/// Newborns per batch; three batches a case.
const PER_BATCH: u64 = 7000;

/// Steps the call flies: the batches are born at steps 0, 1 and 2.
const STEPS: u64 = 3;

/// The two-sample Kolmogorov–Smirnov statistic exceeds `KS_C √((n + m) / (n m))` with
/// probability 10⁻⁶ where both samples come from one continuous law (c = √(−ln(α/2)/2)).
const KS_C: f64 = 2.68;

/// The largest distance between the empirical distribution functions of `a` and `b`.
fn ks_distance(mut a: Vec<f64>, mut b: Vec<f64>) -> f64 {
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (n, m) = (a.len() as f64, b.len() as f64);
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < a.len() && j < b.len() {
        let x = a[i].min(b[j]);
        while i < a.len() && a[i] <= x {
            i += 1;
        }
        while j < b.len() && b[j] <= x {
            j += 1;
        }
        d = d.max((i as f64 / n - j as f64 / m).abs());
    }
    d
}

/// Asserts that `a` (the engine's) and `b` (the GPU's) come from one law.
fn same_law(what: &str, a: Vec<f64>, b: Vec<f64>) {
    let (n, m) = (a.len() as f64, b.len() as f64);
    let limit = KS_C * ((n + m) / (n * m)).sqrt();
    let d = ks_distance(a, b);
    assert!(d <= limit, "{what}: Kolmogorov–Smirnov distance {d:.4} beyond {limit:.4}");
}

/// A start in its batch's frame: the aperture offsets (along the width and height axes, m),
/// the polar angle from the axis and the azimuth (rad), the two fan angles (rad), the speed
/// (m/s) once the nozzle's velocity is taken off.
fn local(p: (DVec3, DVec3), b: &Births) -> [f64; 7] {
    let (x, v) = (p.0 - b.frame.position, p.1 - b.carried);
    let f = &b.frame;
    let (a, w, h) = (v.dot(f.axis), v.dot(f.width_axis), v.dot(f.height_axis));
    [
        x.dot(f.width_axis),
        x.dot(f.height_axis),
        (a / v.length()).clamp(-1.0, 1.0).acos(),
        h.atan2(w),
        w.atan2(a),
        h.atan2(a),
        v.length(),
    ]
}

/// The start of a particle flown from its birth to the end of step `STEPS` with the exact
/// integrator under gravity `g`: its position and velocity at birth.
fn start(p: &Particle, g: DVec3, dt: f64) -> (DVec3, DVec3) {
    let t = (STEPS - u64::from(p.born)) as f64 * dt;
    let v0 = p.anchor_velocity() - g * t;
    (p.anchor - v0 * t - 0.5 * g * t * t, v0)
}

fn case(gpu: &spraysim_gpu::GpuFlight, name: &str, emitter: Emitter) {
    let mut config = SimulationConfig::example_wall(0.1);
    config.motion.integrator = Integrator::Exact;
    config.emitter = emitter;
    let sim = Simulation::new(config.clone()).expect("valid");
    // Three batches from three poses, the last carrying the nozzle's own velocity.
    let frames = [
        (DVec3::new(-1.5, 0.2, 1.0), DVec3::new(1.0, 0.2, -0.3), 0.4, DVec3::ZERO),
        (DVec3::new(-1.2, -0.4, 1.5), DVec3::new(1.0, -0.5, 0.1), -1.1, DVec3::ZERO),
        (DVec3::new(-1.0, 0.0, 0.6), DVec3::X, 0.0, DVec3::new(0.0, 1.5, -0.5)),
    ];
    let births: Vec<Births> = frames
        .iter()
        .enumerate()
        .map(|(k, &(at, axis, roll, carried))| Births {
            step: k as u64,
            first: 100 + k as u64 * PER_BATCH,
            count: PER_BATCH,
            frame: NozzleFrame::new(at, axis.normalize(), roll),
            carried,
        })
        .collect();
    let job = FlightJob {
        config: &config,
        from: 0,
        to: STEPS,
        epoch: STEPS,
        particles: &[],
        quanta: &[],
        births: &births,
        nozzle_quanta: 1 << 24,
        key: spraysim_engine::particles::StreamKey::new(config.seed),
        targets: sim.targets(),
        revised: &vec![None; sim.targets().len()],
    };
    let (report, flown) = gpu.fly_traced(&job).expect("the GPU flies the births");
    let engine = job.newborns();
    assert_eq!(flown.len(), engine.len(), "{name}: one slot a newborn");
    for (g, e) in flown.iter().zip(&engine) {
        assert_eq!((g.id, g.born), (e.id, e.born), "{name}: ids and birth steps in order");
    }
    assert_eq!(report.particles.len(), flown.len(), "{name}: none reaches a surface in {STEPS} steps");
    let (g, dt) = (config.motion.gravity, config.dt);
    let batch = |p: &Particle| &births[((u64::from(p.id) - 100) / PER_BATCH) as usize];
    let gpu_local: Vec<[f64; 7]> = flown.iter().map(|p| local(start(p, g, dt), batch(p))).collect();
    let cpu_local: Vec<[f64; 7]> =
        engine.iter().map(|p| local((p.anchor, p.anchor_velocity()), batch(p))).collect();
    let column = |set: &[[f64; 7]], k: usize| set.iter().map(|s| s[k]).collect::<Vec<_>>();
    let names =
        ["offset across", "offset up", "polar angle", "azimuth", "fan angle across", "fan angle up", "speed"];
    for (k, what) in names.iter().enumerate() {
        let (a, b) = (column(&cpu_local, k), column(&gpu_local, k));
        if a.iter().all(|x| x.abs() < 1e-12) {
            // A point aperture: every start at the nozzle, to the f32 rounding of the flight.
            assert!(b.iter().all(|x| x.abs() < 1e-5), "{name}: {what} off the nozzle's point");
            continue;
        }
        same_law(&format!("{name}: {what}"), a, b);
    }
}

#[test]
fn newborns_follow_the_emitters_laws_as_the_engine_draws_them() {
    let Some(gpu) = common::gpu() else { return };
    let deg = std::f64::consts::PI / 180.0;
    let emitter = |aperture, direction, half: f64| Emitter {
        aperture,
        direction,
        cone_half_angle: half * deg,
        speed: [20.0, 35.0],
        spawn_rate: 1e5,
        particle_volume: 1e-9,
        droplets: None,
    };
    let cases = [
        ("a point, uniform in polar angle", emitter(Aperture::Point, Direction::UniformPolar, 15.0)),
        (
            "a disc, a truncated normal",
            emitter(Aperture::Circle { r: 0.02 }, Direction::TruncatedNormal { mu: 0.3, sigma: 0.4 }, 20.0),
        ),
        (
            "a ring, a truncated normal in its upper tail",
            emitter(
                Aperture::Annulus { r_in: 0.01, r_out: 0.03 },
                Direction::TruncatedNormal { mu: -0.2, sigma: 0.3 },
                25.0,
            ),
        ),
        (
            "a ring, uniform in solid angle",
            emitter(Aperture::Annulus { r_in: 0.005, r_out: 0.02 }, Direction::UniformSolidAngle, 30.0),
        ),
        (
            "a slot, a fan",
            emitter(
                Aperture::Rectangle { hw: 0.01, hh: 0.002 },
                Direction::Fan { wide: 60.0 * deg, narrow: 10.0 * deg },
                5.0,
            ),
        ),
    ];
    for (name, e) in cases {
        case(&gpu, name, e);
    }
}
