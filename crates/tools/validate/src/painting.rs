//! Painting with droplets in the gun's air: the experiments behind docs/painting.md and the
//! "Droplets in the gun's air" section of the validation report.
//!
//! - [`stokes_flight`]: a droplet sprayed into still air (the Galilean twin of one at rest in
//!   a uniform cross-flow) against the closed form of Stokes drag under gravity;
//!   [`drag_law_error`]: the Schiller–Naumann law's step error against a fine integration;
//! - [`impaction`]: droplets entering a stagnation layer with the air, captured or carried
//!   past, against the critical Stokes number 1/4 of a linear stagnation flow (Taylor 1940;
//!   Langmuir & Blodgett 1946) and the local-strain bound derived here;
//! - [`transfer_efficiency`]: each gun preset on the flat-panel test
//!   ([`spraysim_scenario::scenes::painted_panel`]), against its published range, and how it
//!   moves with droplet size, air speed and standoff.

use glam::DVec3;
use spraysim_engine::config::SimulationConfig;
use spraysim_engine::emission::{Aperture, Direction, NozzlePath, SizeDistribution};
use spraysim_engine::motion::{AirFlow, DragLaw, Droplet, GRAVITY, Integrator};
use spraysim_engine::{Metrics, Simulation};
use spraysim_scenario::{Gun, Scenario, scenes};

/// Air at 20 °C: dynamic viscosity, Pa·s.
const AIR_VISCOSITY: f64 = 1.81e-5;

/// A round jet of `speed` (m/s) from a `outlet_diameter` (m) outlet in air at 20 °C, with
/// `drag_law`, and no booth to carry droplets off: the air of these experiments.
fn air(speed: f64, outlet_diameter: f64, drag_law: DragLaw) -> AirFlow {
    AirFlow {
        speed,
        outlet_diameter,
        spread: [0.094, 0.094],
        stagnation_layer: 0.14,
        viscosity: AIR_VISCOSITY,
        density: 1.2,
        drag_law,
        booth_speed: 0.0,
    }
}

/// Paint's density in these experiments, kg/m³ (the painting preset's).
const PAINT_DENSITY: f64 = 1200.0;

/// A droplet's flight through still air, simulated and in closed form.
#[derive(Clone, Debug)]
pub struct StokesFlight {
    /// Times since emission, s.
    pub times: Vec<f64>,
    /// Simulated positions `(x, z)` (m) relative to the nozzle.
    pub simulated: Vec<(f64, f64)>,
    /// The closed form's.
    pub closed_form: Vec<(f64, f64)>,
    /// Largest distance between the two, m.
    pub max_error: f64,
    /// The droplet's Stokes relaxation time, s.
    pub tau: f64,
}

/// A droplet of `diameter` (m) sprayed horizontally at `speed` (m/s) into still air by the
/// engine, stepped at `dt` (s) for `steps` steps under Stokes drag and gravity, against
/// x(t) = v₀ τ (1 − e^{−t/τ}), z(t) = −g τ t + g τ² (1 − e^{−t/τ}). In a frame moving with a
/// uniform cross-flow this is a droplet released into that flow: drag depends only on the
/// velocity relative to the air.
pub fn stokes_flight(diameter: f64, speed: f64, dt: f64, steps: u64) -> StokesFlight {
    let mut c = SimulationConfig::example_wall(dt * steps as f64);
    c.dt = dt;
    c.layer_epoch = 1;
    c.material.density = PAINT_DENSITY;
    c.material.max_lifetime = 10.0;
    c.motion = spraysim_engine::motion::Motion {
        gravity: GRAVITY,
        drag: 0.0,
        integrator: Integrator::Euler,
        air: Some(air(0.0, 0.005, DragLaw::Stokes)),
    };
    let start = DVec3::new(-1.5, 0.0, 1.5);
    c.nozzle = NozzlePath::fixed(start, DVec3::X, 0.0);
    c.emitter.aperture = Aperture::Point;
    c.emitter.direction = Direction::UniformPolar;
    c.emitter.cone_half_angle = 0.0;
    c.emitter.speed = [speed, speed];
    // One particle, born at the first step's start.
    c.emitter.spawn_rate = 1.0 / dt;
    c.duration = dt * steps as f64;
    c.emitter.particle_volume = 1e-12;
    c.emitter.droplets = Some(SizeDistribution::Fixed { diameter });
    c.domain.min = DVec3::new(-2.0, -1.0, -50.0);
    c.targets.clear();
    let tau = PAINT_DENSITY * diameter * diameter / (18.0 * AIR_VISCOSITY);
    let mut sim = Simulation::new(c).unwrap_or_else(|e| panic!("the still-air scene is refused: {e}"));
    let g = GRAVITY.length();
    let mut flight = StokesFlight {
        times: Vec::new(),
        simulated: Vec::new(),
        closed_form: Vec::new(),
        max_error: 0.0,
        tau,
    };
    for _ in 0..steps {
        sim.step();
        // The first particle is the oldest in flight.
        let Some((x, _, age)) = sim.in_flight().max_by(|a, b| a.2.total_cmp(&b.2)) else { break };
        let decay = -(-age / tau).exp_m1();
        let closed = (speed * tau * decay, -g * tau * age + g * tau * tau * decay);
        let sim_xz = (x.x - start.x, x.z - start.z);
        flight.max_error = flight.max_error.max((sim_xz.0 - closed.0).hypot(sim_xz.1 - closed.1));
        flight.times.push(age);
        flight.simulated.push(sim_xz);
        flight.closed_form.push(closed);
    }
    flight
}

