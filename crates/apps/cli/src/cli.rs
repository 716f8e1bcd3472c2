//! What the command line accepts: every subcommand with its options, as clap parses them. The
//! doc comments here are the `--help` texts.

use clap::{Args, Parser, Subcommand, ValueEnum};
use spraysim::scenario::Backend;
use std::path::PathBuf;

/// Particle simulation of construction spraying: shotcrete, spray painting, abrasive blasting.
#[derive(Parser)]
#[command(name = "spraysim", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Subcommand)]
pub enum Command {
    /// Run a scenario (the built-in default scene when none is given) and write its outputs.
    Run(RunArgs),
    /// Continue a run from the checkpoint in its output directory; the outputs are those the
    /// run would have written without the stop, byte for byte (of `[output] render`'s 3D
    /// views, only those due after the checkpoint are drawn).
    Resume(ResumeArgs),
    /// Validate a scenario without running it; prints the resolved scenario with `--resolved`.
    Check(CheckArgs),
    /// Fit emitter parameters so that the simulated profile matches a measured one.
    ///
    /// The profile is a CSV file with a header naming position and value with units, e.g.
    /// `radius [mm],thickness [mm]` (thickness in m, cm, mm or µm; or mass per area in kg/m²
    /// or g/m²). Writes calibrated.toml, calibration.json, profile.csv and profile.png.
    Calibrate(CalibrateArgs),
    /// Run every check against a closed form and write a Markdown report with plots.
    ///
    /// Writes DIR/validation.md and DIR/validation/*.png; fails if any check fails.
    Validate(ValidateArgs),
    /// Print each process preset as TOML to paste into a scenario.
    Presets,
    /// Run a scenario and render 3D views of it without a display: stills and an animation.
    ///
    /// Writes DIR/view_TIME.png for each `--at` time (`view_end.png` for `end`) and, with
    /// `--frames N`, DIR/frames/frame_NNNN.png, DIR/animation.gif and, when `ffmpeg` is on the
    /// PATH, DIR/animation.mp4. Needs the `render` feature (`cargo build --release --features
    /// render`) and a graphics adapter (Mesa's software drivers will do).
    Render(Box<RenderArgs>),
    /// Open the live 3D window on a scenario (the `spraysim-view` program, built with
    /// `cargo build --release -p spraysim-viewer`).
    View(ViewArgs),
    /// Time the reference scene and its scaling variants; prints a Markdown table.
    Bench(BenchArgs),
}

/// `spraysim run`'s arguments.
#[derive(Args)]
pub struct RunArgs {
    /// Scenario file (TOML).
    pub scenario: Option<PathBuf>,
    /// Override a scenario value, e.g. `--set simulation.seed=3 --set emitter.speed=[20,28]`
    /// (checked like the file's).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output directory (overrides `[output] directory`).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Worker threads; 0 uses every core. Results do not depend on it.
    #[arg(short = 'j', long, default_value_t = 0)]
    pub threads: usize,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub quiet: bool,
    /// Write a checkpoint of the whole state every this much simulated time (`10s`, `500ms`,
    /// or seconds) into the output directory, to continue with `spraysim resume DIR`.
    #[arg(long, value_name = "TIME", value_parser = parse_seconds)]
    pub checkpoint_every: Option<f64>,
    /// Treat the sanity warnings as errors: refuse to start when the scenario shows one, and
    /// exit with an error after writing the outputs when the run shows one.
    #[arg(long)]
    pub strict: bool,
    /// What flies the particles: `cpu`, `gpu` (a build with the `gpu` feature) or `auto` (the
    /// GPU where it can, else the CPU); overrides `[simulation] backend`.
    #[arg(long, value_parser = Backend::parse)]
    pub backend: Option<Backend>,
}

/// `spraysim resume`'s arguments.
#[derive(Args)]
pub struct ResumeArgs {
    /// The output directory of the run (holding `checkpoint.spraysim`).
    pub dir: PathBuf,
    /// Worker threads; 0 uses every core. Results do not depend on it.
    #[arg(short = 'j', long, default_value_t = 0)]
    pub threads: usize,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `spraysim check`'s arguments.
#[derive(Args)]
pub struct CheckArgs {
    /// Scenario file (TOML); without one, the built-in default scene (as `run` runs it).
    pub scenario: Option<PathBuf>,
    /// Override a scenario value (see `run --set`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Print the fully resolved scenario.
    #[arg(long)]
    pub resolved: bool,
    /// Treat the sanity warnings as errors: exit with an error when there is one.
    #[arg(long)]
    pub strict: bool,
}

/// `spraysim calibrate`'s arguments.
#[derive(Args)]
pub struct CalibrateArgs {
    /// Scenario file (TOML) to start from; its seed is used for every evaluation.
    pub scenario: PathBuf,
    /// Measured profile (CSV).
    pub profile: PathBuf,
    /// Parameters to fit, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "mu,sigma")]
    pub fit: Vec<Fit>,
    /// Target whose layer is compared (default: the first).
    #[arg(long)]
    pub target: Option<String>,
    /// How the profile runs: from the centre, or along the target's width (`right`) or
    /// height (`up`) axis through the centre.
    #[arg(long, value_enum, default_value_t = Shape::Radial)]
    pub shape: Shape,
    /// Profile centre in the target's right,up coordinates, m (default: where the nozzle
    /// axis at time 0 meets the target).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_name = "U,V")]
    pub center: Option<Vec<f64>>,
    /// Width of the band of cells averaged for a line profile, m.
    #[arg(long, default_value_t = 0.02)]
    pub band: f64,
    /// Compare shapes only: scale the simulated profile to the measured one first.
    #[arg(long)]
    pub shape_only: bool,
    /// Nelder–Mead iterations at most.
    #[arg(long, default_value_t = 100)]
    pub max_iterations: u64,
    /// Stop when the simplex's RMS errors agree within this fraction of the peak.
    #[arg(long, default_value_t = 1e-5)]
    pub tolerance: f64,
    /// Output directory (default: the scenario's `[output] directory`).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Worker threads per simulation; 0 uses every core.
    #[arg(short = 'j', long, default_value_t = 0)]
    pub threads: usize,
    /// No progress display or summary.
    #[arg(short, long)]
    pub quiet: bool,
}

/// An emitter parameter calibration can fit.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Fit {
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

/// How a measured profile runs across the target.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Shape {
    /// Radially from the centre.
    Radial,
    /// Along the target's width axis.
    Right,
    /// Along the target's height axis.
    Up,
}

