//! The closed-form experiments: each runs the engine (or one of its models) and returns what it
//! measured beside what the closed form says, with the statistic that compares them.

use glam::DVec3;
use rand::SeedableRng;
use spraysim_engine::deposit::DepositSurface;
use spraysim_engine::emission::{Aperture, Direction, Emitter, NozzleFrame, normal_cdf};
use spraysim_engine::motion::Integrator;
use spraysim_engine::process::rebound::AlwaysRebound;
use spraysim_engine::process::{ImpactModel, Outcome};
use spraysim_engine::{Metrics, Simulation};
use spraysim_scenario::scenes::{floor, integrator_word, scenario, wall};
use spraysim_scenario::{SHOTCRETE_REBOUND_POLYNOMIAL, Scenario};
use std::f64::consts::PI;
use std::sync::Arc;

pub(crate) fn run(sc: &Scenario, threads: usize) -> Simulation {
    let mut sim = sc.build().unwrap_or_else(|e| panic!("built-in validation scene: {e}"));
    // Thread counts are validated by the caller; results do not depend on them.
    let _ = sim.set_threads(threads);
    sim.run(|_| {});
    sim
}

/// Thickness against radius from a point nozzle onto a plane, without gravity.
#[derive(Clone, Debug)]
pub struct ConeLaw {
    /// Nozzle height above the plane, m.
    pub height: f64,
    /// Cone half-angle, rad.
    pub half_angle: f64,
    /// Annulus centres, m.
    pub radii: Vec<f64>,
    /// Mean simulated thickness per annulus, m.
    pub simulated: Vec<f64>,
    /// Closed form t(r) = V cos³θ / (2π (1 − cos θc) h²) averaged over the same cells, m.
    pub closed_form: Vec<f64>,
    /// Poisson standard error of each simulated annulus mean, m.
    pub sigma: Vec<f64>,
    /// χ² of simulated against closed form.
    pub chi2: f64,
    /// Emitted particles.
    pub emitted: u64,
    /// Particles stuck on the plane.
    pub stuck: u64,
    /// Emitted and deposited volume, m³.
    pub volumes: (f64, f64),
}

/// Sprays `particles` particles from a point `h` = 0.5 m above a floor, uniformly over the solid
/// angle of a 30° half-angle cone when `dir` is `"uniform_solid_angle"` (or with another
/// direction law, to see the check reject it), and compares the stuck layer with the cos³ law in
/// annuli 2 cm wide.
pub fn cone_law(dir: &str, particles: f64, threads: usize) -> ConeLaw {
    let (h, half_deg) = (0.5_f64, 30.0_f64);
    let (size, cols) = (0.8_f64, 160usize);
    let spray = 0.15;
    let sc = cone_scene(dir, h, half_deg, size, cols, particles / spray, spray);
    let sim = run(&sc, threads);
    let m = sim.metrics();
    let floor = &sim.targets()[0];
    let v = m.targets[0].stuck.volume;
    let n = m.emitted.count as f64;
    let half = half_deg.to_radians();
    let cos_c = half.cos();
    let law = |r: f64| {
        let c = (h / (h * h + r * r).sqrt()).powi(3);
        v * c / (2.0 * PI * (1.0 - cos_c) * h * h)
    };
    let cell = size / cols as f64;
    let width = 0.02;
    // Annuli clear of the cone's edge by two cells.
    let bins = ((h * half.tan() - 2.0 * cell) / width) as usize;
    let (mut sum, mut model, mut count) = (vec![0.0; bins], vec![0.0; bins], vec![0usize; bins]);
    for (i, &t) in floor.surface.thickness().iter().enumerate() {
        let x = ((i % cols) as f64 + 0.5) * cell - size / 2.0;
        let y = ((i / cols) as f64 + 0.5) * cell - size / 2.0;
        let r = x.hypot(y);
        let k = (r / width) as usize;
        if k < bins {
            sum[k] += t;
            model[k] += law(r);
            count[k] += 1;
        }
    }
    let mut chi2 = 0.0;
    let mut sigma = Vec::with_capacity(bins);
    for k in 0..bins {
        // Particles expected in the annulus: its share of the cone's solid angle.
        let theta = |r: f64| (r / h).atan();
        let (a, b) = (theta(k as f64 * width), theta((k + 1) as f64 * width));
        let expected = n * (a.cos() - b.cos()) / (1.0 - cos_c);
        let s = model[k] / expected.sqrt();
        chi2 += ((sum[k] - model[k]) / s).powi(2);
        sigma.push(s / count[k] as f64);
    }
    let mean = |x: &[f64]| x.iter().zip(&count).map(|(s, &c)| s / c as f64).collect::<Vec<_>>();
    ConeLaw {
        height: h,
        half_angle: half,
        radii: (0..bins).map(|k| (k as f64 + 0.5) * width).collect(),
        simulated: mean(&sum),
        closed_form: mean(&model),
        sigma,
        chi2,
        emitted: m.emitted.count,
        stuck: floor.tally.stuck.count,
        volumes: (m.emitted.volume, v),
    }
}

