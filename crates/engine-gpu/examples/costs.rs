//! What each part of the reference scene costs the GPU's flight: the scene (shotcrete at 10⁶
//! particles/s for 0.5 s onto the 2 m wall's 1024 × 1024 cells and the floor, through 26 bars of
//! rebar) flown on the GPU in full, then with one cost taken away at a time (the cushion's disc
//! mean, the bars, the impacts after a step's first, four epoch ends in five), each with the
//! stage's profile (its kernels' GPU times, where the adapter writes timestamps).
//!
//! `cargo run --release -p spraysim-gpu --example costs [seed]` (seed 3 by default).

use spraysim_gpu::{GpuFlight, GpuOptions};
use spraysim_scenario::scenes::{NOZZLE_AT_WALL, bar, floor, scenario, wall};
use std::sync::Arc;
use std::time::Instant;

/// The reference scene with `seed`, with or without its `rebar`, the cushion averaged over
/// `cushion` m, and `extra` lines of `[simulation]`.
fn reference(seed: u64, rebar: bool, cushion: f64, extra: &str) -> String {
    let mut t = format!(
        "[simulation]\ndt = 0.001\nduration = 0.5\nseed = {seed}\n{extra}[process]\nmax_lifetime = 3.0\n\
         [process.impact]\ncushion_radius = {cushion:?}\n[emitter]\nspawn_rate = 1e6\n{}{}\
         [domain]\nmin = [-3.0, -2.5, -0.5]\nmax = [0.5, 2.5, 3.0]\n{NOZZLE_AT_WALL}",
        wall().resolution(1024, 1024),
        floor().resolution(400, 300)
    );
    if rebar {
        for k in -6..=6 {
            let offset = 0.15 * f64::from(k);
            t.push_str(&bar(&format!("v{k}"), [-0.05, offset, 0.0], [-0.05, offset, 2.0], 0.008));
            t.push_str(&bar(
                &format!("h{k}"),
                [-0.067, -1.0, 1.0 + offset],
                [-0.067, 1.0, 1.0 + offset],
                0.008,
            ));
        }
    }
    t
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seed = match std::env::args().nth(1) {
        Some(s) => s.parse().map_err(|e| format!("the seed {s:?} is not a whole number: {e}"))?,
        None => 3,
    };
    let gpu = Arc::new(GpuFlight::new(&GpuOptions::default())?);
    println!("{}\n", spraysim_engine::pipeline::FlightStage::describe(gpu.as_ref()));
    let variants = [
        ("in full (run twice: the first includes building the kernels)", true, 0.02, ""),
        ("in full", true, 0.02, ""),
        ("the cushion as the struck cell alone", true, 0.0, ""),
        ("without the bars", false, 0.02, ""),
        ("one impact a step", true, 0.02, "max_impacts_per_step = 1\n"),
        ("epochs of 25 ms", true, 0.02, "layer_epoch = 0.025\n"),
    ];
    for (name, rebar, cushion, extra) in variants {
        let sc = scenario(&reference(seed, rebar, cushion, extra), name);
        spraysim_gpu::check(&sc.config())?;
        let mut sim = sc.build()?;
        sim.set_flight_stage(Some(gpu.clone()));
        gpu.take_profile();
        let start = Instant::now();
        sim.run(|_| {});
        let wall = start.elapsed().as_secs_f64();
        if let Some(e) = sim.flight_stage_error() {
            return Err(format!("{name}: the GPU declined a call: {e}").into());
        }
        let m = sim.metrics();
        println!(
            "{name}: {wall:.4} s, {} particles to a fate\n  {}",
            m.emitted.count - m.fates.in_flight.count,
            gpu.take_profile().describe()
        );
    }
    Ok(())
}
