//! # spraysim-scenario
//!
//! Scenario files for spraysim: TOML in, a validated, immutable [`Scenario`] out, and from it
//! the engine's [`SimulationConfig`]. A file names a process preset in `[process]` and
//! overrides any of its values; every other section has fixed defaults. Every value is checked
//! as it is read, and every refusal names the file, the line and the key:
//!
//! ```text
//! wall.toml:2: `simulation.dt` must be greater than 0 s, got -0.001
//! ```
//!
//! Every file a user names (scenarios, meshes, tool paths, and the checkpoints and profiles of
//! other crates) is read through [`read_input`]: regular files only, each kind within a cap.
//!
//! Scenes written in code (tests, checks, benchmarks) are put together from the TOML building
//! blocks of [`scenes`]: the default scene's wall and floor, its nozzle, a small wall scene.
//!
//! ```
//! use spraysim_scenario::Scenario;
//!
//! let scenario = Scenario::default_scene().with("simulation.duration", 0.05)?;
//! let mut sim = scenario.build()?;
//! sim.run(|_| {});
//! assert!(sim.metrics().emitted.count > 0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod budget;
mod build;
mod error;
mod guns;
mod input;
mod mesh;
mod overrides;
mod params;
mod presets;
mod reader;
pub mod sanity;
mod scenario;
pub mod scenes;
mod splat;
mod tool_path;

pub use budget::{Budget, MemoryPart, bytes_text, default_memory_limit, machine_memory};
pub use error::ScenarioError;
pub use guns::Gun;
pub use input::{InputError, InputKind, InputProblem, read_input};
pub use mesh::{MAX_TRIANGLES, MeshError};
pub use overrides::Value;
pub use params::*;
pub use presets::presets_toml;
pub use reader::{Invalid, MAX_COORD};
pub use scenario::{DEFAULT_SCENE, Scenario};
pub use spraysim_engine::SimulationConfig;