/// The scene of [`cone_law`]: a point nozzle `h` m above a `size` m floor of `cols²` cells,
/// spraying a cone of `half_deg` with direction law `dir` at `rate` particles/s for `spray` s.
fn cone_scene(dir: &str, h: f64, half_deg: f64, size: f64, cols: usize, rate: f64, spray: f64) -> Scenario {
    scenario(
        &format!(
            r#"
            [simulation]
            duration = 0.2
            gravity = [0.0, 0.0, 0.0]
            [process.impact]
            rebound_model = "never"
            [emitter]
            shape = "point"
            direction = "{dir}"
            cone_angle = {cone}
            speed = [50.0, 50.0]
            spawn_rate = {rate}
            # Spray for 0.15 s; by 0.2 s everything has landed.
            [[nozzle.waypoints]]
            time = 0.0
            position = [0.0, 0.0, {h}]
            axis = [0.0, 0.0, -1.0]
            [[nozzle.waypoints]]
            time = {spray}
            position = [0.0, 0.0, {h}]
            axis = [0.0, 0.0, -1.0]
            spray = false
            {floor}
            "#,
            cone = 2.0 * half_deg,
            // Each particle in the cell it strikes: the closed form is the density per cell.
            floor = floor()
                .substrate()
                .at([0.0, 0.0, 0.0])
                .size(size, size)
                .resolution(cols as u32, cols as u32)
                .splat_radius(0.0),
        ),
        "cone",
    )
}

/// A sampled direction law against its density.
#[derive(Clone, Debug)]
pub struct DirectionHistogram {
    /// Bin edges of s = θ / θ_half.
    pub edges: Vec<f64>,
    /// Draws per bin.
    pub counts: Vec<u64>,
    /// Expected draws per bin from the density.
    pub expected: Vec<f64>,
    /// χ² over the bins.
    pub chi2: f64,
}

/// Draws `n` emission directions from a cone of half-angle `half` (rad) with `direction` and
/// compares the histogram of θ / θ_half (20 bins) with `bin_probability(a, b)`, the law's
/// probability of `[a, b)`.
pub fn direction_histogram(
    direction: Direction,
    half: f64,
    n: u64,
    bin_probability: impl Fn(f64, f64) -> f64,
) -> DirectionHistogram {
    const BINS: usize = 20;
    let e = Emitter {
        aperture: Aperture::Point,
        direction,
        cone_half_angle: half,
        speed: [1.0, 1.0],
        spawn_rate: 1.0,
        particle_volume: 1.0,
        droplets: None,
    };
    let frame = NozzleFrame::new(DVec3::ZERO, DVec3::Z, 0.0);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let mut counts = vec![0u64; BINS];
    for _ in 0..n {
        let (_, v) = e.sample(&frame, &mut rng);
        let s = v.z.clamp(-1.0, 1.0).acos() / half;
        counts[((s * BINS as f64) as usize).min(BINS - 1)] += 1;
    }
    let edges: Vec<f64> = (0..=BINS).map(|i| i as f64 / BINS as f64).collect();
    let expected: Vec<f64> = edges.windows(2).map(|w| n as f64 * bin_probability(w[0], w[1])).collect();
    let chi2 = counts.iter().zip(&expected).map(|(&c, &x)| (c as f64 - x).powi(2) / x).sum();
    DirectionHistogram { edges, counts, expected, chi2 }
}

/// Probability of `[a, b)` under N(μ, σ) truncated to `[0, 1]`.
pub fn truncated_normal_bin(mu: f64, sigma: f64) -> impl Fn(f64, f64) -> f64 {
    move |a, b| {
        let mass = normal_cdf((1.0 - mu) / sigma) - normal_cdf(-mu / sigma);
        (normal_cdf((b - mu) / sigma) - normal_cdf((a - mu) / sigma)) / mass
    }
}

