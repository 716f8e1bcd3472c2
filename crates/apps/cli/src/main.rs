//! `spraysim`: command-line front end of the spraysim library.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use spraysim::output::OutputDir;
use spraysim::{Metrics, Scenario};
use spraysim_calibrate::{CalibrationSettings, FitParam, ProfileShape};
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
        /// Override a scenario value, e.g. `--set simulation.seed=3 --set emitter.speed=[20,28]`
        /// (checked like the file's).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Output directory (overrides `[output] directory`).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Worker threads; 0 uses every core. Results do not depend on it.
        #[arg(short = 'j', long, default_value_t = 0)]
        threads: usize,
        /// No progress bar or summary.
        #[arg(short, long)]
        quiet: bool,
        /// Write a checkpoint of the whole state every this much simulated time (`10s`, `500ms`,
        /// or seconds) into the output directory, to continue with `spraysim resume DIR`.
        #[arg(long, value_name = "TIME", value_parser = parse_seconds)]
        checkpoint_every: Option<f64>,
    },
    /// Continue a run from the checkpoint in its output directory; the outputs are those the
    /// run would have written without the stop, byte for byte (of `[output] render`'s 3D
    /// views, only those due after the checkpoint are drawn).
    Resume {
        /// The output directory of the run (holding `checkpoint.spraysim`).
        dir: PathBuf,
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
        /// Override a scenario value (see `run --set`).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
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
        /// Parameters to fit, comma-separated.
        #[arg(long, value_delimiter = ',', default_value = "mu,sigma")]
        fit: Vec<Fit>,
        /// Target whose layer is compared (default: the first).
        #[arg(long)]
        target: Option<String>,
        /// How the profile runs: from the centre, or along the target's width (`right`) or
        /// height (`up`) axis through the centre.
        #[arg(long, value_enum, default_value_t = Shape::Radial)]
        shape: Shape,
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
    /// Run a scenario and render 3D views of it without a display: stills and an animation.
    ///
    /// Writes DIR/view_TIME.png for each `--at` time (`view_end.png` for `end`) and, with
    /// `--frames N`, DIR/frames/frame_NNNN.png, DIR/animation.gif and, when `ffmpeg` is on the
    /// PATH, DIR/animation.mp4. Needs the `render` feature (`cargo build --release --features
    /// render`) and a graphics adapter (Mesa's software drivers will do).
    Render(Box<render::RenderArgs>),
    /// Open the live 3D window on a scenario (the `spraysim-view` program, built with
    /// `cargo build --release -p spraysim-viewer`).
    View {
        /// Scenario file (TOML); the built-in default scene without one.
        scenario: Option<PathBuf>,
        /// Override a scenario value (see `run --set`).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
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
        /// Short variants (0.2 s of spraying each) timed for the optimisation-loop figure.
        #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u32).range(1..=100_000))]
        variants: u32,
        /// Divide by the paper-equivalent implementation's recorded figure instead of building
        /// it with the C++ compiler (`$CXX`, else `c++`, `g++` or `clang++`) and timing it at
        /// the same rate and duration in this run, as the bench does by default (falling back
        /// to the recorded figure, and saying why, where it cannot be built or run).
        #[arg(long)]
        recorded_baseline: bool,
    },
}

/// An emitter parameter calibration can fit.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum Fit {
    /// μ of the truncated-normal direction law, in units of θ_half.
    #[value(name = "mu")]
    Mu,
    /// σ of the truncated-normal direction law, in units of θ_half.
    #[value(name = "sigma")]
    Sigma,
    /// The full cone angle, degrees.
    #[value(name = "cone_angle")]
    ConeAngle,
    /// The lowest emission speed, m/s.
    #[value(name = "speed_min")]
    SpeedMin,
    /// The highest emission speed, m/s.
    #[value(name = "speed_max")]
    SpeedMax,
}

impl From<Fit> for FitParam {
    fn from(f: Fit) -> FitParam {
        match f {
            Fit::Mu => FitParam::Mu,
            Fit::Sigma => FitParam::Sigma,
            Fit::ConeAngle => FitParam::ConeAngle,
            Fit::SpeedMin => FitParam::SpeedMin,
            Fit::SpeedMax => FitParam::SpeedMax,
        }
    }
}

