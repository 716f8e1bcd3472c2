//! The rows of `spraysim bench --backend gpu`: the reference scene (alone, and in batches of 16
//! and 64 run together), the 60 s raster and the short variants (one after the other, in
//! batches, and stepped together as a vectorised environment steps its environments) with their
//! particles flown on another backend's flight stage (the GPU's),
//! beside the CPU's reference row, each with the share of its wall time spent in the stage (its
//! uploads, kernels and read-backs) and the rest (births, booking, layers and their stages, on
//! the CPU).

use crate::{
    BenchError, MatrixSettings, ReferenceScene, measure_median_on, measure_on, median_run, paper_baseline,
    raster_pass,
};
use spraysim_engine::Simulation;
use spraysim_engine::pipeline::{FlightJob, FlightReport, FlightStage};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

/// A flight stage that adds up the time its calls take.
#[derive(Debug)]
pub struct Timed {
    inner: Arc<dyn FlightStage>,
    nanos: AtomicU64,
    calls: AtomicU64,
    /// Calls of one epoch each, whatever `inner` takes.
    per_epoch: bool,
}

impl Timed {
    /// `inner`, timed.
    pub fn new(inner: Arc<dyn FlightStage>) -> Timed {
        Timed { inner, nanos: AtomicU64::new(0), calls: AtomicU64::new(0), per_epoch: false }
    }

    /// `inner`, timed, handed one epoch a call (as a stage that keeps no layers of its own is).
    pub fn per_epoch(inner: Arc<dyn FlightStage>) -> Timed {
        Timed { per_epoch: true, ..Timed::new(inner) }
    }

    /// Seconds spent in the stage and calls made since the last `take`, which zeroes them.
    pub fn take(&self) -> (f64, u64) {
        (self.nanos.swap(0, Ordering::Relaxed) as f64 * 1e-9, self.calls.swap(0, Ordering::Relaxed))
    }
}

impl FlightStage for Timed {
    fn fly(&self, job: &FlightJob<'_>) -> Result<FlightReport, String> {
        let start = Instant::now();
        let report = self.inner.fly(job);
        self.nanos.fetch_add(start.elapsed().as_nanos() as u64, Ordering::Relaxed);
        self.calls.fetch_add(1, Ordering::Relaxed);
        report
    }

    fn describe(&self) -> String {
        self.inner.describe()
    }

    fn profile(&self) -> Option<String> {
        self.inner.profile()
    }

    fn epochs_per_call(&self) -> u64 {
        if self.per_epoch { 1 } else { self.inner.epochs_per_call() }
    }

    fn particles_per_call(&self) -> usize {
        self.inner.particles_per_call()
    }
}

/// How long the stage is kept busy before the reference scene's rows on it, s: a GPU idles at a
/// fraction of its clock (an H200 reads 345 MHz idle) and raises it under sustained load, which
/// a run straight after the CPU's row has not had. (On an H200 it did not remove all of it: see
/// docs/performance.md.)
const BUSY_BEFORE: f64 = 2.0;

/// Runs `scenario` on `threads` threads and `stage` over and over for `seconds` (at least
/// once), untimed, and drops what the stage's account holds of those runs.
fn keep_busy(
    scenario: &spraysim_scenario::Scenario,
    (threads, stage, timed): (usize, &Arc<dyn FlightStage>, &Timed),
    seconds: f64,
) -> Result<(), BenchError> {
    let start = Instant::now();
    loop {
        measure_on(scenario, threads, Some(stage))?;
        if start.elapsed().as_secs_f64() >= seconds {
            break;
        }
    }
    timed.take();
    stage.profile();
    Ok(())
}

/// Writes the stage's own account of where its time went since the last one, if it keeps one.
fn profile(stage: &Arc<dyn FlightStage>, out: &mut impl std::io::Write) -> Result<(), BenchError> {
    if let Some(p) = stage.profile() {
        writeln!(out, "  (stage: {p})")?;
    }
    Ok(())
}

/// Runs `count` short variants of the reference scene (0.2 s each, one seed each) one after the
/// other on `stage`, each set up on the previous one's broad phase and reduced to its metrics;
/// returns variants per second.
pub fn short_variants_on(count: usize, stage: &Arc<dyn FlightStage>) -> Result<f64, BenchError> {
    let base = ReferenceScene { duration: 0.2, ..ReferenceScene::default() }.scenario()?;
    let mut sim = base.build()?;
    sim.set_flight_stage(Some(stage.clone()));
    let start = Instant::now();
    let mut emitted = 0;
    for i in 0..count {
        base.with("simulation.seed", i as i64)?.rebuild(&mut sim)?;
        sim.run(|_| {});
        emitted += sim.metrics().emitted.count;
    }
    let wall = start.elapsed().as_secs_f64();
    if emitted == 0 {
        return Err(BenchError::Settings("the short variants emitted nothing".into()));
    }
    Ok(count as f64 / wall)
}