/// Probability of `[a, b)` of θ/θ_half when directions are uniform over the cone's solid angle
/// of half-angle `half` (rad): (cos aθ − cos bθ) / (1 − cos θ).
pub fn solid_angle_bin(half: f64) -> impl Fn(f64, f64) -> f64 {
    move |a, b| ((a * half).cos() - (b * half).cos()) / (1.0 - half.cos())
}

/// A horizontal shot at 7 m/s from 1.2 m onto a floor: where it lands, with step `dt` (s).
pub fn landing_x(dt: f64, integrator: Integrator) -> f64 {
    let name = integrator_word(integrator);
    let sc = scenario(
        &format!(
            r#"
            [simulation]
            dt = {dt}
            duration = {dt}
            integrator = "{name}"
            [emitter]
            shape = "point"
            cone_angle = 0.0
            speed = [7.0, 7.0]
            spawn_rate = {rate}
            [process.impact]
            rebound_model = "never"
            # One particle: spraying during the first step only.
            [[nozzle.waypoints]]
            time = 0.0
            position = [0.0, 0.0, 1.2]
            axis = [1.0, 0.0, 0.0]
            [[nozzle.waypoints]]
            time = {half}
            position = [0.0, 0.0, 1.2]
            axis = [1.0, 0.0, 0.0]
            spray = false
            {floor}
            "#,
            rate = 1.0 / dt,
            half = dt / 2.0,
            // 2 m wide (y), 10 m along its up direction (x), from 0 to 10 m in front.
            floor = floor().substrate().at([5.0, 0.0, 0.0]).size(2.0, 10.0).resolution(8, 8),
        ),
        "shot",
    );
    let mut sim = sc.build().unwrap_or_else(|e| panic!("built-in validation scene: {e}"));
    sim.step(); // emits the one particle
    while sim.swarm().alive() > 0 {
        sim.step();
    }
    assert_eq!(sim.targets()[0].tally.stuck.count, 1, "the shot must land on the floor");
    // The particle's last position is where it stuck.
    sim.swarm().particles[0].anchor.x
}

/// Closed form of [`landing_x`]: x = v √(2h/g), m.
pub fn landing_x_closed_form() -> f64 {
    7.0 * (2.0 * 1.2 / 9.81_f64).sqrt()
}

/// The shotcrete field curve (the preset's polynomial law), evaluated independently of the
/// engine: p_r(θ) = 0.10 + 2.4 (θ/90°)³, clamped to `[0, 1]` (θ in degrees from the normal).
pub fn shotcrete_rebound_probability(theta_deg: f64) -> f64 {
    let x = theta_deg / 90.0;
    let c = SHOTCRETE_REBOUND_POLYNOMIAL;
    (c[0] + c[1] * x + c[2] * x * x + c[3] * x.powi(3)).clamp(0.0, 1.0)
}

/// Rebound fraction on a face tilted by `theta_deg`, sprayed straight down.
#[derive(Clone, Copy, Debug)]
pub struct ReboundFraction {
    /// Impact angle from the normal, degrees.
    pub theta_deg: f64,
    /// Material factor α.
    pub alpha: f64,
    /// Measured share that rebounds from its first impact.
    pub measured: f64,
    /// α · p_r(θ).
    pub expected: f64,
    /// Particles that hit.
    pub n: u64,
    /// The run's metrics (for conservation).
    pub conserved: bool,
}

/// A point jet of `particles` over 0.2 s, straight down onto a 0.5 m shotcrete plate tilted by
/// `theta_deg` from horizontal, with material factor `alpha`; `impact` is TOML added to
/// `[process.impact]` (a `rebound_model`, say). Gravity acts along the flight path, so every
/// impact happens at exactly `theta_deg` from the plate's normal. The plate's heightfield is a
/// single cell: the layer then grows as a flat slab, where a finer field would grow a ridge
/// under the pencil jet whose flanks change the angle of later impacts.
pub fn tilted_plate(theta_deg: f64, alpha: f64, particles: f64, seed: u64, impact: &str) -> Scenario {
    let t = theta_deg.to_radians();
    scenario(
        &format!(
            r#"
            [simulation]
            duration = 0.2
            seed = {seed}
            [process]
            preset = "shotcrete"
            [process.impact]
            alpha = {alpha}
            {impact}
            [emitter]
            shape = "point"
            cone_angle = 0.0
            spawn_rate = {rate}
            [nozzle]
            position = [0.0, 0.0, 0.3]
            axis = [0.0, 0.0, -1.0]
            [[target]]
            name = "plate"
            center = [0.0, 0.0, 0.0]
            normal = [{}, 0.0, {}]
            up = [0.0, 1.0, 0.0]
            size = [0.5, 0.5]
            resolution = [1, 1]
            "#,
            t.sin(),
            t.cos(),
            rate = particles / 0.2,
        ),
        "tilted plate",
    )
}