/// How a measured profile runs across the target.
#[derive(Clone, Copy, Debug, ValueEnum)]
enum Shape {
    /// Radially from the centre.
    Radial,
    /// Along the target's width axis.
    Right,
    /// Along the target's height axis.
    Up,
}

impl From<Shape> for ProfileShape {
    fn from(s: Shape) -> ProfileShape {
        match s {
            Shape::Radial => ProfileShape::Radial,
            Shape::Right => ProfileShape::Right,
            Shape::Up => ProfileShape::Up,
        }
    }
}

/// `println!` to stdout that returns an error instead of panicking when stdout is closed.
macro_rules! say {
    ($($arg:tt)*) => {
        writeln!(std::io::stdout().lock(), $($arg)*)?
    };
}

mod render;

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
        Command::Run { scenario, set, output, threads, quiet, checkpoint_every } => {
            run(&load(scenario.as_deref(), &set)?, output, threads, quiet, checkpoint_every)
        }
        Command::Resume { dir, threads, quiet } => resume(&dir, threads, quiet),
        Command::Check { scenario, set, resolved } => check(&scenario, &set, resolved),
        Command::Bench { spawn_rate, duration, threads, repeats, variants, recorded_baseline } => {
            let (repeats, variants) = (repeats as usize, variants as usize);
            let settings = spraysim_bench::MatrixSettings {
                spawn_rate,
                duration,
                threads,
                repeats,
                variants,
                measure_baseline: !recorded_baseline,
            };
            spraysim_bench::run_matrix(&settings, &mut std::io::stdout().lock())?;
            render::bench_line()
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
            let center = match center.as_deref() {
                None => None,
                Some(&[u, v]) => Some([u, v]),
                Some(other) => anyhow::bail!("--center takes two numbers, U,V in m; got {}", other.len()),
            };
            let settings = CalibrationSettings {
                fit: fit.into_iter().map(FitParam::from).collect(),
                target,
                shape: shape.into(),
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
        Command::Render(args) => render::render(&args),
        Command::View { scenario, set } => render::view(scenario.as_deref(), &set),
    }
}

/// Validates a scenario and prints its size, or the scenario resolved.
fn check(scenario: &Path, set: &[String], resolved: bool) -> Result<()> {
    let sc = load(Some(scenario), set)?;
    if resolved {
        let duration = sc.simulation().duration;
        let ends = match sc.spraying_ends() {
            Some(t) if t < duration => {
                format!("# Spraying ends at {t:.3} s, before the end of the run at {duration} s.\n")
            }
            Some(t) => {
                format!("# Spraying would end at {t:.3} s, after the end of the run at {duration} s.\n")
            }
            None => format!("# Spraying goes on until the end of the run at {duration} s.\n"),
        };
        return write_out(&format!("{ends}{}", sc.to_toml()));
    }
    let b = sc.budget();
    say!(
        "{}: valid ({} targets, {} obstacles): {} steps, {:.4e} particles ({:.3e} in flight at most), \
         about {} of memory (limit {})",
        scenario.display(),
        sc.targets().len(),
        sc.obstacles().len(),
        b.steps,
        b.particles,
        b.in_flight,
        spraysim::scenario::bytes_text(b.memory),
        spraysim::scenario::bytes_text(b.limit)
    );
    warn_size(&sc);
    Ok(())
}

/// The scenario at `path` (the default scene without one), with the `--set` overrides.
fn load(path: Option<&Path>, set: &[String]) -> Result<Scenario> {
    let mut sc = match path {
        Some(p) => Scenario::from_path(p)?,
        None => Scenario::default_scene(),
    };
    for assignment in set {
        sc = sc.with_assignment(assignment)?;
    }
    for w in sc.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(sc)
}

/// Creates (if needed) and locks the output directory `dir`, refusing one that cannot be
/// written or that another writer holds.
fn lock(dir: &Path) -> Result<OutputDir> {
    OutputDir::lock(dir).with_context(|| format!("output directory {}", dir.display()))
}