/// Runs simulations to their ends together, their calls flown in shared dispatches (the GPU's
/// batches), and hands them back finished.
pub type Together<'a> = &'a dyn Fn(Vec<Simulation>) -> Result<Vec<Simulation>, String>;

/// Advances simulations by a number of steps together, their calls flown in shared dispatches
/// (the GPU's batches, which last from one such step to the next): a vectorised environment's
/// step.
pub type StepTogether<'a> = &'a dyn Fn(&mut [&mut Simulation], u64) -> Result<(), String>;

/// Short variants stepped together in the vectorised-environment row.
const VECTOR_SCENES: usize = 16;

/// Steps of each vectorised step in that row (an agent's action lasting 10 ms at Δt = 1 ms).
const VECTOR_STEPS: u64 = 10;

/// `VECTOR_SCENES` copies of the short variant (0.2 s, seeds 1 on) on `stage`, stepped
/// `VECTOR_STEPS` steps at a time by `step` to their ends; returns vectorised steps per second
/// and the length of one, s.
fn vector_steps(step: StepTogether<'_>, stage: &Arc<dyn FlightStage>) -> Result<(f64, f64), BenchError> {
    let short = ReferenceScene { duration: 0.2, ..ReferenceScene::default() }.scenario()?;
    let mut sims = (1..=VECTOR_SCENES)
        .map(|k| {
            let mut sim = short.with("simulation.seed", k as i64)?.build()?;
            sim.set_flight_stage(Some(stage.clone()));
            Ok(sim)
        })
        .collect::<Result<Vec<Simulation>, BenchError>>()?;
    let length = VECTOR_STEPS as f64 * sims.first().map_or(0.0, |s| s.config().dt);
    let start = Instant::now();
    let mut steps = 0u64;
    while sims.iter().any(|s| !s.is_finished()) {
        let mut refs: Vec<&mut Simulation> = sims.iter_mut().collect();
        step(&mut refs, VECTOR_STEPS).map_err(BenchError::Settings)?;
        steps += 1;
    }
    Ok((steps as f64 / start.elapsed().as_secs_f64(), length))
}

/// `count` copies of `scenario` (seeds 1 to `count`), run to their ends together; returns their
/// wall time (s) and the particles they brought to a fate (emitted and no longer in flight).
fn batch_of(
    scenario: &spraysim_scenario::Scenario,
    count: usize,
    together: Together<'_>,
) -> Result<(f64, u64), BenchError> {
    let sims = (1..=count)
        .map(|k| Ok(scenario.with("simulation.seed", k as i64)?.build()?))
        .collect::<Result<Vec<Simulation>, BenchError>>()?;
    let start = Instant::now();
    let done = together(sims).map_err(BenchError::Settings)?;
    let wall = start.elapsed().as_secs_f64();
    let emitted = done.iter().map(|s| s.metrics().emitted.count).sum::<u64>();
    if emitted == 0 {
        return Err(BenchError::Settings("the batch emitted nothing".into()));
    }
    let in_flight = done.iter().map(|s| s.metrics().fates.in_flight.count).sum::<u64>();
    Ok((wall, emitted - in_flight))
}

