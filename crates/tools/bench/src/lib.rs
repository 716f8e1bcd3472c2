//! # spraysim-bench
//!
//! The documented reference scene for performance measurements, a timer over whole runs, and
//! the table of the reference scene's scaling variants that `spraysim bench` prints.
//!
//! Reference scene: a 2 m × 2 m wall target at 1 m standoff with a 1024 × 1024 heightfield, a
//! collector floor, a reinforcement mesh of 13 horizontal and 13 vertical bars (8 mm radius,
//! 150 mm spacing, 50 mm in front of the wall), the shotcrete preset, a static nozzle pointed at
//! the wall's centre, Δt = 1 ms (all adjustable through [`ReferenceScene`]).

use spraysim_engine::Simulation;
use spraysim_engine::deposit::RectangleSurface;
use spraysim_engine::motion::Integrator;
use spraysim_engine::pipeline::FlightStage;
use spraysim_scenario::scenes::{NOZZLE_AT_WALL, bar, floor, integrator_word, wall};
use spraysim_scenario::{Scenario, ScenarioError};
use std::sync::Arc;
use std::time::Instant;

pub mod baseline;
pub mod stage;

pub use spraysim_engine::SetupError;

/// Why a benchmark could not run.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    /// A setting is out of range.
    #[error("{0}")]
    Settings(String),
    /// A benchmark scene is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// A simulation could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The table could not be written.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

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
    /// How each step advances the particles (forward Euler in the documented scene).
    pub integrator: Integrator,
    /// Time step, s.
    pub dt: f64,
    /// Whether the rebar mesh stands in front of the wall.
    pub rebar: bool,
    /// Length of a layer epoch, s (`None`: the scenarios' default).
    pub layer_epoch: Option<f64>,
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
            rebar: true,
            layer_epoch: None,
        }
    }
}

impl ReferenceScene {
    /// Length of the scene's layer epoch, s.
    pub fn epoch(&self) -> f64 {
        self.layer_epoch.unwrap_or(spraysim_scenario::DEFAULT_LAYER_EPOCH)
    }

    /// The scene as a scenario; an error names the knob that makes it invalid (a spawn rate
    /// or duration that is not a positive number, say).
    pub fn scenario(&self) -> Result<Scenario, ScenarioError> {
        Scenario::from_toml(&self.toml(NOZZLE_AT_WALL), "reference scene")
    }

    /// The scene as TOML, with `nozzle` (TOML) as its nozzle.
    fn toml(&self, nozzle: &str) -> String {
        let integrator = integrator_word(self.integrator);
        let mut t = format!(
            r#"
            [simulation]
            dt = {dt}
            integrator = "{integrator}"
            duration = {duration}
            layer_epoch = {epoch}
            [process]
            preset = "shotcrete"
            max_lifetime = 3.0
            [emitter]
            spawn_rate = {rate}
            {wall}{floor}
            [domain]
            min = [-3.0, -2.5, -0.5]
            max = [0.5, 2.5, 3.0]
            "#,
            dt = self.dt,
            duration = self.duration,
            epoch = self.epoch(),
            rate = self.spawn_rate,
            wall = wall().resolution(self.resolution, self.resolution),
            floor = floor().resolution(400, 300),
        );
        t.push_str(nozzle);
        let n = if self.rebar { self.pieces_per_bar.max(1) } else { 0 };
        let radius = 0.008;
        // Vertical bars touch the wall's 50 mm plane; horizontal ones lie just in front of them.
        for k in -6..=6 {
            let offset = 0.15 * f64::from(k);
            for p in 0..n {
                let (a, b) = (2.0 * p as f64 / n as f64, 2.0 * (p + 1) as f64 / n as f64);
                let z = 1.0 + offset;
                t.push_str(&bar(&format!("v{k}_{p}"), [-0.05, offset, a], [-0.05, offset, b], radius));
                t.push_str(&bar(&format!("h{k}_{p}"), [-0.067, a - 1.0, z], [-0.067, b - 1.0, z], radius));
            }
        }
        t
    }
}

