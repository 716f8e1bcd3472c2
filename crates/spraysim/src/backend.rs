//! What flies a run's particles (`[simulation] backend`): the CPU engine, or the GPU's kernels
//! where this build has them (the `gpu` feature, `spraysim-gpu`), an adapter opens and the
//! scenario lies in their scope. The command and the Python binding both choose here.

use crate::pipeline::FlightStage;
use crate::scenario::Backend;
use crate::{Scenario, Simulation};
use std::sync::Arc;

/// How to get a build with the GPU backend.
pub const BUILD_GPU: &str = "build the command with `cargo build --release -p spraysim-cli --features gpu` (the Python \
     package is built with it)";

/// Why the GPU cannot fly a scenario's particles.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BackendError(pub String);

impl std::fmt::Display for BackendError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BackendError {}

/// What a backend was resolved to.
#[derive(Clone, Debug, Default)]
pub struct Chosen {
    /// The flight stage to set on the simulation; `None`: the engine's own flight (the CPU).
    pub stage: Option<Arc<dyn FlightStage>>,
    /// For `auto` on the CPU: why not the GPU, in one line.
    pub fallback: Option<String>,
}

impl Chosen {
    /// What runs the flights, in words (see [`describe`]).
    pub fn describe(&self) -> String {
        describe(self.stage.as_deref())
    }
}

/// What runs the flights of a simulation with flight stage `stage`, in words: `CPU`, or
/// `GPU (adapter, driver, API)`.
pub fn describe(stage: Option<&dyn FlightStage>) -> String {
    stage.map_or_else(|| "CPU".to_string(), |s| format!("GPU ({})", s.describe()))
}

/// The flight stage `backend` asks for `scenario`: none for `cpu`; for `gpu` the GPU's, or an
/// error naming why (a build without it, no adapter, a feature outside its scope, with its
/// key); for `auto` the GPU's where it can, else none, with why.
pub fn choose(backend: Backend, scenario: &Scenario) -> Result<Chosen, BackendError> {
    if backend == Backend::Cpu {
        return Ok(Chosen::default());
    }
    match gpu_for(scenario) {
        Ok(stage) => Ok(Chosen { stage: Some(stage), fallback: None }),
        Err(e) if backend == Backend::Auto => Ok(Chosen { stage: None, fallback: Some(e.0) }),
        Err(e) => Err(e),
    }
}

/// The GPU's flight stage for `scenario`, or why there is none.
fn gpu_for(scenario: &Scenario) -> Result<Arc<dyn FlightStage>, BackendError> {
    #[cfg(feature = "gpu")]
    spraysim_gpu::check(&scenario.config()).map_err(|e| BackendError(e.to_string()))?;
    #[cfg(not(feature = "gpu"))]
    let _ = scenario;
    gpu()
}

/// The process's GPU flight stage on the first adapter, opened on first use and shared by every
/// simulation after (calls from several take turns), or why there is none.
#[cfg(feature = "gpu")]
pub fn gpu() -> Result<Arc<dyn FlightStage>, BackendError> {
    Ok(gpu_flight()?)
}

/// A build without the GPU backend has no stage.
#[cfg(not(feature = "gpu"))]
pub fn gpu() -> Result<Arc<dyn FlightStage>, BackendError> {
    Err(no_gpu())
}

/// The process's GPU flight stage (see [`gpu`]), as the GPU crate's type.
#[cfg(feature = "gpu")]
pub fn gpu_flight() -> Result<Arc<spraysim_gpu::GpuFlight>, BackendError> {
    use std::sync::OnceLock;
    static GPU: OnceLock<Result<Arc<spraysim_gpu::GpuFlight>, String>> = OnceLock::new();
    let opened = GPU.get_or_init(|| {
        spraysim_gpu::GpuFlight::new(&spraysim_gpu::GpuOptions::default())
            .map(Arc::new)
            .map_err(|e| e.to_string())
    });
    opened.clone().map_err(BackendError)
}

/// Why a build without the GPU backend has none.
#[cfg(not(feature = "gpu"))]
fn no_gpu() -> BackendError {
    BackendError(format!("this build has no GPU backend: {BUILD_GPU}"))
}

/// Runs `sims` to their ends together on the process's GPU, their calls flown in shared
/// dispatches (batches whose grids fit one binding, side by side; see
/// `spraysim_gpu::run_together`), each on a thread of its own; each stops after the call under
/// way once `stop` is set. Each run's results equal its run alone on the GPU.
#[cfg(feature = "gpu")]
pub fn run_together(
    sims: Vec<Simulation>,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<Vec<Simulation>, BackendError> {
    spraysim_gpu::run_together(&gpu_flight()?, sims, stop, |_, sim| sim)
        .map_err(|e| BackendError(e.to_string()))
}

/// A build without the GPU backend cannot run simulations together on one.
#[cfg(not(feature = "gpu"))]
pub fn run_together(
    _sims: Vec<Simulation>,
    _stop: &std::sync::atomic::AtomicBool,
) -> Result<Vec<Simulation>, BackendError> {
    Err(no_gpu())
}

/// Advances each of `sims` by `steps` steps (or to its run's end), together: those on the GPU
/// with their calls flown in shared dispatches, each on a thread of its own (see
/// `spraysim_gpu::step_together`), the others on the CPU; each stops after the call under way
/// once `stop` is set. Each one's results equal its steps alone.
#[cfg(feature = "gpu")]
pub fn step_together(
    sims: &mut [&mut Simulation],
    steps: u64,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<(), BackendError> {
    if sims.iter().all(|s| s.flight_stage().is_none()) {
        step_on_cpu(sims, steps, stop);
        return Ok(());
    }
    spraysim_gpu::step_together(&gpu_flight()?, sims, steps, stop).map_err(|e| BackendError(e.to_string()))
}

/// Advances each of `sims` (none of which can be on a GPU in this build) by `steps` steps.
#[cfg(not(feature = "gpu"))]
pub fn step_together(
    sims: &mut [&mut Simulation],
    steps: u64,
    stop: &std::sync::atomic::AtomicBool,
) -> Result<(), BackendError> {
    step_on_cpu(sims, steps, stop);
    Ok(())
}

/// Advances each of `sims` by `steps` steps (or to its run's end) on its own flight, one after
/// the other, a call at a time while `stop` is not set.
fn step_on_cpu(sims: &mut [&mut Simulation], steps: u64, stop: &std::sync::atomic::AtomicBool) {
    for sim in sims.iter_mut() {
        let goal = sim.steps_ahead(steps);
        while sim.steps_done() < goal && !stop.load(std::sync::atomic::Ordering::Relaxed) {
            // A call ends by itself at its epoch's (or its stage's) end.
            sim.advance_call(goal - sim.steps_done());
        }
    }
}