/// Times the reference scene on the CPU (every thread) and on `stage`, then in batches of 16
/// and 64 scenes run `together`, then the raster and the short variants (one after the other,
/// in batches of 64, and 16 of them stepped together by `step`), as a Markdown table with the
/// stage's share of each wall time.
pub fn run_stage_rows(
    stage: Arc<dyn FlightStage>,
    (together, step): (Together<'_>, StepTogether<'_>),
    m: &MatrixSettings,
    out: &mut impl std::io::Write,
) -> Result<(), BenchError> {
    m.check()?;
    let all = m.thread_counts().into_iter().max().unwrap_or(1);
    let timed = Arc::new(Timed::new(stage));
    let on: Arc<dyn FlightStage> = timed.clone();
    writeln!(out, "flight stage: {}\n", on.describe())?;
    let paper = paper_baseline(m, out)?;
    let reference =
        ReferenceScene { spawn_rate: m.spawn_rate, duration: m.duration, ..ReferenceScene::default() }
            .scenario()?;
    writeln!(
        out,
        "reference scene, {:.0} particles/s for {} s; each reference row the median of {} timed runs after a warm-up; \
         the stage kept busy for {BUSY_BEFORE} s before its rows (a GPU raises its clock under sustained load)\n",
        m.spawn_rate, m.duration, m.repeats
    )?;
    writeln!(
        out,
        "| run | wall [s] | particles/s to fate | × paper baseline | × CPU | in the stage | stage calls |"
    )?;
    writeln!(out, "|---|---:|---:|---:|---:|---:|---:|")?;
    let cpu = measure_median_on(&reference, all, m.repeats, None)?;
    writeln!(
        out,
        "| reference, CPU, {all} threads | {:.4} | {:.3e} | {:.1} | 1 | — | — |",
        cpu.wall,
        cpu.particles_per_second(),
        cpu.particles_per_second() / paper
    )?;
    keep_busy(&reference, (all, &on, &timed), BUSY_BEFORE)?;
    // Each run with the stage's time within it: in calls of as many epochs as the stage takes,
    // then of one epoch each (the layers settled on the CPU between two).
    let single = Arc::new(Timed::per_epoch(on.clone()));
    for (name, stage, timed) in
        [("stage", &on, &timed), ("stage, a call per epoch", &(single.clone() as _), &single)]
    {
        let (gpu, (inside, calls)) =
            median_run(&reference, (all, m.repeats, Some(stage)), |r| (r, timed.take()), |r| r.0.wall)?;
        writeln!(
            out,
            "| reference, {name} | {:.4} | {:.3e} | {:.1} | {:.2} | {:.0} % | {calls} |",
            gpu.wall,
            gpu.particles_per_second(),
            gpu.particles_per_second() / paper,
            gpu.particles_per_second() / cpu.particles_per_second(),
            100.0 * inside / gpu.wall,
        )?;
        profile(stage, out)?;
    }
    batch_rows(&reference, together, (paper, cpu.particles_per_second()), &on, out)?;
    timed.take();
    let raster = measure_on(&raster_pass(1e5)?, all, Some(&on))?;
    let (inside, calls) = timed.take();
    writeln!(
        out,
        "| 60 s raster at 10⁵ particles/s, cohesion every 0.5 s, stage | {:.3} | {:.3e} | {:.0} | — | {:.0} % | {calls} |",
        raster.wall,
        raster.particles_per_second(),
        raster.particles_per_second() / paper,
        100.0 * inside / raster.wall
    )?;
    profile(&on, out)?;
    short_rows(m.variants.max(1), (together, step), (&on, &timed), out)
}

/// The rows of the short variants: `variants` of them one after the other on `on` (timed by
/// `timed`), in batches of 64 run `together`, and 16 of them stepped together by `step`.
fn short_rows(
    variants: usize,
    (together, step): (Together<'_>, StepTogether<'_>),
    (on, timed): (&Arc<dyn FlightStage>, &Arc<Timed>),
    out: &mut impl std::io::Write,
) -> Result<(), BenchError> {
    let per_second = short_variants_on(variants, on)?;
    let (inside, calls) = timed.take();
    writeln!(
        out,
        "\n{variants} short variants of the reference scene (0.2 s each, one seed each, one after the other on the stage): {per_second:.1} per second, {:.0} % of the time in the stage ({calls} calls)",
        100.0 * inside * per_second / variants as f64
    )?;
    profile(on, out)?;
    let short = ReferenceScene { duration: 0.2, ..ReferenceScene::default() }.scenario()?;
    let start = Instant::now();
    for first in (0..variants).step_by(64) {
        batch_of(&short, 64.min(variants - first), together)?;
    }
    let per_second = variants as f64 / start.elapsed().as_secs_f64();
    writeln!(out, "{variants} short variants in batches of 64 run together: {per_second:.1} per second")?;
    profile(on, out)?;
    let (per_second, length) = vector_steps(step, on)?;
    writeln!(
        out,
        "{VECTOR_SCENES} short variants stepped together {VECTOR_STEPS} steps ({:.0} ms) at a time, as a vectorised \
         environment: {per_second:.1} vectorised steps per second ({:.0} environment steps per second)",
        1e3 * length,
        per_second * VECTOR_SCENES as f64
    )?;
    profile(on, out)?;
    Ok(())
}

/// The rows of the reference scene in batches of 16 and 64 run `together` (every scene's calls
/// in shared dispatches; batches whose grids fit one binding, side by side), against the
/// paper's and the CPU's particles/s (`rates`), each with the stage's profile.
fn batch_rows(
    reference: &spraysim_scenario::Scenario,
    together: Together<'_>,
    (paper, cpu): (f64, f64),
    stage: &Arc<dyn FlightStage>,
    out: &mut impl std::io::Write,
) -> Result<(), BenchError> {
    for count in [16, 64] {
        let (wall, retired) = batch_of(reference, count, together)?;
        let rate = retired as f64 / wall;
        writeln!(
            out,
            "| reference, {count} scenes together | {wall:.4} | {rate:.3e} | {:.1} | {:.2} | — | — |",
            rate / paper,
            rate / cpu,
        )?;
        profile(stage, out)?;
    }
    Ok(())
}