/// The reference scene with a 60 s robot raster over the wall at `spawn_rate` particles per
/// second, cohesion analysed every 0.5 s: the optimisation-loop workload.
pub fn raster_pass(spawn_rate: f64) -> Result<Scenario, ScenarioError> {
    let scene = ReferenceScene { spawn_rate, duration: 60.0, ..ReferenceScene::default() };
    let raster = "[nozzle.raster]\ntarget = \"wall\"\nsize = [1.6, 1.5]\nstandoff = 1.0\nspeed = 0.5\n\
                  step_over = 0.1\nlead = 0.1\n[process.cohesion]\ninterval = 0.5\n";
    Scenario::from_toml(&scene.toml(raster), "reference raster")
}

/// The reference scene with at least `count` particles in flight (fewer only if the run ends
/// first): emitted at 5·10⁷ particles/s, so that they are all still on their way to the wall,
/// for timing what draws or processes a full swarm.
pub fn in_flight(count: usize) -> Result<spraysim_engine::Simulation, BenchError> {
    let rate = 5e7;
    let duration = (2.0 * count as f64 / rate).max(1e-3);
    let scene = ReferenceScene { spawn_rate: rate, duration, ..ReferenceScene::default() };
    let mut sim = scene.scenario()?.build()?;
    while sim.swarm().alive() < count && !sim.is_finished() {
        sim.step();
    }
    Ok(sim)
}

/// Mean time of one cohesion analysis of a `side × side` heightfield carrying a shotcrete
/// layer (a noisy mound, over-loaded at its crest), s.
pub fn time_cohesion(side: usize, repeats: usize) -> f64 {
    use spraysim_engine::process::layer::{Strength, analyse};
    let face =
        spraysim_engine::collision::Face::new(glam::DVec3::Z, glam::DVec3::NEG_X, glam::DVec3::Z, [2.0, 2.0]);
    let mut r = RectangleSurface::new(face, side, side, 0.0);
    let f = &mut r.field;
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
        regions += analyse(&r, 2300.0, spraysim_engine::motion::GRAVITY, &s).regions.len();
    }
    assert!(regions > 0, "the bench layer must be over-loaded somewhere");
    start.elapsed().as_secs_f64() / repeats as f64
}

/// Particles per second brought to their final fate by the paper-equivalent implementation
/// (single-threaded C++: forward Euler, every obstacle tested at every step, no broad phase;
/// [`baseline`]) on the reference scene at 10⁶ particles/s for 0.5 s, recorded on the 2-core
/// development machine (built with `g++ -O3 -march=native`): the yardstick the "× paper
/// baseline" column divides by when the bench cannot build and time the implementation itself.
pub const PAPER_BASELINE_PARTICLES_PER_SECOND: f64 = 5.56e4;

/// Runs `count` short variants of the reference scene (0.2 s of spraying at its default rate,
/// each with its own seed), as an optimisation loop would: each is parsed, set up (reusing the
/// broad phase of the worker's previous variant, see [`Scenario::rebuild`]), run on one thread
/// and reduced to its metrics, and the variants share `threads` workers (0: all cores).
/// Returns variants per second of wall-clock time.
pub fn short_variants(count: usize, threads: usize) -> Result<f64, BenchError> {
    use rayon::prelude::*;
    let base = ReferenceScene { duration: 0.2, ..ReferenceScene::default() }.scenario()?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| SetupError::Threads { threads, message: e.to_string() })?;
    let start = Instant::now();
    let emitted: Result<u64, BenchError> = pool.install(|| {
        (0..count)
            .into_par_iter()
            // One simulation per task, set up afresh for each of its variants: the broad phase
            // is built once per task.
            .map_init(
                || None,
                |sim: &mut Option<Simulation>, i| {
                    let variant = base.with("simulation.seed", i as i64)?;
                    let sim = match sim {
                        Some(sim) => {
                            variant.rebuild(sim)?;
                            sim
                        }
                        None => {
                            let mut fresh = variant.build()?;
                            fresh.set_threads(1)?;
                            sim.insert(fresh)
                        }
                    };
                    sim.run(|_| {});
                    Ok(sim.metrics().emitted.count)
                },
            )
            .sum()
    });
    let wall = start.elapsed().as_secs_f64();
    if emitted? == 0 {
        return Err(BenchError::Settings("the short variants emitted nothing".into()));
    }
    Ok(count as f64 / wall)
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
    /// Particle updates: the particle-steps flown as full steps (an exact search for hits);
    /// the others coasted through open space.
    pub particle_updates: u64,
    /// Particles that reached a final fate (stuck, left, expired).
    pub retired: u64,
    /// Particles still in flight at the end.
    pub in_flight: u64,
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

    /// Share of the particle-steps actually worked (1 when every particle is stepped every
    /// step).
    pub fn worked_share(&self) -> f64 {
        self.particle_updates as f64 / self.particle_steps.max(1) as f64
    }

    /// Simulated seconds per wall-clock second.
    pub fn real_time_factor(&self) -> f64 {
        self.sim_time / self.wall
    }
}

