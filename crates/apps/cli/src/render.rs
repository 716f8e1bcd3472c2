//! 3D views from the command line: `spraysim render`, `[output] render` in `spraysim run`, the
//! frame-time line of `spraysim bench`, and `spraysim view`, which starts the viewer program.
//! Drawing needs the `render` feature; a build without it refuses, saying how to build it.

use anyhow::{Context, Result, bail};
use spraysim::Scenario;
use spraysim::scenario::{ParticleColoring, RenderCamera, RenderParams, RenderTime, ViewPreset};
use std::io::Write;
use std::path::{Path, PathBuf};

/// `spraysim render`'s arguments.
#[derive(clap::Args)]
#[cfg_attr(not(feature = "render"), allow(dead_code, reason = "read only by the renderer"))]
pub struct RenderArgs {
    /// Scenario file (TOML); the built-in default scene without one.
    scenario: Option<PathBuf>,
    /// Override a scenario value (see `run --set`).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Output directory.
    #[arg(short, long)]
    output: PathBuf,
    /// Times of the stills, s, comma-separated; `end` is the end of the run.
    #[arg(long, value_delimiter = ',', default_value = "end")]
    at: Vec<String>,
    /// Camera preset (default `iso`), or give `--eye` and `--target`.
    #[arg(long, value_parser = ["front", "side", "top", "iso", "follow"])]
    camera: Option<String>,
    /// Eye position X,Y,Z, m (with `--target`: a camera placed by hand).
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_name = "X,Y,Z")]
    eye: Option<Vec<f64>>,
    /// Point looked at X,Y,Z, m.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true, value_name = "X,Y,Z")]
    target: Option<Vec<f64>>,
    /// Vertical field of view, degrees.
    #[arg(long, default_value_t = 40.0)]
    fov: f64,
    /// Image size WIDTHxHEIGHT, px.
    #[arg(long, default_value = "1280x720")]
    size: String,
    /// Animation frames spread evenly over the run (0: none).
    #[arg(long, default_value_t = 0)]
    frames: u32,
    /// What colours the particles.
    #[arg(long, value_parser = ["state", "speed"], default_value = "state")]
    color_by: String,
    /// Particle size, px (default: the process's: shotcrete 3, blasting 2, painting 1).
    #[arg(long)]
    point_size: Option<f64>,
    /// Factor on the deposit's thickness for its relief (1: true scale).
    #[arg(long, default_value_t = 1.0)]
    exaggerate: f64,
    /// Most particles drawn; more are drawn as an even sample.
    #[arg(long, default_value_t = 2_000_000)]
    max_particles: u64,
    /// Worker threads; 0 uses every core.
    #[arg(short = 'j', long, default_value_t = 0)]
    threads: usize,
    /// No progress bar or summary.
    #[arg(short, long)]
    quiet: bool,
}

/// The render settings `args` give for `scenario`, checked; an error names the flag.
fn params(args: &RenderArgs, scenario: &Scenario) -> Result<RenderParams> {
    let mut p = RenderParams::defaults(scenario.process().preset);
    p.at = args
        .at
        .iter()
        .map(|t| match t.trim() {
            "end" => Ok(RenderTime::End),
            x => x
                .parse::<f64>()
                .map(RenderTime::At)
                .map_err(|_| anyhow::anyhow!("--at takes times in s or `end`, got {x:?}")),
        })
        .collect::<Result<_>>()?;
    let point = |v: &Option<Vec<f64>>, flag: &str| -> Result<Option<[f64; 3]>> {
        match v.as_deref() {
            None => Ok(None),
            Some(&[x, y, z]) => Ok(Some([x, y, z])),
            Some(other) => bail!("--{flag} takes three numbers X,Y,Z in m; got {}", other.len()),
        }
    };
    p.camera = match (point(&args.eye, "eye")?, point(&args.target, "target")?, &args.camera) {
        (Some(eye), Some(target), None) => RenderCamera::Custom { eye, target },
        (None, None, camera) => {
            let name = camera.as_deref().unwrap_or("iso");
            RenderCamera::Preset(ViewPreset::ALL.into_iter().find(|v| v.name() == name).unwrap_or_default())
        }
        (_, _, Some(_)) => {
            bail!("--camera is a preset; --eye and --target place the camera by hand: give one or the other")
        }
        _ => bail!("--eye and --target go together"),
    };
    let size: Vec<u32> = args.size.split(['x', 'X', '×']).filter_map(|s| s.trim().parse().ok()).collect();
    let [w, h] = size[..] else {
        bail!("--size takes WIDTHxHEIGHT in px, e.g. 1280x720; got {:?}", args.size)
    };
    p.size = [w, h];
    p.frames = args.frames;
    p.fov = args.fov;
    p.color_by = if args.color_by == "speed" { ParticleColoring::Speed } else { ParticleColoring::State };
    p.point_size = args.point_size.unwrap_or(p.point_size);
    p.exaggeration = args.exaggerate;
    p.max_particles = args.max_particles;
    p.check(scenario.simulation().duration).map_err(|(field, message)| {
        let flag = match field {
            "exaggeration" => "exaggerate".to_string(),
            f => f.replace('_', "-"),
        };
        anyhow::anyhow!("--{flag} {message}")
    })?;
    Ok(p)
}