/// `10s`, `500ms` or `2.5` (seconds) as seconds, above 0.
fn parse_seconds(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let (number, scale) = match (t.strip_suffix("ms"), t.strip_suffix('s')) {
        (Some(n), _) => (n, 1e-3),
        (None, Some(n)) => (n, 1.0),
        (None, None) => (t, 1.0),
    };
    match number.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x * scale),
        _ => Err(format!("expected a time above 0 such as `10s`, `500ms` or `2.5`, got {text:?}")),
    }
}

/// Runs longer than these are worth a word before they start.
const LONG_STEPS: u64 = 10_000_000;
const MANY_PARTICLES: f64 = 1e9;

/// Warns of a run whose step or particle count is far beyond the usual.
fn warn_size(sc: &Scenario) {
    let b = sc.budget();
    if b.steps > LONG_STEPS || b.particles > MANY_PARTICLES {
        eprintln!(
            "warning: this run takes {} steps (simulation.duration / simulation.dt) and emits {:.3e} particles \
             (emitter.spawn_rate × simulation.duration): it may take a very long time",
            b.steps, b.particles
        );
    }
}

fn run(
    scenario: &Scenario,
    output: Option<PathBuf>,
    threads: usize,
    quiet: bool,
    checkpoint_every: Option<f64>,
) -> Result<()> {
    // The resolved scenario written with the outputs names the directory they went to (in
    // TOML, which holds UTF-8 only).
    let scenario = &match output {
        Some(dir) => {
            let Some(text) = dir.to_str() else {
                anyhow::bail!(
                    "output directory {}: not valid UTF-8, which the resolved scenario cannot record: \
                     choose a name in UTF-8",
                    dir.display()
                );
            };
            scenario.with("output.directory", text)?
        }
        None => scenario.clone(),
    };
    warn_size(scenario);
    // Refused or set up before anything is written: a build without 3D views, or no graphics
    // adapter, a thread count beyond the machine's.
    let recorder = render::recorder(scenario)?;
    let mut sim = scenario.build()?;
    sim.set_threads(threads)?;
    let every = checkpoint_every.map(|t| (t / scenario.simulation().dt).round().max(1.0) as u64);
    let dir = lock(Path::new(&scenario.output().directory))?;
    // A new run replaces the directory's run: an earlier run's checkpoint no longer applies.
    spraysim::output::checkpoint::remove_checkpoint(&dir);
    dir.record_run(&scenario.to_toml())?;
    execute(scenario, sim, &dir, (every, recorder), quiet)
}

/// Continues the run whose checkpoint is in `dir`.
fn resume(path: &Path, threads: usize, quiet: bool) -> Result<()> {
    use spraysim::output::checkpoint;
    spraysim::check_threads(threads)?;
    if !path.is_dir() {
        anyhow::bail!("cannot resume: {} is not a directory", path.display());
    }
    // Locked first: a second resume of the same run is refused before it reads anything.
    let dir = lock(path).context("cannot resume")?;
    let ck = checkpoint::read_checkpoint(path).context("cannot resume")?;
    if let Some(warning) = checkpoint::check_belongs(&dir, &ck).context("cannot resume")? {
        eprintln!("warning: {warning}");
    }
    let origin = path.join(checkpoint::CHECKPOINT_FILE).display().to_string();
    let scenario = Scenario::from_toml(&ck.scenario, &origin)?;
    let mut recorder = render::recorder(&scenario)?;
    let mut sim = scenario.build()?;
    sim.restore_state(&ck.state).with_context(|| format!("{origin}: cannot resume"))?;
    // Views due before the checkpoint's time show states this process never had.
    recorder.skip_before(sim.time());
    sim.set_threads(threads)?;
    if !quiet {
        say!("resuming at t = {:.3} s of {} s", sim.time(), scenario.simulation().duration);
    }
    execute(&scenario, sim, &dir, ((ck.every_steps > 0).then_some(ck.every_steps), recorder), quiet)
}

/// Exit status of a run stopped by Ctrl-C (128 + SIGINT).
const INTERRUPTED: i32 = 130;