/// Runs `scenario` to the end on `threads` threads (0: all cores) and times it.
pub fn measure(scenario: &Scenario, threads: usize) -> Result<Measurement, BenchError> {
    measure_on(scenario, threads, None)
}

/// [`measure`], the particles flown on `stage` (`None`: the engine's own flight).
pub fn measure_on(
    scenario: &Scenario,
    threads: usize,
    stage: Option<&Arc<dyn FlightStage>>,
) -> Result<Measurement, BenchError> {
    let mut sim = scenario.build()?;
    sim.set_threads(threads)?;
    sim.set_flight_stage(stage.cloned());
    let start = Instant::now();
    sim.run(|_| {});
    let wall = start.elapsed().as_secs_f64();
    let m = sim.metrics();
    Ok(Measurement {
        wall,
        sim_time: sim.time(),
        particle_steps: sim.particle_steps(),
        particle_updates: sim.particle_updates(),
        retired: m.emitted.count - m.fates.in_flight.count,
        in_flight: m.fates.in_flight.count,
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
) -> Result<Measurement, BenchError> {
    measure_median_on(scenario, threads, repeats, None)
}

/// [`measure_median`], the particles flown on `stage` (`None`: the engine's own flight).
pub fn measure_median_on(
    scenario: &Scenario,
    threads: usize,
    repeats: usize,
    stage: Option<&Arc<dyn FlightStage>>,
) -> Result<Measurement, BenchError> {
    median_run(scenario, (threads, repeats, stage), |m| m, |m| m.wall)
}

/// Runs `scenario` on `threads` threads and `stage` `repeats` times (at least once) after one
/// untimed warm-up of a tenth of its duration, passing each run, the warm-up too, to `each`,
/// and returns what `each` made of the run of median `wall` time (s). `each` may take what a run
/// leaves behind elsewhere (a stage's own timings); the warm-up's result is dropped.
pub fn median_run<T>(
    scenario: &Scenario,
    (threads, repeats, stage): (usize, usize, Option<&Arc<dyn FlightStage>>),
    mut each: impl FnMut(Measurement) -> T,
    wall: impl Fn(&T) -> f64,
) -> Result<T, BenchError> {
    let s = scenario.simulation();
    let warm = scenario.with("simulation.duration", (0.1 * s.duration).max(s.dt))?;
    each(measure_on(&warm, threads, stage)?);
    let runs = (0..repeats.max(1))
        .map(|_| measure_on(scenario, threads, stage).map(&mut each))
        .collect::<Result<Vec<_>, _>>()?;
    median_by(runs, wall).ok_or_else(|| BenchError::Settings("no timed run".into()))
}

/// The element of median `time` (s) of `runs` (the later of the middle two of an even count);
/// `None` for none.
pub fn median_by<T>(mut runs: Vec<T>, time: impl Fn(&T) -> f64) -> Option<T> {
    runs.sort_by(|a, b| time(a).total_cmp(&time(b)));
    let middle = runs.len() / 2;
    (!runs.is_empty()).then(|| runs.swap_remove(middle))
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

/// Wall time (s) of the first 10 s of the HVLP gun's flat-panel test at 10⁴ particles/s on
/// `threads` threads, with the gun's air and in still air (the same droplets, flying as the
/// paper's do), each the median of `repeats` runs after a warm-up: what the air model costs.
pub fn painting_cost(threads: usize, repeats: usize) -> Result<(f64, f64), BenchError> {
    let air = spraysim_scenario::scenes::painted_panel(spraysim_scenario::Gun::Hvlp, 1e4, 1, "")
        .with("simulation.duration", 10.0)?;
    let still = air.with("air.model", "none")?;
    let wall = |sc: &Scenario| -> Result<f64, BenchError> { Ok(measure_median(sc, threads, repeats)?.wall) };
    Ok((wall(&air)?, wall(&still)?))
}

/// What [`run_matrix`] runs.
#[derive(Clone, Debug, PartialEq)]
pub struct MatrixSettings {
    /// Particles emitted per second in the throughput runs.
    pub spawn_rate: f64,
    /// Simulated seconds per run.
    pub duration: f64,
    /// Worker thread counts (0: every core). The runs that do not vary it use the largest;
    /// with more than one, the reference scene and the raster are also timed on each (the
    /// scaling table).
    pub threads: Vec<usize>,
    /// Timed runs per row (after one untimed warm-up); the median is reported.
    pub repeats: usize,
    /// Short variants timed for the optimisation-loop figure.
    pub variants: usize,
    /// Whether to build and time the paper-equivalent implementation in this run (falling back
    /// to [`PAPER_BASELINE_PARTICLES_PER_SECOND`] where it cannot be built or run) rather than
    /// divide by that recorded figure.
    pub measure_baseline: bool,
}

impl MatrixSettings {
    /// Refuses a rate or duration that is not a positive number, before anything runs.
    pub(crate) fn check(&self) -> Result<(), BenchError> {
        if !(self.spawn_rate.is_finite() && self.spawn_rate > 0.0) {
            return Err(BenchError::Settings(format!(
                "--spawn-rate must be a positive number of particles/s, got {}",
                self.spawn_rate
            )));
        }
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return Err(BenchError::Settings(format!(
                "--duration must be a positive number of seconds, got {}",
                self.duration
            )));
        }
        Ok(())
    }

    /// The thread counts asked for, 0 replaced by this machine's cores.
    pub(crate) fn thread_counts(&self) -> Vec<usize> {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        let mut counts: Vec<usize> = self.threads.iter().map(|&t| if t == 0 { cores } else { t }).collect();
        if counts.is_empty() {
            counts.push(cores);
        }
        counts
    }
}

/// One row of the table: a name, a scene and a thread count.
type Row = (String, ReferenceScene, usize);

/// The reference scene and its scaling variants, on `all` threads unless named.
fn variants(m: &MatrixSettings, all: usize) -> Vec<Row> {
    let base = ReferenceScene { spawn_rate: m.spawn_rate, duration: m.duration, ..ReferenceScene::default() };
    let exact = ReferenceScene { integrator: Integrator::Exact, ..base.clone() };
    vec![
        (format!("reference, {all} threads"), base.clone(), all),
        ("reference, 1 thread".into(), base.clone(), 1),
        (
            "spawn rate ×10".into(),
            ReferenceScene { spawn_rate: m.spawn_rate * 10.0, duration: m.duration / 10.0, ..base.clone() },
            all,
        ),
        ("heightfield 256²".into(), ReferenceScene { resolution: 256, ..base.clone() }, all),
        ("heightfield 2048²".into(), ReferenceScene { resolution: 2048, ..base.clone() }, all),
        ("520 bars".into(), ReferenceScene { pieces_per_bar: 20, ..base.clone() }, all),
        (
            "layer epoch of one step".into(),
            ReferenceScene { layer_epoch: Some(base.dt), ..base.clone() },
            all,
        ),
        ("exact integrator".into(), exact.clone(), all),
        ("exact integrator, Δt = 10 ms".into(), ReferenceScene { dt: 0.01, ..exact }, all),
    ]
}

/// The paper-equivalent implementation's particles per second to fate on the throughput runs'
/// rate and duration: timed now (median of `m.repeats` runs) if asked and it can be built and
/// run, else the recorded figure. Writes a line to `out` saying which, and why.
pub(crate) fn paper_baseline(m: &MatrixSettings, out: &mut impl std::io::Write) -> Result<f64, BenchError> {
    let recorded = PAPER_BASELINE_PARTICLES_PER_SECOND;
    let fallback = format!(
        "the recorded {recorded:.3e} particles/s to fate (10⁶ particles/s for 0.5 s, on another day)"
    );
    if !m.measure_baseline {
        writeln!(out, "paper baseline: {fallback}, not timed in this run\n")?;
        return Ok(recorded);
    }
    let timed = baseline::Baseline::build()
        .and_then(|b| Ok((b.run_median(m.spawn_rate, m.duration, m.repeats)?, b.build)));
    match timed {
        Ok((run, build)) => {
            writeln!(
                out,
                "paper baseline: timed in this run (built with `{build}`, median of {} runs): {:.3e} particles/s to fate ({} of {} emitted in {:.2} s; recorded figure {recorded:.3e})\n",
                m.repeats.max(1),
                run.particles_per_second(),
                run.retired,
                run.emitted,
                run.seconds,
            )?;
            Ok(run.particles_per_second())
        }
        Err(e) => {
            writeln!(out, "paper baseline: {fallback}, because {e}\n")?;
            Ok(recorded)
        }
    }
}

/// Times the reference scene and its scaling variants and writes a Markdown table to `out`,
/// then, with several thread counts, the scaling table, then the 60 s raster, the short
/// variants, the cohesion analysis and the storage per particle.
pub fn run_matrix(m: &MatrixSettings, out: &mut impl std::io::Write) -> Result<(), BenchError> {
    m.check()?;
    let counts = m.thread_counts();
    for &t in &counts {
        spraysim_engine::check_threads(t)?;
    }
    let all = counts.iter().copied().max().unwrap_or(1);
    let runs = variants(m, all)
        .into_iter()
        .map(|(name, scene, threads)| Ok((name, scene.scenario()?, threads)))
        .collect::<Result<Vec<_>, BenchError>>()?;
    let raster = raster_pass(1e5)?;
    let paper = paper_baseline(m, out)?;
    writeln!(
        out,
        "reference scene, Δt = 1 ms, forward Euler, layer epoch {} ms, {:.0} particles/s for {} s unless noted; each row the median of {} timed runs after a warm-up\n",
        1e3 * ReferenceScene::default().epoch(),
        m.spawn_rate,
        m.duration,
        m.repeats
    )?;
    writeln!(
        out,
        "| run | wall [s] | particle-steps/s | full steps | particles/s to fate | × paper baseline | real-time factor | peak RSS [MiB] |"
    )?;
    writeln!(out, "|---|---:|---:|---:|---:|---:|---:|---:|")?;
    for (name, scenario, threads) in runs {
        let r = measure_median(&scenario, threads, m.repeats)?;
        writeln!(
            out,
            "| {name} | {:.3} | {:.3e} | {:.1} % | {:.3e} | {:.1} | {:.3} | {:.0} |",
            r.wall,
            r.particle_steps_per_second(),
            100.0 * r.worked_share(),
            r.particles_per_second(),
            r.particles_per_second() / paper,
            r.real_time_factor(),
            r.peak_rss as f64 / (1024.0 * 1024.0)
        )?;
    }
    if counts.len() > 1 {
        scaling(m, &counts, &raster, paper, out)?;
    }
    let r = measure(&raster, all)?;
    writeln!(
        out,
        "\n60 s raster over the reference wall at 10⁵ particles/s, cohesion every 0.5 s, {all} threads: {:.2} s wall time ({:.1}× real time)",
        r.wall,
        r.real_time_factor()
    )?;
    let variants = m.variants.max(1);
    writeln!(
        out,
        "{variants} short variants of the reference scene (0.2 s each, one seed each, set up on the broad phase of the previous one, run and reduced to metrics): {:.1} per second",
        short_variants(variants, all)?
    )?;
    let (air, still) = painting_cost(all, m.repeats)?;
    writeln!(
        out,
        "painting, the HVLP gun on the flat panel at 10⁴ particles/s for 10 s, {all} threads: {air:.2} s with the gun's air, {still:.2} s in still air ({:.2}× the cost)",
        air / still
    )?;
    let ms = 1e3 * time_cohesion(1024, 20);
    writeln!(out, "cohesion analysis of a 1024 × 1024 heightfield: {ms:.2} ms")?;
    writeln!(
        out,
        "particle storage: {} bytes per particle slot, everything included",
        spraysim_engine::particles::Swarm::BYTES_PER_PARTICLE
    )?;
    Ok(())
}

/// The scaling table: the reference scene and the 60 s raster on each of `counts` threads,
/// with the speed-up over the first count.
fn scaling(
    m: &MatrixSettings,
    counts: &[usize],
    raster: &Scenario,
    paper: f64,
    out: &mut impl std::io::Write,
) -> Result<(), BenchError> {
    let reference =
        ReferenceScene { spawn_rate: m.spawn_rate, duration: m.duration, ..ReferenceScene::default() }
            .scenario()?;
    writeln!(
        out,
        "\n| threads | reference wall [s] | speed-up | × paper baseline | 60 s raster wall [s] | speed-up |"
    )?;
    writeln!(out, "|---:|---:|---:|---:|---:|---:|")?;
    let mut first: Option<(f64, f64)> = None;
    for &t in counts {
        let r = measure_median(&reference, t, m.repeats)?;
        let raster_wall = measure(raster, t)?.wall;
        let (r0, s0) = *first.get_or_insert((r.wall, raster_wall));
        writeln!(
            out,
            "| {t} | {:.3} | {:.2}× | {:.1} | {:.2} | {:.2}× |",
            r.wall,
            r0 / r.wall,
            r.particles_per_second() / paper,
            raster_wall,
            s0 / raster_wall
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The baseline's rate and the line it printed, at 10⁴ particles/s for `duration` s.
    fn baseline_line(measure_baseline: bool, duration: f64) -> (f64, String) {
        let m = MatrixSettings {
            spawn_rate: 1e4,
            duration,
            threads: vec![1],
            repeats: 1,
            variants: 1,
            measure_baseline,
        };
        let mut out = Vec::new();
        let rate = paper_baseline(&m, &mut out).expect("a rate or a fallback, never an error");
        (rate, String::from_utf8_lossy(&out).into_owned())
    }

    #[test]
    fn the_recorded_baseline_is_used_when_asked_and_said() {
        let (rate, line) = baseline_line(false, 0.2);
        assert_eq!(rate, PAPER_BASELINE_PARTICLES_PER_SECOND);
        assert!(line.contains("not timed in this run"), "{line}");
    }

    #[test]
    fn a_baseline_that_cannot_be_timed_falls_back_to_the_recorded_one_and_says_why() {
        // 20 ms: no particle reaches a surface, so there is no rate to divide by (or no
        // compiler, which falls back the same way).
        let (rate, line) = baseline_line(true, 0.02);
        assert_eq!(rate, PAPER_BASELINE_PARTICLES_PER_SECOND);
        assert!(line.contains("because"), "{line}");
    }

    #[test]
    fn a_timed_baseline_is_the_rate_it_printed() {
        let (rate, line) = baseline_line(true, 0.2);
        if line.contains("timed in this run") {
            assert!(rate.is_finite() && rate > 0.0 && rate != PAPER_BASELINE_PARTICLES_PER_SECOND, "{line}");
            assert!(line.contains(&format!("{rate:.3e}")), "{line}");
        } else {
            assert!(line.contains("no C++ compiler"), "only a missing compiler may skip the timing: {line}");
        }
    }
}
