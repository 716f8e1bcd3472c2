//! The documented reference scene for performance measurements, and a timer over whole runs.
//!
//! Reference scene: a 2 m × 2 m wall target at 1 m standoff with a 1024 × 1024 heightfield, a
//! collector floor, a reinforcement mesh of 13 horizontal and 13 vertical bars (8 mm radius,
//! 150 mm spacing, 50 mm in front of the wall), the shotcrete preset, a static nozzle pointed at
//! the wall's centre, Δt = 1 ms (all adjustable through [`ReferenceScene`]).

use crate::integrator::Integrator;
use crate::{Scenario, Simulation};
use std::fmt::Write;
use std::time::Instant;

/// Knobs of the reference scene; [`ReferenceScene::default`] is the documented scene.
#[derive(Clone, Debug)]
pub struct ReferenceScene {
    /// Wall heightfield cells per side.
    pub resolution: u32,
    /// Each of the 26 bars is split into this many collinear pieces (1: 26 bars; 20: 520), so
    /// that the geometry stays the same while the primitive count grows.
    pub pieces_per_bar: usize,
    /// Particles per second.
    pub spawn_rate: f64,
    /// Simulated time, s.
    pub duration: f64,
    /// Integrator.
    pub integrator: Integrator,
    /// Time step, s.
    pub dt: f64,
}

impl Default for ReferenceScene {
    fn default() -> Self {
        ReferenceScene {
            resolution: 1024,
            pieces_per_bar: 1,
            spawn_rate: 1e4,
            duration: 1.0,
            integrator: Integrator::Euler,
            dt: 1e-3,
        }
    }
}

impl ReferenceScene {
    /// The scene as a scenario; an error names the knob that makes it invalid (a spawn rate
    /// or duration that is not a positive number, say).
    pub fn scenario(&self) -> Result<Scenario, crate::scenario::ScenarioError> {
        let mut t = format!(
            r#"
            [simulation]
            dt = 0.001
            duration = {duration}
            [process]
            preset = "shotcrete"
            max_lifetime = 3.0
            [emitter]
            spawn_rate = {rate}
            [nozzle]
            position = [-1.0, 0.0, 1.0]
            axis = [1.0, 0.0, 0.0]
            [[target]]
            name = "wall"
            center = [0.0, 0.0, 1.0]
            normal = [-1.0, 0.0, 0.0]
            up = [0.0, 0.0, 1.0]
            size = [2.0, 2.0]
            resolution = [{res}, {res}]
            [[target]]
            name = "floor"
            role = "collector"
            center = [-1.5, 0.0, 0.0]
            normal = [0.0, 0.0, 1.0]
            up = [1.0, 0.0, 0.0]
            size = [4.0, 3.0]
            resolution = [400, 300]
            [domain]
            min = [-3.0, -2.5, -0.5]
            max = [0.5, 2.5, 3.0]
            "#,
            duration = self.duration,
            rate = self.spawn_rate,
            res = self.resolution,
        );
        let n = self.pieces_per_bar.max(1);
        let radius = 0.008;
        // Vertical bars touch the wall's 50 mm plane; horizontal ones lie just in front of them.
        for k in -6..=6 {
            let offset = 0.15 * f64::from(k);
            for p in 0..n {
                let (a, b) = (2.0 * p as f64 / n as f64, 2.0 * (p + 1) as f64 / n as f64);
                let _ = write!(
                    t,
                    "[[obstacle]]\nname = \"v{k}_{p}\"\nshape = \"cylinder\"\nstart = [-0.05, {offset}, {a}]\nend = [-0.05, {offset}, {b}]\nradius = {radius}\n\
                     [[obstacle]]\nname = \"h{k}_{p}\"\nshape = \"cylinder\"\nstart = [-0.067, {y0}, {z}]\nend = [-0.067, {y1}, {z}]\nradius = {radius}\n",
                    z = 1.0 + offset,
                    y0 = a - 1.0,
                    y1 = b - 1.0,
                );
            }
        }
        let mut sc = Scenario::from_toml(&t, "reference scene")?;
        sc.simulation.integrator = self.integrator;
        sc.simulation.dt = self.dt;
        Ok(sc)
    }
}

/// The reference scene with a 60 s robot raster over the wall at `spawn_rate` particles per
/// second, cohesion analysed every 0.5 s: the optimisation-loop workload.
pub fn raster_pass(spawn_rate: f64) -> Result<Scenario, crate::scenario::ScenarioError> {
    let mut sc = ReferenceScene { spawn_rate, duration: 60.0, ..ReferenceScene::default() }.scenario()?;
    sc.nozzle.raster = Some(crate::scenario::RasterParams {
        target: "wall".into(),
        size: Some([1.6, 1.5]),
        standoff: 1.0,
        speed: 0.5,
        step_over: 0.1,
        lead: 0.1,
        ..Default::default()
    });
    sc.process.cohesion.interval = 0.5;
    Ok(sc)
}

