//! # spraysim
//!
//! A particle-system simulator of construction spraying processes (shotcrete, spray painting,
//! abrasive blasting) after Yazdi Samadi et al., one engine whose processes differ only in
//! parameters. SI units throughout (m, s, kg), z up, gravity −9.81 m/s² along z; angles are in
//! degrees in scenario files and radians in code.
//!
//! This crate gathers the layers a program needs (see `docs/architecture.md`):
//! - the engine ([`spraysim_engine`], re-exported at the top level: [`Simulation`],
//!   [`SimulationConfig`], and its modules [`collision`], [`deposit`], [`emission`],
//!   [`events`], [`process`], …);
//! - scenario files ([`scenario`]: [`Scenario`], presets, meshes, tool paths);
//! - outputs ([`output`]: `metrics.json`, arrays, heatmaps, written all or nothing);
//! - the choice of what flies the particles ([`backend`]: the CPU, or the GPU with the `gpu`
//!   feature).
//!
//! ```
//! use spraysim::{Scenario, Simulation};
//!
//! let scenario = Scenario::from_toml(
//!     r#"
//!     [simulation]
//!     duration = 0.2
//!     [process]
//!     preset = "painting"
//!     [nozzle]
//!     position = [-0.25, 0.0, 1.0]
//!     [[target]]
//!     name = "panel"
//!     center = [0.0, 0.0, 1.0]
//!     normal = [-1.0, 0.0, 0.0]
//!     up = [0.0, 0.0, 1.0]
//!     size = [1.0, 1.0]
//!     resolution = [128, 128]
//!     "#,
//!     "example",
//! )?;
//! let mut sim = Simulation::new(scenario.config())?;
//! sim.run(|_| {});
//! let m = sim.metrics();
//! assert_eq!(m.rebound_ratio, Some(0.0)); // painting: α = 0
//! let panel = &m.targets[0];
//! assert!((panel.layer_volume - panel.stuck.volume).abs() < 1e-9 * panel.stuck.volume);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod backend;

pub use spraysim_engine::*;
/// The GPU backend's crate (the `gpu` feature).
#[cfg(feature = "gpu")]
pub use spraysim_gpu as gpu;
pub use spraysim_output as output;
pub use spraysim_scenario as scenario;
pub use spraysim_scenario::{Scenario, ScenarioError};

/// The README's Rust code blocks, if any, compiled and run as doctests so that they cannot drift.
#[doc = include_str!("../../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The Rust example of `docs/usage.md` (spraysim from Rust), compiled and run as a doctest so
/// that it cannot drift.
#[doc = include_str!("../../../docs/usage.md")]
#[cfg(doctest)]
pub struct UsageDoctests;
