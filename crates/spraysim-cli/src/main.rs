//! `spraysim`: command-line front end of the spraysim library.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use spraysim::{Metrics, Scenario, Simulation};
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
    },
}

fn main() -> ExitCode {
    match dispatch(Cli::parse().command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // `{:#}` prints the whole chain of causes on one line, without a backtrace.
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn dispatch(command: Command) -> Result<()> {
    match command {
        Command::Run { scenario, output, threads, quiet } => run(scenario.as_deref(), output, threads, quiet),
        Command::Check { scenario, resolved } => {
            let sc = Scenario::from_path(&scenario)?;
            if resolved {
                print!("{}", sc.to_toml());
            } else {
                println!(
                    "{}: valid ({} targets, {} obstacles)",
                    scenario.display(),
                    sc.targets.len(),
                    sc.obstacles.len()
                );
            }
            Ok(())
        }
        Command::Bench { spawn_rate, duration, threads } => bench(spawn_rate, duration, threads),
        Command::Presets => {
            print!("{}", spraysim::scenario::presets_toml());
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
        print_summary(&sim.metrics(), wall);
        println!("wrote {} files to {}", files.len(), dir.display());
    }
    Ok(())
}

fn print_summary(m: &Metrics, wall: f64) {
    let pct = |a: f64, b: f64| if b > 0.0 { 100.0 * a / b } else { 0.0 };
    let e = m.emitted;
    println!("simulated {:.3} s in {:.2} s ({:.2}× real time)", m.time, wall, m.time / wall.max(1e-9));
    println!("{:<22}{:>12}{:>16}{:>9}", "fate", "particles", "volume [m³]", "share");
    let f = &m.fates;
    for (name, a) in [
        ("emitted", e),
        ("stuck on targets", f.stuck_on_targets),
        ("stuck on obstacles", f.stuck_on_obstacles),
        ("left the domain", f.left_domain),
        ("expired", f.expired),
        ("in flight", f.in_flight),
    ] {
        println!("{name:<22}{:>12}{:>16.6e}{:>8.2}%", a.count, a.volume, pct(a.volume, e.volume));
    }
    let show = |x: Option<f64>| x.map_or("n/a".to_string(), |v| format!("{:.2} %", 100.0 * v));
    println!("rebound ratio {}   transfer efficiency {}", show(m.rebound_ratio), show(m.transfer_efficiency));
    let fell = m.failures.events.iter().fold(0.0, |acc, e| acc + e.volume);
    println!("cohesive failures {}   fallen volume {fell:.3e} m³", m.failures.events.len());
    println!(
        "{:<12}{:>10}{:>12}{:>12}{:>8}{:>11}",
        "target", "hits", "mean [mm]", "max [mm]", "CV", "covered"
    );
    for t in &m.targets {
        let th = &t.thickness;
        println!(
            "{:<12}{:>10}{:>12.3}{:>12.3}{:>8.2}{:>10.1}%",
            t.name,
            t.hits,
            th.mean * 1e3,
            th.max * 1e3,
            th.cv,
            100.0 * th.covered_fraction
        );
    }
}

/// Runs the reference scene and its scaling variants and prints one table row each.
fn bench(spawn_rate: f64, duration: f64, threads: usize) -> Result<()> {
    use spraysim::bench::{ReferenceScene, measure};
    use spraysim::integrator::Integrator;
    let base = ReferenceScene { spawn_rate, duration, ..ReferenceScene::default() };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let all = if threads == 0 { cores } else { threads };
    let runs: Vec<(String, ReferenceScene, usize)> = vec![
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
    println!(
        "reference scene, Δt = 1 ms, forward Euler, {spawn_rate:.0} particles/s for {duration} s unless noted\n"
    );
    println!(
        "| run | wall [s] | particle-steps/s | particles/s to fate | real-time factor | peak RSS [MiB] |"
    );
    println!("|---|---:|---:|---:|---:|---:|");
    for (name, scene, threads) in runs {
        let m = measure(&scene.scenario(), threads)?;
        println!(
            "| {name} | {:.3} | {:.3e} | {:.3e} | {:.3} | {:.0} |",
            m.wall,
            m.particle_steps_per_second(),
            m.particles_per_second(),
            m.real_time_factor(),
            m.peak_rss as f64 / (1024.0 * 1024.0)
        );
    }
    let m = measure(&spraysim::bench::raster_pass(1e5), all)?;
    println!(
        "\n60 s raster over the reference wall at 10⁵ particles/s, cohesion every 0.5 s: {:.2} s wall time ({:.1}× real time)",
        m.wall,
        m.real_time_factor()
    );
    let ms = 1e3 * spraysim::bench::time_cohesion(1024, 20);
    println!("cohesion analysis of a 1024 × 1024 heightfield: {ms:.2} ms");
    println!("particle storage: {} bytes per particle slot", spraysim::swarm::Swarm::BYTES_PER_PARTICLE);
    Ok(())
}
