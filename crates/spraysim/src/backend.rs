//! What flies a run's particles (`[simulation] backend`): the CPU engine, or the GPU's kernels
//! where this build has them (the `gpu` feature, `spraysim-gpu`), an adapter opens and the
//! scenario lies in their scope. The command and the Python binding both choose here.

use crate::Scenario;
use crate::pipeline::FlightStage;
use crate::scenario::Backend;
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
    use std::sync::OnceLock;
    static GPU: OnceLock<Result<Arc<spraysim_gpu::GpuFlight>, String>> = OnceLock::new();
    let opened = GPU.get_or_init(|| {
        spraysim_gpu::GpuFlight::new(&spraysim_gpu::GpuOptions::default())
            .map(Arc::new)
            .map_err(|e| e.to_string())
    });
    match opened {
        Ok(g) => Ok(g.clone()),
        Err(e) => Err(BackendError(e.clone())),
    }
}

/// A build without the GPU backend has no stage.
#[cfg(not(feature = "gpu"))]
pub fn gpu() -> Result<Arc<dyn FlightStage>, BackendError> {
    Err(BackendError(format!("this build has no GPU backend: {BUILD_GPU}")))
}
