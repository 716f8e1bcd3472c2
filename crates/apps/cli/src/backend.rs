//! What flies a run's particles: the CPU engine, or the GPU's kernels where this build has them
//! (the `gpu` feature) and the scenario lies in their scope (`[simulation] backend`,
//! `--backend`).

use anyhow::Result;
use spraysim::pipeline::FlightStage;
use spraysim::scenario::Backend;
use spraysim::{Scenario, Simulation};
use std::sync::Arc;

/// How to build the command with the GPU backend.
#[cfg(not(feature = "gpu"))]
pub const BUILD_GPU: &str = "build the command with `cargo build --release -p spraysim-cli --features gpu`";

/// Sets `sim`'s flight stage as `scenario`'s backend asks and returns what runs the flights, in
/// words, where it is not the CPU. `gpu` is refused, naming why, where the build, the adapter or
/// the scenario does not allow it; `auto` then runs on the CPU and says why in one line on
/// stderr.
pub fn attach(sim: &mut Simulation, scenario: &Scenario) -> Result<Option<String>> {
    let backend = scenario.simulation().backend;
    if backend == Backend::Cpu {
        return Ok(None);
    }
    match gpu_stage(scenario) {
        Ok(stage) => {
            let name = format!("GPU ({})", stage.describe());
            sim.set_flight_stage(Some(stage));
            Ok(Some(name))
        }
        Err(e) if backend == Backend::Auto => {
            eprintln!("backend \"auto\": running on the CPU: {e:#}");
            Ok(None)
        }
        Err(e) => Err(e.context("backend \"gpu\" (simulation.backend)")),
    }
}

/// The GPU's flight stage for `scenario`, or why there is none.
fn gpu_stage(scenario: &Scenario) -> Result<Arc<dyn FlightStage>> {
    #[cfg(feature = "gpu")]
    spraysim_gpu::check(&scenario.config())?;
    #[cfg(not(feature = "gpu"))]
    let _ = scenario;
    open_gpu()
}

/// The GPU's flight stage on the first adapter, or why there is none.
#[cfg(feature = "gpu")]
pub fn open_gpu() -> Result<Arc<dyn FlightStage>> {
    Ok(Arc::new(spraysim_gpu::GpuFlight::new(&spraysim_gpu::GpuOptions::default())?))
}

/// A build without the GPU backend has no stage.
#[cfg(not(feature = "gpu"))]
pub fn open_gpu() -> Result<Arc<dyn FlightStage>> {
    anyhow::bail!("this build has no GPU backend: {BUILD_GPU}")
}
