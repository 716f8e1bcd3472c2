//! `spraysim-view`: a live 3D window on a spraysim run (also started by `spraysim view`).
//!
//! The simulation runs on its own thread and publishes what the window draws; the window steers
//! it (play, pause, step, speed, restart) and draws with the same renderer as the headless
//! `spraysim render`, inside egui's wgpu pass.

mod app;
mod worker;

use anyhow::{Context, Result};
use clap::Parser;
use eframe::egui;
use spraysim::Scenario;
use spraysim_render::SceneOptions;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::Ordering;
use std::sync::{Arc, Mutex};

/// Live 3D view of a spraysim run: the nozzle, the particles in flight, the rebound, the
/// obstacles and the layer building up.
#[derive(Parser)]
#[command(name = "spraysim-view", version, about)]
struct Args {
    /// Scenario file (TOML); the built-in default scene without one.
    scenario: Option<PathBuf>,
    /// Override a scenario value, e.g. `--set simulation.duration=4` (checked like the file's).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Worker threads of the simulation; 0 uses every core.
    #[arg(short = 'j', long, default_value_t = 0)]
    threads: usize,
    /// Window width and height, logical px.
    #[arg(long, value_delimiter = ',', default_values_t = [1280.0, 800.0])]
    window: Vec<f32>,
    /// Close after this many frames (for tests and scripted screenshots).
    #[arg(long)]
    frames: Option<u64>,
    /// Save the window as a PNG just before closing (with `--frames`).
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
}

fn main() -> ExitCode {
    match run(Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let mut line = e.to_string();
            for cause in e.chain().skip(1) {
                let text = cause.to_string();
                if !line.contains(&text) {
                    line = format!("{line}: {text}");
                }
            }
            eprintln!("error: {line}");
            ExitCode::FAILURE
        }
    }
}

fn run(args: Args) -> Result<()> {
    let scenario = match &args.scenario {
        Some(p) => Scenario::from_path(p)?,
        None => Scenario::default_scene(),
    };
    // Applied together and checked once, as the command line's `--set`s are.
    let scenario = if args.set.is_empty() { scenario } else { scenario.with_assignments(&args.set)? };
    let mut sim = scenario.build()?;
    sim.set_threads(args.threads)?;
    let options = SceneOptions::for_scenario(&scenario);
    let title = format!("spraysim — {}", options.title);
    let shared = Arc::new(worker::Shared::default());
    shared.max_particles.store(250_000, Ordering::Relaxed);
    let (tx, rx) = std::sync::mpsc::channel();
    let saved = Arc::new(Mutex::new(None));
    let exit = args.frames.map(|frames| app::ExitPlan {
        frames,
        screenshot: args.screenshot.clone(),
        saved: saved.clone(),
    });
    let [w, h] =
        [args.window.first().copied().unwrap_or(1280.0), args.window.get(1).copied().unwrap_or(800.0)];
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default().with_inner_size([w, h]).with_title(&title),
        renderer: eframe::Renderer::Wgpu,
        depth_buffer: app::DEPTH_BITS,
        multisampling: 0,
        ..Default::default()
    };
    let worker_options = options.clone();
    let worker_shared = shared.clone();
    eframe::run_native(
        "spraysim-view",
        native,
        Box::new(move |cc| {
            let ctx = cc.egui_ctx.clone();
            let wake = Box::new(move || ctx.request_repaint());
            let w = worker::Worker::new(sim, worker_options, worker_shared, wake);
            std::thread::Builder::new().name("simulation".into()).spawn(move || w.run(rx))?;
            let view = app::App::new(cc, options.title.clone(), options, (tx, shared), exit)?;
            Ok(Box::new(view))
        }),
    )
    .map_err(|e| anyhow::anyhow!("{e}"))
    .context("the 3D window could not run (is there a display, and a graphics driver such as Mesa's?)")?;
    if args.screenshot.is_some() {
        match saved.lock().ok().and_then(|s| s.clone()) {
            Some(Ok(path)) => eprintln!("saved the window to {}", path.display()),
            Some(Err(e)) => anyhow::bail!("cannot save the screenshot: {e}"),
            None => anyhow::bail!("the window closed before its screenshot was taken"),
        }
    }
    Ok(())
}
