//! `spraysim bench`: times the reference scene and its scaling variants as a Markdown table,
//! then the 3D view's frame time where this build draws 3D views; with `--backend gpu`, the GPU
//! backend's rows instead.

use crate::cli::BenchArgs;
use anyhow::Result;
use spraysim::scenario::Backend;

/// Runs the bench's matrix and prints its table, then the render line; or the GPU's rows.
pub fn bench(args: &BenchArgs) -> Result<()> {
    let settings = spraysim_bench::MatrixSettings {
        spawn_rate: args.spawn_rate,
        duration: args.duration,
        threads: args.threads.clone(),
        repeats: args.repeats as usize,
        variants: args.variants as usize,
        measure_baseline: !args.recorded_baseline,
    };
    if args.backend != Backend::Cpu {
        match gpu_rows(&settings) {
            Ok(()) => return Ok(()),
            Err(e) if args.backend == Backend::Auto => eprintln!("backend \"auto\": timing the CPU: {e:#}"),
            Err(e) => return Err(e),
        }
    }
    spraysim_bench::run_matrix(&settings, &mut std::io::stdout().lock())?;
    render_line()
}

/// The GPU backend's rows, and its storage per particle slot.
fn gpu_rows(settings: &spraysim_bench::MatrixSettings) -> Result<()> {
    let gpu = spraysim::backend::gpu()?;
    let stop = std::sync::atomic::AtomicBool::new(false);
    let together = |sims| spraysim::backend::run_together(sims, &stop).map_err(|e| e.to_string());
    let step = |sims: &mut [&mut spraysim::Simulation], steps| {
        spraysim::backend::step_together(sims, steps, &stop).map_err(|e| e.to_string())
    };
    let rows =
        (&together as spraysim_bench::stage::Together<'_>, &step as spraysim_bench::stage::StepTogether<'_>);
    spraysim_bench::stage::run_stage_rows(gpu, rows, settings, &mut std::io::stdout().lock())?;
    #[cfg(feature = "gpu")]
    {
        let slot = spraysim::gpu::BYTES_PER_SLOT;
        say!(
            "GPU particle storage: {slot} bytes per particle slot ({:.1} at most with the buffer's headroom)",
            slot as f64 * 17.0 / 16.0
        );
    }
    Ok(())
}

/// The render line of a build without 3D views: says how to get one.
#[cfg(not(feature = "render"))]
fn render_line() -> Result<()> {
    say!("3D view frame time: not measured ({})", super::render::BUILD_RENDER);
    Ok(())
}

/// The renderer's frame time on the reference scene with 10⁶ particles in flight.
#[cfg(feature = "render")]
fn render_line() -> Result<()> {
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