/// The Schiller–Naumann drag's error over a flight: a droplet of `diameter` (m) at `speed`
/// (m/s) through still air without gravity, advanced by the engine's held-drag step of `dt`
/// (s) for `duration` s, against a fourth-order Runge–Kutta integration of
/// dv/dt = −v/τ_f(|v|) at a step 1000 times finer. Returns the distance flown (m) and the
/// error in it (m).
pub fn drag_law_error(diameter: f64, speed: f64, dt: f64, duration: f64) -> (f64, f64) {
    let air = air(0.0, 0.005, DragLaw::SchillerNaumann);
    let d = air.droplet(diameter, PAINT_DENSITY);
    let steps = (duration / dt).round() as u64;
    let (mut x, mut v) = (DVec3::ZERO, DVec3::X * speed);
    for _ in 0..steps {
        (x, v) = air.step(None, &d, x, v, DVec3::ZERO, dt);
    }
    let accel = |v: f64| -v / air.relaxation_time(&d, DVec3::X * v, DVec3::ZERO);
    let (mut xf, mut vf) = (0.0, speed);
    let h = dt / 1000.0;
    for _ in 0..steps * 1000 {
        let (k1x, k1v) = (vf, accel(vf));
        let (k2x, k2v) = (vf + 0.5 * h * k1v, accel(vf + 0.5 * h * k1v));
        let (k3x, k3v) = (vf + 0.5 * h * k2v, accel(vf + 0.5 * h * k2v));
        let (k4x, k4v) = (vf + h * k3v, accel(vf + h * k3v));
        xf += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        vf += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
    (xf, (x.x - xf).abs())
}

/// Droplets carried into a stagnation layer, captured or not, at one Stokes number.
#[derive(Clone, Copy, Debug)]
pub struct Impaction {
    /// Stokes number τ W_c/δ: the relaxation time over the layer's strain time at the wall.
    pub stokes: f64,
    /// Share of the jet's flux of droplets that reaches the wall.
    pub efficiency: f64,
    /// Whether the droplet on the jet's axis reaches it.
    pub on_axis: bool,
}

/// The capture efficiency of the local-strain bound: a droplet at an offset where the wall
/// strain is W(ρ)/δ is captured if τ W(ρ)/δ > 1/4; over a Gaussian jet's flux that is the
/// share 1 − 1/(4 Stk) (0 below Stk = 1/4). Droplets swept outwards by the wall jet before they
/// land fall short of it.
pub fn local_strain_bound(stokes: f64) -> f64 {
    (1.0 - 0.25 / stokes).max(0.0)
}

/// The impaction of droplets of one size onto a flat wall 0.2 m from a round jet (U₀ = 100
/// m/s, d₀ = 6 mm, spread 0.094, δ = 0.14 H, Stokes drag, no gravity) at each Stokes number of
/// `stokes`: `droplets` droplets enter the layer with the air's velocity, spread over the jet
/// by its flux (their radii at the quantiles of the Gaussian's flux), and each is stepped at
/// 0.1 ms (with the engine's substeps) until it reaches the wall, leaves the layer or 0.2 s
/// pass. The droplet's diameter is chosen for each Stokes number.
pub fn impaction(stokes: &[f64], droplets: usize) -> Vec<Impaction> {
    let air = air(100.0, 0.006, DragLaw::Stokes);
    let (h_wall, across) = (0.2, [DVec3::Y, DVec3::Z]);
    let frame = air.frame(DVec3::ZERO, DVec3::X, across, Some((DVec3::X * h_wall, DVec3::NEG_X)));
    let wall = frame.wall.unwrap_or_else(|| panic!("the jet strikes the wall"));
    let b = 0.094 * (h_wall - wall.depth);
    stokes
        .iter()
        .map(|&stk| {
            let tau = stk / wall.strain;
            let diameter = (tau * 18.0 * AIR_VISCOSITY / PAINT_DENSITY).sqrt();
            let d = air.droplet(diameter, PAINT_DENSITY);
            let captured = |rho: f64| reaches_wall(&air, &frame, &d, h_wall - wall.depth, rho, h_wall);
            let hits = (0..droplets)
                .filter(|&i| {
                    let share = (i as f64 + 0.5) / droplets as f64;
                    captured(b * (-(-share).ln_1p() / std::f64::consts::LN_2).sqrt())
                })
                .count();
            Impaction { stokes: stk, efficiency: hits as f64 / droplets as f64, on_axis: captured(0.0) }
        })
        .collect()
}

/// Whether droplet `d`, entering the layer at distance `z` along the jet's axis and `rho` off it
/// with the air's velocity, reaches the wall at `h_wall`.
fn reaches_wall(
    air: &AirFlow,
    frame: &spraysim_engine::motion::JetFrame,
    d: &Droplet,
    z: f64,
    rho: f64,
    h_wall: f64,
) -> bool {
    let mut x = DVec3::new(z, rho, 0.0);
    let mut v = air.velocity(frame, x);
    let dt = 1e-4;
    for _ in 0..2000 {
        (x, v) = air.step(Some(frame), d, x, v, DVec3::ZERO, dt);
        if x.x >= h_wall {
            return true;
        }
        if x.x < z - 1e-3 || x.y.abs() > 0.1 {
            return false;
        }
    }
    false
}

/// One gun's transfer efficiency on the flat-panel test.
#[derive(Clone, Debug)]
pub struct PanelRun {
    /// The gun.
    pub gun: Gun,
    /// Transfer efficiency of each seed, 0–1.
    pub efficiencies: Vec<f64>,
    /// The last seed's metrics.
    pub metrics: Metrics,
}

impl PanelRun {
    /// The mean transfer efficiency over the seeds, 0–1.
    pub fn mean(&self) -> f64 {
        self.efficiencies.iter().sum::<f64>() / self.efficiencies.len().max(1) as f64
    }
}

/// Runs `scenario` on `threads` threads and returns its metrics.
pub fn run(scenario: &Scenario, threads: usize) -> Metrics {
    let mut sim =
        Simulation::new(scenario.config()).unwrap_or_else(|e| panic!("the panel scene is refused: {e}"));
    sim.set_threads(threads).unwrap_or_else(|e| panic!("{e}"));
    sim.run(|_| {});
    sim.metrics()
}

/// `gun`'s transfer efficiency on the flat-panel test at `spawn_rate` particles/s, for seeds
/// 1 to `seeds`, with `settings` (`(key, value)` overrides: a droplet size, an air speed, a
/// standoff) applied.
pub fn transfer_efficiency(
    gun: Gun,
    spawn_rate: f64,
    seeds: u64,
    settings: &[(&str, f64)],
    threads: usize,
) -> PanelRun {
    let mut efficiencies = Vec::new();
    let mut last = None;
    for seed in 1..=seeds {
        let mut sc = scenes::painted_panel(gun, spawn_rate, seed, "volume_solids = 0.4");
        for &(key, value) in settings {
            sc = sc.with(key, value).unwrap_or_else(|e| panic!("{key} = {value}: {e}"));
        }
        let m = run(&sc, threads);
        efficiencies.push(m.transfer_efficiency.unwrap_or(0.0));
        last = Some(m);
    }
    let metrics = last.unwrap_or_else(|| panic!("at least one seed"));
    PanelRun { gun, efficiencies, metrics }
}
