//! `spraysim bench`: times the reference scene and its scaling variants as a Markdown table,
//! then the 3D view's frame time where this build draws 3D views.

use crate::cli::BenchArgs;
use anyhow::Result;

/// Runs the bench's matrix and prints its table, then the render line.
pub fn bench(args: &BenchArgs) -> Result<()> {
    let settings = spraysim_bench::MatrixSettings {
        spawn_rate: args.spawn_rate,
        duration: args.duration,
        threads: args.threads.clone(),
        repeats: args.repeats as usize,
        variants: args.variants as usize,
        measure_baseline: !args.recorded_baseline,
    };
    spraysim_bench::run_matrix(&settings, &mut std::io::stdout().lock())?;
    render_line()
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