/// `spraysim validate`'s arguments.
#[derive(Args)]
pub struct ValidateArgs {
    /// Output directory (`docs` regenerates the committed report).
    #[arg(short, long, default_value = "validation")]
    pub output: PathBuf,
    /// Sample sizes as a multiple of the test suite's.
    #[arg(long, default_value_t = 10.0)]
    pub size: f64,
    /// Worker threads; 0 uses every core. Results do not depend on it.
    #[arg(short = 'j', long, default_value_t = 0)]
    pub threads: usize,
}

/// `spraysim render`'s arguments.
#[derive(Args)]
#[cfg_attr(not(feature = "render"), allow(dead_code, reason = "read only by the renderer"))]
pub struct RenderArgs {
    /// Scenario file (TOML); the built-in default scene without one.
    pub scenario: Option<PathBuf>,
    /// Override a scenario value (see `run --set`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Output directory.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Times of the stills, s, comma-separated; `end` is the end of the run.
    #[arg(long, value_delimiter = ',', default_value = "end")]
    pub at: Vec<String>,
    /// Camera preset (default `iso`), or give `--eye` and `--target`.
    #[arg(long, value_parser = ["front", "side", "top", "iso", "follow"])]
    pub camera: Option<String>,
    /// Eye position X,Y,Z, m (with `--target`: a camera placed by hand).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_name = "X,Y,Z")]
    pub eye: Option<Vec<f64>>,
    /// Point looked at X,Y,Z, m.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_name = "X,Y,Z")]
    pub target: Option<Vec<f64>>,
    /// Vertical field of view, degrees.
    #[arg(long, default_value_t = 40.0)]
    pub fov: f64,
    /// Image size WIDTHxHEIGHT, px.
    #[arg(long, default_value = "1280x720")]
    pub size: String,
    /// Animation frames spread evenly over the run (0: none).
    #[arg(long, default_value_t = 0)]
    pub frames: u32,
    /// What colours the particles.
    #[arg(long, value_parser = ["state", "speed"], default_value = "state")]
    pub color_by: String,
    /// Particle size, px (default: the process's: shotcrete 3, blasting 2, painting 1).
    #[arg(long)]
    pub point_size: Option<f64>,
    /// Factor on the deposit's thickness for its relief (1: true scale).
    #[arg(long, default_value_t = 1.0)]
    pub exaggerate: f64,
    /// Most particles drawn; more are drawn as an even sample.
    #[arg(long, default_value_t = 2_000_000)]
    pub max_particles: u64,
    /// Worker threads; 0 uses every core.
    #[arg(short = 'j', long, default_value_t = 0)]
    pub threads: usize,
    /// No progress bar or summary.
    #[arg(short, long)]
    pub quiet: bool,
}

/// `spraysim view`'s arguments.
#[derive(Args)]
pub struct ViewArgs {
    /// Scenario file (TOML); the built-in default scene without one.
    pub scenario: Option<PathBuf>,
    /// Override a scenario value (see `run --set`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// `spraysim bench`'s arguments.
#[derive(Args)]
pub struct BenchArgs {
    /// Particles emitted per second in the throughput runs.
    #[arg(long, default_value_t = 1e6)]
    pub spawn_rate: f64,
    /// Simulated seconds per run.
    #[arg(long, default_value_t = 0.5)]
    pub duration: f64,
    /// Worker thread counts, comma-separated (0: every core). The runs that do not vary it use
    /// the largest; with several (`--threads 1,2,4,8,16`) the reference scene and the 60 s
    /// raster are timed on each, in a scaling table.
    #[arg(short = 'j', long, value_delimiter = ',', default_value = "0")]
    pub threads: Vec<usize>,
    /// Timed runs per table row (after one untimed warm-up); the median is reported.
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub repeats: u32,
    /// Short variants (0.2 s of spraying each) timed for the optimisation-loop figure.
    #[arg(long, default_value_t = 1000, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub variants: u32,
    /// Divide by the paper-equivalent implementation's recorded figure instead of building
    /// it with the C++ compiler (`$CXX`, else `c++`, `g++` or `clang++`) and timing it at
    /// the same rate and duration in this run, as the bench does by default (falling back
    /// to the recorded figure, and saying why, where it cannot be built or run).
    #[arg(long)]
    pub recorded_baseline: bool,
    /// `gpu`: time the GPU backend's rows (a build with the `gpu` feature) instead of the CPU's
    /// matrix, with the CPU's reference row beside them.
    #[arg(long, value_parser = Backend::parse, default_value = "cpu")]
    pub backend: Backend,
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
