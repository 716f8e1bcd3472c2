//! # spraysim-gpu
//!
//! The GPU backend of spraysim: the engine's flight stage ([`FlightStage`]) as wgpu compute
//! kernels in WGSL (`flight.wgsl`), one invocation per particle, flying it through every step
//! of a layer epoch against the layers as they stood at the epoch's start, and a call's epochs
//! (up to the next layer-stage run) in one submission, the layers settled on the GPU between
//! two, and the newborns sampled where they fly (`births.wgsl`). The engine keeps the rest of
//! the pipeline: it schedules the births (counts, ids, the nozzle's pose), books what the
//! kernels counted, settles its own layers and runs the layer stages (slump, cohesion, drip) on
//! the CPU, whose released material flies on the GPU in the next call.
//!
//! ```no_run
//! use spraysim_engine::{Simulation, SimulationConfig};
//! use spraysim_gpu::{GpuFlight, GpuOptions};
//! use std::sync::Arc;
//!
//! let config = SimulationConfig::example_wall(0.2);
//! spraysim_gpu::check(&config)?; // refuses what the GPU does not run, naming it
//! let mut sim = Simulation::new(config)?;
//! sim.set_flight_stage(Some(Arc::new(GpuFlight::new(&GpuOptions::default())?)));
//! sim.run(|_| {});
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## What differs from the CPU engine
//!
//! The results agree with the CPU engine's within statistical tolerances, not to the bit:
//!
//! - **f32.** Positions and velocities are single precision (0.5 µm at 4 m), and a rebound
//!   leaves from 2 µm off the surface, not 1 nm.
//! - **Every step in full.** Each step of each particle is tested against every target, and
//!   against each obstacle shape whose bounding box (widened by 1 mm) the box of the step's path
//!   overlaps; one box round all the shapes lets most steps skip them with one test. No
//!   coasting: with the exact integrator a step's hits are found on its chord, which leaves the
//!   arc by at most g Δt²/8 (1.2 µm at Δt = 1 ms).
//! - **The layer at the cell crossed.** A layer is struck where the path crosses the height of
//!   the layer in the cell under the crossing (found again at most three times), not by a march
//!   through its cells; the cushion under an impact is averaged over at most 25 × 25 cells (a
//!   wider disc is sampled with a stride).
//! - **Its own random streams.** Draws come from a counter-based hash of (seed, particle,
//!   event, draw) in u32 arithmetic, not from the CPU's generators.
//!
//! It is deterministic: deposits, impacts and fates are booked in integer atomics (volumes in
//! quanta of the run's volume quantum, 2⁻²⁴ of a nozzle particle's volume, as 64-bit pairs),
//! whose sums do not depend on the order of the invocations, and the cells they list are
//! sorted before the engine books them. The same scenario and seed on the same adapter and
//! driver give the same outputs.
//!
//! ## Scope
//!
//! [`check`] refuses, naming the feature: mesh targets (rectangles and cylindrical shells, with
//! openings, run), mesh and shell obstacles, shapes, rebound laws and erosion laws defined outside
//! the engine, the gun's air and an impact log. Calls whose impacts an observer gathers as events fly on the CPU.

mod batch;
mod births;
mod bounds;
mod device;
mod dispatch;
mod flight;
mod kernels;
mod pack;
mod report;
mod scope;
mod timing;

pub use batch::{BatchMember, GpuBatch, run_together, step_together};
pub use device::{EPOCHS_PER_CALL, Gpu, GpuOptions};
pub use flight::GpuFlight;
pub use pack::BYTES_PER_SLOT;
pub use scope::{MAX_COEFFICIENTS, MAX_FOOTPRINT, MAX_IMPACTS_PER_STEP, MAX_SIEVES, Unsupported, check};
pub use spraysim_engine::pipeline::FlightStage;
pub use timing::{KernelTimes, Profile};

/// Why the GPU backend cannot run.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No adapter was found (no GPU driver, no Mesa lavapipe).
    #[error("no GPU adapter: {0}")]
    NoAdapter(String),
    /// The device could not be opened, or failed.
    #[error("the GPU device failed: {0}")]
    Device(String),
    /// Results could not be read back.
    #[error("cannot read the GPU's results back: {0}")]
    Readback(String),
    /// A call is larger than one binding holds.
    #[error("too large for the GPU backend: {0}")]
    TooLarge(String),
    /// The configuration asks for what the backend does not run.
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
}