/// `spraysim view`: starts the viewer program, found beside this one or on the PATH.
pub fn view(scenario: Option<&Path>, set: &[String]) -> Result<()> {
    let name = format!("spraysim-view{}", std::env::consts::EXE_SUFFIX);
    let beside = std::env::current_exe().ok().map(|e| e.with_file_name(&name)).filter(|p| p.is_file());
    let program = beside.unwrap_or_else(|| PathBuf::from(&name));
    let mut cmd = std::process::Command::new(&program);
    cmd.args(scenario);
    for s in set {
        cmd.arg("--set").arg(s);
    }
    match cmd.status() {
        Ok(status) if status.success() => Ok(()),
        Ok(status) => bail!("{} ended with {status}", program.display()),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => bail!(
            "the 3D window is the separate program spraysim-view; build it with \
             `cargo build --release -p spraysim-viewer` (then `spraysim view` finds it beside this one), \
             or run it with `cargo run --release -p spraysim-viewer -- [SCENARIO]`"
        ),
        Err(e) => Err(e).with_context(|| format!("starting {}", program.display())),
    }
}

#[cfg(not(feature = "render"))]
mod imp {
    use super::*;

    /// How to get a `spraysim` that draws 3D views.
    const BUILD_RENDER: &str = "this spraysim was built without 3D views; build it with \
        `cargo build --release --features render` (or run `cargo run --release --features render -- …`)";

    /// Stands in for the recorder of a build without 3D views: refuses `[output] render`.
    pub struct Recorder;

    /// Refuses a scenario with `[output] render`: this build cannot draw it.
    pub fn recorder(scenario: &Scenario) -> Result<Recorder> {
        if scenario.output().render.is_some() {
            bail!("{}: `[output] render` asks for 3D views, but {BUILD_RENDER}", scenario.origin());
        }
        Ok(Recorder)
    }

    impl Recorder {
        /// Nothing to draw.
        pub fn observe(&mut self, _sim: &spraysim::Simulation) -> Result<()> {
            Ok(())
        }

        /// Nothing to skip.
        pub fn skip_before(&mut self, _time: f64) {}

        /// Nothing written.
        pub fn finish(self, _sim: &spraysim::Simulation, _quiet: bool) -> Result<Vec<(String, Vec<u8>)>> {
            Ok(Vec::new())
        }
    }

    /// `spraysim render` without the feature: checks the arguments, then says how to build it.
    pub fn render(args: &RenderArgs) -> Result<()> {
        let sc = crate::load(args.scenario.as_deref(), &args.set)?;
        params(args, &sc)?;
        bail!("`spraysim render`: {BUILD_RENDER}")
    }

    /// The bench's render line without the feature.
    pub fn bench_line() -> Result<()> {
        say!("3D view frame time: not measured ({BUILD_RENDER})");
        Ok(())
    }
}

#[cfg(feature = "render")]
mod imp {
    use super::*;
    use indicatif::{ProgressBar, ProgressStyle};
    use spraysim_render::record;

    /// The views a run's `[output] render` asks for, if any.
    pub struct Recorder(Option<record::Recorder>);