/// Mean time of one cohesion analysis of a `side × side` heightfield carrying a shotcrete
/// layer (a noisy mound, over-loaded at its crest), s.
pub fn time_cohesion(side: usize, repeats: usize) -> f64 {
    use crate::cohesion::{Strength, analyse};
    let mut f = crate::heightfield::HeightField::new(2.0, 2.0, side, side, 0.0);
    let mut noise = 0x2545_F491_4F6C_DD1D_u64;
    for c in 0..(side * side) as u32 {
        let (u, v) = f.cell_center(c);
        noise ^= noise << 13;
        noise ^= noise >> 7;
        noise ^= noise << 17;
        let jitter = (noise >> 11) as f64 / (1u64 << 53) as f64;
        let t = 0.3 * (-(u * u + v * v) / 0.18).exp() * (0.9 + 0.2 * jitter);
        f.deposit(c, t * f.cell_area());
    }
    let s = Strength { tensile: 1500.0, shear: 5000.0, cohesion: 2000.0 };
    let start = Instant::now();
    let mut regions = 0;
    for _ in 0..repeats {
        regions += analyse(&f, glam::DVec3::NEG_X, 2300.0, crate::integrator::GRAVITY, &s).regions.len();
    }
    assert!(regions > 0, "the bench layer must be over-loaded somewhere");
    start.elapsed().as_secs_f64() / repeats as f64
}

/// What one timed run measured.
#[derive(Clone, Debug)]
pub struct Measurement {
    /// Wall-clock time of the run, s.
    pub wall: f64,
    /// Simulated time, s.
    pub sim_time: f64,
    /// Particle-steps: Σ over steps of the particles in flight at that step.
    pub particle_steps: u64,
    /// Particles that reached a final fate (stuck, left, expired).
    pub retired: u64,
    /// Peak resident memory of the process so far, bytes (Linux; 0 elsewhere).
    pub peak_rss: u64,
}

impl Measurement {
    /// Particle-steps per wall-clock second.
    pub fn particle_steps_per_second(&self) -> f64 {
        self.particle_steps as f64 / self.wall
    }

    /// Particles brought from emission to a final fate per wall-clock second.
    pub fn particles_per_second(&self) -> f64 {
        self.retired as f64 / self.wall
    }

    /// Simulated seconds per wall-clock second.
    pub fn real_time_factor(&self) -> f64 {
        self.sim_time / self.wall
    }
}

/// Runs `scenario` to the end on `threads` threads (0: all cores) and times it.
pub fn measure(scenario: &Scenario, threads: usize) -> Result<Measurement, crate::SetupError> {
    let mut sim = Simulation::new(scenario)?;
    sim.set_threads(threads)?;
    let start = Instant::now();
    sim.run(|_| {});
    let wall = start.elapsed().as_secs_f64();
    let m = sim.metrics();
    Ok(Measurement {
        wall,
        sim_time: sim.time(),
        particle_steps: sim.particle_steps(),
        retired: m.emitted.count - m.fates.in_flight.count,
        peak_rss: peak_rss(),
    })
}

/// Runs `scenario` `repeats` times (at least once) after one untimed warm-up run of a tenth
/// of its duration, and returns the run of median wall-clock time: a single run on a shared
/// machine is easily 20 % off either way.
pub fn measure_median(
    scenario: &Scenario,
    threads: usize,
    repeats: usize,
) -> Result<Measurement, crate::SetupError> {
    let mut warm = scenario.clone();
    warm.simulation.duration = (0.1 * warm.simulation.duration).max(warm.simulation.dt);
    measure(&warm, threads)?;
    let mut runs = (0..repeats.max(1)).map(|_| measure(scenario, threads)).collect::<Result<Vec<_>, _>>()?;
    runs.sort_by(|a, b| a.wall.total_cmp(&b.wall));
    Ok(runs.swap_remove(runs.len() / 2))
}

/// Peak resident set size of this process, bytes, from `/proc/self/status` (0 if unavailable).
pub fn peak_rss() -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| {
                l.split_whitespace().nth(1).and_then(|kb| kb.parse::<u64>().ok()).map(|kb| kb * 1024)
            })
        })
        .unwrap_or(0)
}
