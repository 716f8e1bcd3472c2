//! `spraysim`: command-line front end of the spraysim library.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use spraysim::{Metrics, Scenario, Simulation};
use std::io::{ErrorKind, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Particle simulation of construction spraying: shotcrete, spray painting, abrasive blasting.
#[derive(Parser)]
#[command(name = "spraysim", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scenario (the built-in default scene when none is given) and write its outputs.
    Run {
        /// Scenario file (TOML).
        scenario: Option<PathBuf>,
        /// Output directory (overrides `[output] directory`).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Worker threads; 0 uses every core. Results do not depend on it.
        #[arg(short = 'j', long, default_value_t = 0)]
        threads: usize,
        /// No progress bar or summary.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Validate a scenario without running it; prints the resolved scenario with `--resolved`.
    Check {
        /// Scenario file (TOML).
        scenario: PathBuf,
        /// Print the fully resolved scenario.
        #[arg(long)]
        resolved: bool,
    },
    /// Fit emitter parameters so that the simulated profile matches a measured one.
    ///
    /// The profile is a CSV file with a header naming position and value with units, e.g.
    /// `radius [mm],thickness [mm]` (thickness in m, cm, mm or µm; or mass per area in kg/m²
    /// or g/m²). Writes calibrated.toml, calibration.json, profile.csv and profile.png.
    Calibrate {
        /// Scenario file (TOML) to start from; its seed is used for every evaluation.
        scenario: PathBuf,
        /// Measured profile (CSV).
        profile: PathBuf,
        /// Parameters to fit, comma-separated: mu, sigma, cone_angle, speed_min, speed_max.
        #[arg(long, value_delimiter = ',', default_value = "mu,sigma")]
        fit: Vec<String>,
        /// Target whose layer is compared (default: the first).
        #[arg(long)]
        target: Option<String>,
        /// How the profile runs: `radial` (from the centre), `right` or `up` (along the
        /// target's width or height axis, through the centre).
        #[arg(long, default_value = "radial")]
        shape: String,
        /// Profile centre in the target's right,up coordinates, m (default: where the nozzle
        /// axis at time 0 meets the target).
        #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_name = "U,V")]
        center: Option<Vec<f64>>,
        /// Width of the band of cells averaged for a line profile, m.
        #[arg(long, default_value_t = 0.02)]
        band: f64,
        /// Compare shapes only: scale the simulated profile to the measured one first.
        #[arg(long)]
        shape_only: bool,
        /// Nelder–Mead iterations at most.
        #[arg(long, default_value_t = 100)]
        max_iterations: u64,
        /// Stop when the simplex's RMS errors agree within this fraction of the peak.
        #[arg(long, default_value_t = 1e-5)]
        tolerance: f64,
        /// Output directory.
        #[arg(short, long, default_value = "calibration")]
        output: PathBuf,
        /// Worker threads per simulation; 0 uses every core.
        #[arg(short = 'j', long, default_value_t = 0)]
        threads: usize,
        /// No progress display or summary.
        #[arg(short, long)]
        quiet: bool,
    },
    /// Run every check against a closed form and write a Markdown report with plots.
    ///
    /// Writes DIR/validation.md and DIR/validation/*.png; fails if any check fails.
    Validate {
        /// Output directory (`docs` regenerates the committed report).
        #[arg(short, long, default_value = "validation")]
        output: PathBuf,
        /// Sample sizes as a multiple of the test suite's.
        #[arg(long, default_value_t = 10.0)]
        size: f64,
        /// Worker threads; 0 uses every core. Results do not depend on it.
        #[arg(short = 'j', long, default_value_t = 0)]
        threads: usize,
    },
    /// Print each process preset as TOML to paste into a scenario.
    Presets,
    /// Time the reference scene and its scaling variants; prints a Markdown table.
    Bench {
        /// Particles emitted per second in the throughput runs.
        #[arg(long, default_value_t = 1e6)]
        spawn_rate: f64,
        /// Simulated seconds per run.
        #[arg(long, default_value_t = 0.5)]
        duration: f64,
        /// Worker threads for the runs that do not vary it; 0 uses every core.
        #[arg(short = 'j', long, default_value_t = 0)]
        threads: usize,
        /// Timed runs per table row (after one untimed warm-up); the median is reported.
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
        repeats: u32,
    },
}

/// `println!` to stdout that returns an error instead of panicking when stdout is closed.
macro_rules! say {
    ($($arg:tt)*) => {
        writeln!(std::io::stdout().lock(), $($arg)*)?
    };
}

/// Writes `text` to stdout as it is.
fn write_out(text: &str) -> Result<()> {
    std::io::stdout().lock().write_all(text.as_bytes())?;
    Ok(())
}

fn main() -> ExitCode {
    match dispatch(Cli::parse().command) {
        Ok(()) => ExitCode::SUCCESS,
        // The reader went away (`spraysim presets | head`): what it wanted, it has.
        Err(e) if e.downcast_ref::<std::io::Error>().is_some_and(|e| e.kind() == ErrorKind::BrokenPipe) => {
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// The whole chain of causes on one line, without a backtrace; a cause whose text its
/// parent already quotes (as the library's errors do) is not repeated.
fn one_line(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.contains(&text) {
            line = format!("{line}: {text}");
        }
    }
    line
}

fn dispatch(command: Command) -> Result<()> {
    match command {
        Command::Run { scenario, output, threads, quiet } => run(scenario.as_deref(), output, threads, quiet),
        Command::Check { scenario, resolved } => {
            let sc = Scenario::from_path(&scenario)?;
            if resolved {
                write_out(&sc.to_toml())?;
            } else {
                say!(
                    "{}: valid ({} targets, {} obstacles)",
                    scenario.display(),
                    sc.targets.len(),
                    sc.obstacles.len()
                );
            }
            Ok(())
        }
        Command::Bench { spawn_rate, duration, threads, repeats } => {
            bench(spawn_rate, duration, threads, repeats as usize)
        }
        Command::Validate { output, size, threads } => validate(&output, size, threads),
        Command::Calibrate {
            scenario,
            profile,
            fit,
            target,
            shape,
            center,
            band,
            shape_only,
            max_iterations,
            tolerance,
            output,
            threads,
            quiet,
        } => {
            use spraysim::calibration::{CalibrationSettings, FitParam, ProfileShape};
            let fit = fit
                .iter()
                .map(|name| {
                    FitParam::parse(name.trim()).with_context(|| {
                        let all: Vec<&str> = FitParam::ALL.iter().map(|p| p.name()).collect();
                        format!("--fit: unknown parameter `{name}` (one of {})", all.join(", "))
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            let shape = match shape.as_str() {
                "radial" => ProfileShape::Radial,
                "right" => ProfileShape::Right,
                "up" => ProfileShape::Up,
                other => anyhow::bail!("--shape: `{other}` is not one of radial, right, up"),
            };
            let center = match center.as_deref() {
                None => None,
                Some(&[u, v]) => Some([u, v]),
                Some(other) => anyhow::bail!("--center takes two numbers, U,V in m; got {}", other.len()),
            };
            let settings = CalibrationSettings {
                fit,
                target,
                shape,
                center,
                band,
                shape_only,
                max_iterations,
                tolerance,
                threads,
            };
            calibrate(&scenario, &profile, &settings, &output, quiet)
        }
        Command::Presets => {
            write_out(&spraysim::scenario::presets_toml())?;
            Ok(())
        }
    }
}

fn load(path: Option<&Path>) -> Result<Scenario> {
    Ok(match path {
        Some(p) => Scenario::from_path(p)?,
        None => Scenario::default_scene(),
    })
}

fn run(path: Option<&Path>, output: Option<PathBuf>, threads: usize, quiet: bool) -> Result<()> {
    let mut scenario = load(path)?;
    if let Some(dir) = &output {
        scenario.output.directory = dir.display().to_string();
    }
    let dir = PathBuf::from(&scenario.output.directory);
    // Refuse an unwritable directory before spending time on the run.
    spraysim::io::check_writable(&dir)
        .with_context(|| format!("output directory {} is not writable", dir.display()))?;
    let mut sim = Simulation::new(&scenario)?;
    sim.set_threads(threads)?;

    let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new(sim.total_steps()) };
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40.cyan/blue} {percent:>3}% t = {msg} [{elapsed_precise}, eta {eta}]",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let redraw = (sim.total_steps() / 200).max(1);
    sim.run(|s| {
        if s.steps_done() % redraw == 0 || s.is_finished() {
            let wall = start.elapsed().as_secs_f64().max(1e-9);
            bar.set_position(s.steps_done());
            bar.set_message(format!(
                "{:.3} s, {:.2}× real time, {} in flight",
                s.time(),
                s.time() / wall,
                s.swarm().alive()
            ));
        }
    });
    bar.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();

    let files = spraysim::io::write_outputs(&sim, &dir)
        .with_context(|| format!("writing outputs to {}", dir.display()))?;
    if !quiet {
        print_summary(&sim.metrics(), wall)?;
        say!("wrote {} files to {}", files.len(), dir.display());
    }
    Ok(())
}

fn print_summary(m: &Metrics, wall: f64) -> Result<()> {
    let pct = |a: f64, b: f64| if b > 0.0 { 100.0 * a / b } else { 0.0 };
    let e = m.emitted;
    say!("simulated {:.3} s in {:.2} s ({:.2}× real time)", m.time, wall, m.time / wall.max(1e-9));
    say!("{:<22}{:>12}{:>16}{:>9}", "fate", "particles", "volume [m³]", "share");
    let f = &m.fates;
    for (name, a) in [
        ("emitted", e),
        ("stuck on targets", f.stuck_on_targets),
        ("stuck on obstacles", f.stuck_on_obstacles),
        ("left the domain", f.left_domain),
        ("expired", f.expired),
        ("in flight", f.in_flight),
    ] {
        say!("{name:<22}{:>12}{:>16.6e}{:>8.2}%", a.count, a.volume, pct(a.volume, e.volume));
    }
    let show = |x: Option<f64>| x.map_or("n/a".to_string(), |v| format!("{:.2} %", 100.0 * v));
    say!("rebound ratio {}   transfer efficiency {}", show(m.rebound_ratio), show(m.transfer_efficiency));
    let fell = m.failures.events.iter().fold(0.0, |acc, e| acc + e.volume);
    say!("cohesive failures {}   fallen volume {fell:.3e} m³", m.failures.events.len());
    say!("{:<12}{:>10}{:>12}{:>12}{:>8}{:>11}", "target", "hits", "mean [mm]", "max [mm]", "CV", "covered");
    for t in &m.targets {
        let th = &t.thickness;
        say!(
            "{:<12}{:>10}{:>12.3}{:>12.3}{:>8.2}{:>10.1}%",
            t.name,
            t.hits,
            th.mean * 1e3,
            th.max * 1e3,
            th.cv,
            100.0 * th.covered_fraction
        );
    }
    Ok(())
}

/// Runs the closed-form checks and writes their report.
fn validate(output: &Path, size: f64, threads: usize) -> Result<()> {
    if !(size.is_finite() && (0.01..=1000.0).contains(&size)) {
        anyhow::bail!("--size must be between 0.01 and 1000, got {size}");
    }
    spraysim::io::check_writable(output)
        .with_context(|| format!("output directory {} is not writable", output.display()))?;
    let start = Instant::now();
    let report = spraysim::validation::report(spraysim::validation::Size::times(size), threads, |name| {
        eprintln!("[{:>6.1} s] {name}", start.elapsed().as_secs_f64());
    });
    let files = report
        .files()
        .and_then(|f| spraysim::io::write_all(output, &f))
        .with_context(|| format!("writing the report to {}", output.display()))?;
    for v in &report.verdicts {
        say!("{:<6} {}: {} ({})", if v.passed { "pass" } else { "FAIL" }, v.name, v.statistic, v.criterion);
    }
    say!("wrote {} files to {} in {:.1} s", files.len(), output.display(), start.elapsed().as_secs_f64());
    let failed = report.verdicts.iter().filter(|v| !v.passed).count();
    if failed > 0 {
        anyhow::bail!("{failed} of {} checks failed", report.verdicts.len());
    }
    Ok(())
}

/// Fits the emitter to a measured profile and writes the results.
fn calibrate(
    path: &Path,
    profile: &Path,
    settings: &spraysim::calibration::CalibrationSettings,
    output: &Path,
    quiet: bool,
) -> Result<()> {
    use spraysim::calibration::MeasuredProfile;
    let scenario = Scenario::from_path(path)?;
    let measured = MeasuredProfile::from_path(profile)?;
    spraysim::io::check_writable(output)
        .with_context(|| format!("output directory {} is not writable", output.display()))?;
    // Nelder–Mead's evaluation count is not known in advance: a spinner with the best error.
    let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new_spinner() };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let names: Vec<&str> = settings.fit.iter().map(|p| p.name()).collect();
    let cal = spraysim::calibration::calibrate(&scenario, &measured, settings, |e| {
        let values: Vec<String> = names.iter().zip(&e.values).map(|(n, v)| format!("{n} = {v:.4}")).collect();
        bar.set_message(format!(
            "evaluation {}: {} → RMS {:.2} % (best {:.2} %)",
            e.index,
            values.join(", "),
            100.0 * e.rms,
            100.0 * e.best_rms
        ));
        bar.tick();
    })?;
    bar.finish_and_clear();
    let files = spraysim::io::calibration::files(&cal, &measured)
        .and_then(|f| spraysim::io::write_all(output, &f))
        .with_context(|| format!("writing outputs to {}", output.display()))?;
    if !quiet {
        say!("{} evaluations, {} iterations ({})", cal.evaluations, cal.iterations, cal.termination);
        say!("{:<12}{:>14}{:>14}  unit", "parameter", "start", "fitted");
        for ((p, a), b) in cal.params.iter().zip(&cal.initial).zip(&cal.fitted) {
            say!("{:<12}{a:>14.6}{b:>14.6}  {}", p.name(), p.unit());
        }
        say!("{:<22}{:>10}{:>10}", "error, % of peak", "start", "fitted");
        let (i, f) = (&cal.initial_errors, &cal.errors);
        for (name, a, b) in [
            ("max absolute", i.max_abs, f.max_abs),
            ("RMS", i.rms, f.rms),
            ("mean absolute", i.mean_abs, f.mean_abs),
        ] {
            say!("{name:<22}{:>10.2}{:>10.2}", 100.0 * a, 100.0 * b);
        }
        if settings.shape_only {
            say!("simulated profile scaled by {:.4} (shape only)", cal.scale);
        }
        say!("wrote {} files to {}", files.len(), output.display());
    }
    Ok(())
}

/// Runs the reference scene and its scaling variants and prints one table row each.
fn bench(spawn_rate: f64, duration: f64, threads: usize, repeats: usize) -> Result<()> {
    use spraysim::bench::{ReferenceScene, measure, measure_median};
    use spraysim::integrator::Integrator;
    // Refused before anything runs or prints.
    if !(spawn_rate.is_finite() && spawn_rate > 0.0) {
        anyhow::bail!("--spawn-rate must be a positive number of particles/s, got {spawn_rate}");
    }
    if !(duration.is_finite() && duration > 0.0) {
        anyhow::bail!("--duration must be a positive number of seconds, got {duration}");
    }
    let base = ReferenceScene { spawn_rate, duration, ..ReferenceScene::default() };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let all = if threads == 0 { cores } else { threads };
    let scenes: Vec<(String, ReferenceScene, usize)> = vec![
        (format!("reference, {all} threads"), base.clone(), all),
        ("reference, 1 thread".into(), base.clone(), 1),
        (
            "spawn rate ×10".into(),
            ReferenceScene { spawn_rate: spawn_rate * 10.0, duration: duration / 10.0, ..base.clone() },
            all,
        ),
        ("heightfield 256²".into(), ReferenceScene { resolution: 256, ..base.clone() }, all),
        ("heightfield 2048²".into(), ReferenceScene { resolution: 2048, ..base.clone() }, all),
        ("520 bars".into(), ReferenceScene { pieces_per_bar: 20, ..base.clone() }, all),
        ("exact integrator".into(), ReferenceScene { integrator: Integrator::Exact, ..base.clone() }, all),
        (
            "exact, Δt = 10 ms".into(),
            ReferenceScene { integrator: Integrator::Exact, dt: 0.01, ..base.clone() },
            all,
        ),
    ];
    let runs = scenes
        .into_iter()
        .map(|(name, scene, threads)| Ok((name, scene.scenario()?, threads)))
        .collect::<Result<Vec<_>>>()?;
    let raster = spraysim::bench::raster_pass(1e5)?;
    say!(
        "reference scene, Δt = 1 ms, forward Euler, {spawn_rate:.0} particles/s for {duration} s unless noted; each row the median of {repeats} timed runs after a warm-up\n"
    );
    say!("| run | wall [s] | particle-steps/s | particles/s to fate | real-time factor | peak RSS [MiB] |");
    say!("|---|---:|---:|---:|---:|---:|");
    for (name, scenario, threads) in runs {
        let m = measure_median(&scenario, threads, repeats)?;
        say!(
            "| {name} | {:.3} | {:.3e} | {:.3e} | {:.3} | {:.0} |",
            m.wall,
            m.particle_steps_per_second(),
            m.particles_per_second(),
            m.real_time_factor(),
            m.peak_rss as f64 / (1024.0 * 1024.0)
        );
    }
    let m = measure(&raster, all)?;
    say!(
        "\n60 s raster over the reference wall at 10⁵ particles/s, cohesion every 0.5 s: {:.2} s wall time ({:.1}× real time)",
        m.wall,
        m.real_time_factor()
    );
    let ms = 1e3 * spraysim::bench::time_cohesion(1024, 20);
    say!("cohesion analysis of a 1024 × 1024 heightfield: {ms:.2} ms");
    say!("particle storage: {} bytes per particle slot", spraysim::swarm::Swarm::BYTES_PER_PARTICLE);
    Ok(())
}