/// A straight-down jet of `particles` onto a shotcrete plate tilted by `theta_deg`, with the
/// polynomial rebound law: gravity acts along the flight path, so every impact happens at
/// exactly that angle. Runs with the same `seed` share their random numbers, so their errors
/// are correlated.
pub fn rebound_fraction(
    theta_deg: f64,
    alpha: f64,
    particles: f64,
    seed: u64,
    threads: usize,
) -> ReboundFraction {
    // The field curve itself: the preset's capture law reads the layer, which this check does
    // not build.
    let sc = tilted_plate(theta_deg, alpha, particles, seed, r#"rebound_model = "polynomial""#);
    let m = run(&sc, threads).metrics();
    ReboundFraction {
        theta_deg,
        alpha,
        // What bounces at the first impact: a rebound may land on the plate again.
        measured: m.bounce_ratio.unwrap_or(f64::NAN),
        expected: (alpha * shotcrete_rebound_probability(theta_deg)).clamp(0.0, 1.0),
        n: m.emitted.count,
        conserved: conserved(&m),
    }
}

/// Every emitted particle is in exactly one fate, by count exactly and by volume to rounding.
pub fn conserved(m: &Metrics) -> bool {
    let total = m.fates.total();
    total.count == m.emitted.count && (total.volume - m.emitted.volume).abs() <= 1e-12 * m.emitted.volume
}

/// One forced rebound at a time through the impact model.
#[derive(Clone, Debug)]
pub struct Restitution {
    /// Restitution factor set.
    pub restitution: f64,
    /// Mean rebound speed / impact speed measured.
    pub speed_ratio: f64,
    /// Histogram of u = (1 − cos ψ) / (1 − cos ψ_max) over 20 bins (uniform when the scatter
    /// is uniform over its cone), ψ the angle from the specular direction.
    pub scatter_counts: Vec<u64>,
    /// χ² of that histogram against uniform.
    pub scatter_chi2: f64,
    /// Largest ψ seen, rad.
    pub max_scatter: f64,
}

/// `n` forced rebounds at normal incidence with `restitution` and a scatter cone of half-angle
/// `scatter` (rad).
pub fn restitution(restitution: f64, scatter: f64, n: u64) -> Restitution {
    const BINS: usize = 20;
    let model = ImpactModel {
        alpha: 1.0,
        rebound: Arc::new(AlwaysRebound),
        restitution,
        scatter,
        rest_speed: 0.0,
        rest_max_slope: 0.0,
        cushion_radius: 0.0,
    };
    // Normal incidence: the specular direction is the normal and the cone stays off the surface.
    let (normal, v) = (DVec3::Z, DVec3::new(0.0, 0.0, -10.0));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let mut counts = vec![0u64; BINS];
    let (mut speed, mut max_scatter) = (0.0, 0.0_f64);
    for _ in 0..n {
        let Outcome::Rebound(out) = model.resolve(&ImpactModel::site(v, normal, None, 0.0, false), &mut rng)
        else {
            continue;
        };
        speed += out.length();
        let cos = out.normalize().z.clamp(-1.0, 1.0);
        max_scatter = max_scatter.max(cos.acos());
        let u = (1.0 - cos) / (1.0 - scatter.cos());
        counts[((u * BINS as f64) as usize).min(BINS - 1)] += 1;
    }
    let expected = n as f64 / BINS as f64;
    let scatter_chi2 = counts.iter().map(|&c| (c as f64 - expected).powi(2) / expected).sum();
    Restitution {
        restitution,
        speed_ratio: speed / n as f64 / v.length(),
        scatter_counts: counts,
        scatter_chi2,
        max_scatter,
    }
}

/// Material accounting of one run.
#[derive(Clone, Debug)]
pub struct Balance {
    /// Name of the scene whose volume balance this is.
    pub name: String,
    /// Emitted particles.
    pub emitted: u64,
    /// Sum of the particles over the fates.
    pub in_fates: u64,
    /// |Σ fate volumes − emitted volume| / emitted volume.
    pub fate_volume_error: f64,
    /// Residual of the volume balance (stuck + fallen + lost + in flight against emitted, with
    /// material released by failures followed to its own fate), relative to emitted.
    pub balance_residual: f64,
    /// Cohesive failure events.
    pub failures: usize,
    /// Volume released by failures, m³.
    pub released: f64,
}

/// Runs `sc` and accounts for its material.
pub fn balance(name: &str, sc: &Scenario, threads: usize) -> Balance {
    let m = run(sc, threads).metrics();
    let total = m.fates.total();
    Balance {
        name: name.to_string(),
        emitted: m.emitted.count,
        in_fates: total.count,
        fate_volume_error: (total.volume - m.emitted.volume).abs() / m.emitted.volume.max(1e-300),
        balance_residual: m.volume_balance.residual.abs() / m.volume_balance.emitted.max(1e-300),
        failures: m.failures.events.len(),
        released: m.failures.events.iter().map(|e| e.volume).sum(),
    }
}

/// A preset sprayed at a 1.5 m panel over a collector floor for `duration` s; `extra` is TOML
/// appended to the scene (obstacles, say).
pub fn panel_scene(preset: &str, duration: f64, extra: &str) -> Scenario {
    scenario(
        &format!(
            r#"
            [simulation]
            duration = {duration}
            [process]
            preset = "{preset}"
            [nozzle]
            position = [-0.3, 0.0, 1.0]
            axis = [1.0, 0.0, 0.0]
            {panel}{floor}
            {extra}
            "#,
            panel = wall().named("panel").size(1.5, 1.5).resolution(256, 256),
            floor = floor().at([-1.0, 0.0, 0.0]).size(4.0, 2.0).resolution(64, 64),
        ),
        preset,
    )
}

/// A 0.5 m × 0.5 m shotcrete face (`normal`, `up`, `center`) sprayed evenly to its edges by a
/// 0.7 m × 0.7 m rectangular emitter 0.2 m in front of it, so that about half of `flow` (m³/s)
/// lands on it, at `spawn_rate` particles/s for `duration` s, with a collector floor below and
/// cohesion analysed every `interval` s.
pub fn sprayed_face(
    normal: [f64; 3],
    up: [f64; 3],
    center: [f64; 3],
    flow: f64,
    duration: f64,
    interval: f64,
    spawn_rate: f64,
) -> Scenario {
    let n = DVec3::from_array(normal);
    let nozzle = DVec3::from_array(center) + n * 0.2;
    scenario(
        &format!(
            r#"
            [simulation]
            duration = {duration}
            [process]
            preset = "shotcrete"
            flow_rate = {flow}
            [process.impact]
            rebound_model = "never"
            # Failure in isolation: slump would cap a wall at τ_y/(ρ g), below its shear limit.
            [process.slump]
            interval = 0.0
            # Weak cohesion: the few cells that particle noise keeps under the threshold must not
            # hold the whole layer, so that failure follows the adhesive thresholds.
            [process.cohesion]
            interval = {interval}
            cohesion = 20.0
            [emitter]
            shape = "rectangle"
            width = 0.7
            height = 0.7
            cone_angle = 0.0
            spawn_rate = {spawn_rate}
            speed = [10.0, 10.0]
            [nozzle]
            position = {nozzle:?}
            axis = {axis:?}
            [[target]]
            name = "face"
            center = {center:?}
            normal = {normal:?}
            up = {up:?}
            size = [0.5, 0.5]
            resolution = [50, 50]
            splat_radius = 0.02
            {floor}
            [domain]
            min = [-3.0, -3.0, -2.0]
            max = [3.0, 3.0, 3.0]
            "#,
            nozzle = nozzle.to_array(),
            axis = (-n).to_array(),
            floor = floor().at([0.0, 0.0, -1.0]).size(4.0, 4.0).resolution(40, 40),
        ),
        "sprayed face",
    )
}

/// A ceiling sprayed upwards (10 mm/s on the face) until the layer fails in pull-off.
pub fn failing_ceiling(duration: f64) -> Scenario {
    sprayed_face([0.0, 0.0, -1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0], 4.9e-3, duration, 0.1, 20000.0)
}