/// Counts Ctrl-C presses: the first stops the run at the end of its step, the second aborts
/// at once, unless files are being moved into place, in which case the run exits as soon as
/// they are.
fn handle_interrupts() -> Result<()> {
    use spraysim::output::control;
    static SET: std::sync::Once = std::sync::Once::new();
    let mut result = Ok(());
    SET.call_once(|| {
        result = ctrlc::set_handler(|| {
            // A later press claims the abort before it is counted: a run waiting for the count
            // to move (at a pause point) must not start moving files in between.
            if control::interrupts() >= 1 && control::try_abort() {
                eprintln!("\naborted: the output directory holds what it held before");
                std::process::exit(INTERRUPTED);
            }
            if control::interrupt() == 1 {
                eprintln!("\ninterrupted: stopping at the end of this step to write the outputs so far (Ctrl-C again to abort)");
            }
        });
    });
    result.context("cannot watch for Ctrl-C")
}

/// Steps `sim` to its end or to an interrupt, with checkpoints every `every` steps and the 3D
/// views `recorder` draws, and writes its outputs, views included, into `dir` as one set.
fn execute(
    scenario: &Scenario,
    mut sim: spraysim::Simulation,
    dir: &OutputDir,
    (every, mut recorder): (Option<u64>, render::Recorder),
    quiet: bool,
) -> Result<()> {
    use spraysim::output::{checkpoint, control};
    handle_interrupts()?;
    let save = |sim: &spraysim::Simulation, k: u64| {
        let ck =
            checkpoint::Checkpoint { scenario: scenario.to_toml(), every_steps: k, state: sim.save_state() };
        checkpoint::write_checkpoint(dir, &ck)
            .with_context(|| format!("writing a checkpoint into {}", dir.path().display()))
    };
    let bar = progress_bar(&sim, quiet);
    let (start, redraw) = (Instant::now(), (sim.total_steps() / 200).max(1));
    recorder.observe(&sim)?;
    while !sim.is_finished() && control::interrupts() == 0 {
        sim.step();
        recorder.observe(&sim)?;
        if sim.steps_done().is_multiple_of(redraw) || sim.is_finished() {
            show_progress(&bar, &sim, start);
        }
        if let Some(k) = every.filter(|&k| sim.steps_done().is_multiple_of(k) && !sim.is_finished()) {
            save(&sim, k)?;
        }
        control::pause_point(&format!("step:{}", sim.steps_done()));
    }
    bar.finish_and_clear();
    let wall = start.elapsed().as_secs_f64();
    let completed = sim.is_finished();
    if !completed {
        eprintln!(
            "interrupted at t = {:.6} s of {} s: writing the outputs so far, marked \"completed\": false",
            sim.time(),
            scenario.simulation().duration
        );
        if let Some(k) = every {
            save(&sim, k)?;
        }
    }
    let views = recorder.finish(&sim, quiet)?;
    let files = spraysim::output::write_outputs_with(&sim, scenario, dir, views)
        .with_context(|| format!("writing outputs to {}", dir.path().display()))?;
    if control::interrupts() >= 2 {
        // A second Ctrl-C came while the files moved into place: they are, so stop now.
        std::process::exit(INTERRUPTED);
    }
    if completed {
        checkpoint::remove_checkpoint(dir);
    }
    if !quiet {
        print_summary(&sim.metrics(), wall)?;
        say!("wrote {} files to {}", files.len(), dir.path().display());
    }
    if !completed {
        let resume = if every.is_some() {
            format!("; `spraysim resume {}` continues it", dir.path().display())
        } else {
            String::new()
        };
        eprintln!("run interrupted at t = {:.6} s: the outputs hold the run so far{resume}", sim.time());
        std::io::stdout().flush()?;
        std::process::exit(INTERRUPTED);
    }
    Ok(())
}

fn progress_bar(sim: &spraysim::Simulation, quiet: bool) -> ProgressBar {
    let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new(sim.total_steps()) };
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40.cyan/blue} {percent:>3}% t = {msg} [{elapsed_precise}, eta {eta}]",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_position(sim.steps_done());
    bar
}