    /// The recorder of `scenario`'s `[output] render`; opens the graphics adapter now, before
    /// the run, so that a machine without one fails at once.
    pub fn recorder(scenario: &Scenario) -> Result<Recorder> {
        let Some(p) = &scenario.output().render else { return Ok(Recorder(None)) };
        let r = record::Recorder::new(scenario, p, &Default::default())
            .with_context(|| format!("{}: `[output] render`", scenario.origin()))?;
        Ok(Recorder(Some(r)))
    }

    impl Recorder {
        /// Renders what is due at `sim`'s time.
        pub fn observe(&mut self, sim: &spraysim::Simulation) -> Result<()> {
            if let Some(r) = &mut self.0 {
                r.observe(sim)?;
            }
            Ok(())
        }

        /// Drops the stills and frames due before `time` (s): a resumed run cannot draw them.
        pub fn skip_before(&mut self, time: f64) {
            if let Some(r) = &mut self.0 {
                r.skip_before(time);
            }
        }

        /// Renders the end stills and encodes the animation; returns the files (name, contents).
        pub fn finish(self, sim: &spraysim::Simulation, quiet: bool) -> Result<Vec<(String, Vec<u8>)>> {
            let Some(mut r) = self.0 else { return Ok(Vec::new()) };
            // Stopped early: the views of times never reached are not drawn.
            if !sim.is_finished() {
                r.drop_after(sim.time());
            }
            let recording = r.finish(sim)?;
            if !quiet {
                for n in &recording.notes {
                    eprintln!("note: {n}");
                }
            }
            Ok(recording.files)
        }
    }

    /// `spraysim render`.
    pub fn render(args: &RenderArgs) -> Result<()> {
        let sc = crate::load(args.scenario.as_deref(), &args.set)?;
        let p = params(args, &sc)?;
        let start = std::time::Instant::now();
        let mut rec = record::Recorder::new(&sc, &p, &Default::default())?;
        let mut sim = sc.build()?;
        sim.set_threads(args.threads)?;
        let dir = crate::lock(&args.output)?;
        let bar = if args.quiet { ProgressBar::hidden() } else { ProgressBar::new(sim.total_steps()) };
        bar.set_style(
            ProgressStyle::with_template("{bar:40.cyan/blue} {percent:>3}% t = {msg} [{elapsed_precise}]")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        rec.observe(&sim)?;
        while !sim.is_finished() {
            sim.step();
            rec.observe(&sim)?;
            bar.set_position(sim.steps_done());
            bar.set_message(format!("{:.3} s, {} in flight", sim.time(), sim.swarm().alive()));
        }
        bar.finish_and_clear();
        let adapter = rec.describe();
        let recording = rec.finish(&sim)?;
        let files = dir
            .write_set(&recording.files)
            .with_context(|| format!("writing to {}", args.output.display()))?;
        if !args.quiet {
            for n in &recording.notes {
                eprintln!("note: {n}");
            }
            let stills: Vec<&str> = recording
                .files
                .iter()
                .map(|(n, _)| n.as_str())
                .filter(|n| !n.starts_with("frames/"))
                .collect();
            say!("rendered on {adapter} in {:.1} s", start.elapsed().as_secs_f64());
            say!("wrote {} files to {}: {}", files.len(), args.output.display(), stills.join(", "));
        }
        Ok(())
    }

    /// The renderer's frame time on the reference scene with 10⁶ particles in flight.
    pub fn bench_line() -> Result<()> {
        let sim = spraysim_bench::in_flight(1_000_000)?;
        let t = spraysim_render::gpu::time_frames(&sim, (1280, 720), 3);
        match t {
            Ok(t) => say!(
                "3D view of the reference scene, {} particles in flight, 1280 × 720: {:.0} ms a frame \
                 (scene {:.0} ms, draw and read back {:.0} ms; median of 3 on {})",
                t.particles,
                1e3 * (t.scene + t.draw),
                1e3 * t.scene,
                1e3 * t.draw,
                t.adapter
            ),
            Err(e) => say!("3D view frame time: not measured ({e})"),
        }
        Ok(())
    }
}

pub use imp::{Recorder, bench_line, recorder, render};
