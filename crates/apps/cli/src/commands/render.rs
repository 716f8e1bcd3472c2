//! `spraysim render`: a run drawn as 3D stills and an animation without a display; and
//! `spraysim view`, which starts the separate viewer program. Drawing needs the `render`
//! feature; a build without it checks the arguments, then refuses, saying how to build it.

use super::load;
use crate::cli::{RenderArgs, ViewArgs};
use anyhow::{Context, Result, bail};
use spraysim::Scenario;
use spraysim::scenario::{ParticleColoring, RenderCamera, RenderParams, RenderTime, ViewPreset};
use std::path::PathBuf;

/// How to get a `spraysim` that draws 3D views.
#[cfg(not(feature = "render"))]
pub const BUILD_RENDER: &str = "this spraysim was built without 3D views; build it with \
    `cargo build --release --features render` (or run `cargo run --release --features render -- …`)";

/// `spraysim render` without the feature: checks the arguments, then says how to build it.
#[cfg(not(feature = "render"))]
pub fn render(args: &RenderArgs) -> Result<()> {
    let sc = load(args.scenario.as_deref(), &args.set)?;
    params(args, &sc)?;
    bail!("`spraysim render`: {BUILD_RENDER}")
}

/// `spraysim render`: runs the scenario, drawing its stills and frames, and writes them.
#[cfg(feature = "render")]
pub fn render(args: &RenderArgs) -> Result<()> {
    use crate::control::RunControl;
    use indicatif::{ProgressBar, ProgressStyle};
    use spraysim_render::record;
    let sc = load(args.scenario.as_deref(), &args.set)?;
    let p = params(args, &sc)?;
    let start = std::time::Instant::now();
    let mut rec = record::Recorder::new(&sc, &p, &Default::default())?;
    let mut sim = sc.build()?;
    sim.set_threads(args.threads)?;
    let dir = super::lock(&args.output)?;
    let bar = if args.quiet { ProgressBar::hidden() } else { ProgressBar::new(sim.total_steps()) };
    bar.set_style(
        ProgressStyle::with_template("{bar:40.cyan/blue} {percent:>3}% t = {msg} [{elapsed_precise}]")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    rec.observe(&sim)?;
    while !sim.is_finished() {
        let k = rec.steps_to_next(&sim).map_or(sim.steps_to_epoch_end(), |k| k.min(sim.steps_to_epoch_end()));
        sim.advance(k);
        rec.observe(&sim)?;
        bar.set_position(sim.steps_done());
        bar.set_message(format!("{:.3} s, {} in flight", sim.time(), sim.swarm().alive()));
    }
    bar.finish_and_clear();
    let adapter = rec.describe();
    let recording = rec.finish(&sim)?;
    let files = dir
        .write_set_with(&recording.files, &RunControl)
        .with_context(|| format!("writing to {}", args.output.display()))?;
    if !args.quiet {
        for n in &recording.notes {
            eprintln!("note: {n}");
        }
        let stills: Vec<&str> =
            recording.files.iter().map(|(n, _)| n.as_str()).filter(|n| !n.starts_with("frames/")).collect();
        say!("rendered on {adapter} in {:.1} s", start.elapsed().as_secs_f64());
        say!("wrote {} files to {}: {}", files.len(), args.output.display(), stills.join(", "));
    }
    Ok(())
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
pub fn view(args: &ViewArgs) -> Result<()> {
    let (scenario, set) = (args.scenario.as_deref(), &args.set);
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