fn show_progress(bar: &ProgressBar, s: &spraysim::Simulation, start: Instant) {
    let wall = start.elapsed().as_secs_f64().max(1e-9);
    bar.set_position(s.steps_done());
    bar.set_message(format!(
        "{:.3} s, {:.2}× real time, {} in flight",
        s.time(),
        s.time() / wall,
        s.swarm().alive()
    ));
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
    say!(
        "rebound (ACI: not in place) {}   bounced at first impact {}   trapped rebound {}",
        show(m.rebound_ratio),
        show(m.bounce_ratio),
        show(m.trapped_ratio)
    );
    say!("transfer efficiency {}", show(m.transfer_efficiency));
    let fell = m.failures.events.iter().fold(0.0, |acc, e| acc + e.volume);
    say!(
        "cohesive failures {}   fallen volume {fell:.3e} m³   slumped off the edges {:.3e} m³",
        m.failures.events.len(),
        m.failures.ran_off.volume
    );
    let layered: Vec<_> = m.targets.iter().filter(|t| t.layer_volume > 0.0).collect();
    // The share within the tolerance band, where a target gives one.
    let spec = layered.iter().any(|t| t.thickness.in_tolerance.is_some());
    if !layered.is_empty() {
        say!(
            "{:<12}{:>10}{:>12}{:>12}{:>8}{:>11}{}",
            "target",
            "hits",
            "mean [mm]",
            "max [mm]",
            "CV",
            "covered",
            if spec { format!("{:>11}", "in spec") } else { String::new() }
        );
    }
    for t in layered {
        let th = &t.thickness;
        let in_spec =
            th.in_tolerance.map_or_else(|| format!("{:>11}", "—"), |f| format!("{:>10.1}%", 100.0 * f));
        say!(
            "{:<12}{:>10}{:>12.3}{:>12.3}{:>8.2}{:>10.1}%{}",
            t.name,
            t.hits,
            th.mean * 1e3,
            th.max * 1e3,
            th.cv,
            100.0 * th.covered_fraction,
            if spec { in_spec } else { String::new() }
        );
    }
    print_erosion(m)
}

/// The wear of every eroded target: the coat cleaned and left, the substrate worn.
fn print_erosion(m: &Metrics) -> Result<()> {
    let eroded: Vec<_> = m.targets.iter().filter_map(|t| t.erosion.as_ref().map(|e| (t, e))).collect();
    if eroded.is_empty() {
        return Ok(());
    }
    say!(
        "{:<12}{:>10}{:>12}{:>11}{:>14}{:>14}",
        "target",
        "hits/cm²",
        "cleaned",
        "coat [µm]",
        "wear [µm]",
        "max wear [µm]"
    );
    for (t, e) in eroded {
        let cleaned = e.cleaned_fraction.map_or("n/a".to_string(), |c| format!("{:.1}%", 100.0 * c));
        say!(
            "{:<12}{:>10.2}{:>12}{:>11.1}{:>14.3}{:>14.3}",
            t.name,
            t.hits_per_cm2,
            cleaned,
            e.coating_left_mean * 1e6,
            e.substrate_mean_depth * 1e6,
            e.substrate_max_depth * 1e6
        );
    }
    Ok(())
}

/// Runs the closed-form checks and writes their report.
fn validate(output: &Path, size: f64, threads: usize) -> Result<()> {
    if !(size.is_finite() && (0.01..=1000.0).contains(&size)) {
        anyhow::bail!("--size must be between 0.01 and 1000, got {size}");
    }
    spraysim::check_threads(threads)?;
    let dir = lock(output)?;
    let start = Instant::now();
    let report = spraysim_validate::report(spraysim_validate::Size::times(size), threads, |name| {
        eprintln!("[{:>6.1} s] {name}", start.elapsed().as_secs_f64());
    });
    let files = report
        .files()
        .and_then(|f| dir.write_set(&f))
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
    settings: &CalibrationSettings,
    output: &Path,
    quiet: bool,
) -> Result<()> {
    use spraysim_calibrate::MeasuredProfile;
    let scenario = Scenario::from_path(path)?;
    let measured = MeasuredProfile::from_path(profile)?;
    spraysim::check_threads(settings.threads)?;
    // Nelder–Mead's evaluation count is not known in advance: a spinner with the best error.
    let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new_spinner() };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let names: Vec<&str> = settings.fit.iter().map(|p| p.name()).collect();
    let cal = spraysim_calibrate::calibrate(&scenario, &measured, settings, |e| {
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
    // Locked once the fit is done: the fit's refusals (a target it does not have, say) then
    // leave no folder behind.
    let dir = lock(output)?;
    let files = spraysim_calibrate::files::files(&cal, &measured)
        .and_then(|f| dir.write_set(&f))
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
