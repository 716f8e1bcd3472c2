//! # spraysim
//!
//! A particle-system simulator of construction spraying processes (shotcrete, spray painting,
//! abrasive blasting) after Yazdi Samadi et al., one engine whose processes differ only in
//! parameters. SI units throughout (m, s, kg), z up, gravity −9.81 m/s² along z; angles are in
//! degrees in scenario files and radians in code.
//!
//! Where things live:
//! - [`scenario`]: TOML scenarios, presets, validation;
//! - [`emitter`] and [`nozzle`]: where particles come from;
//! - [`swarm`]: particle storage (structure of arrays);
//! - [`integrator`]: flight under gravity and drag;
//! - [`collision`]: segment tests against planes, faces, disks, spheres, boxes, cylinders;
//! - [`impact`]: stick or rebound, restitution, scatter;
//! - [`heightfield`] and [`target`]: deposited layers and per-surface tallies;
//! - [`cohesion`]: cohesive failure of the deposited layer; [`erosion`]: abrasive wear;
//! - [`pipeline`]: the [`Simulation`] and its stages;
//! - [`metrics`] and [`io`]: results, files and heatmaps;
//! - [`calibration`]: fitting emitter parameters to a measured profile;
//! - [`validation`]: checks against closed forms and their report;
//! - [`mod@bench`]: the reference scene for performance measurements.
//!
//! ```
//! use spraysim::{Scenario, Simulation};
//!
//! let mut scenario = Scenario::from_toml(
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
//! let mut sim = Simulation::new(&scenario)?;
//! sim.run(|_| {});
//! let m = sim.metrics();
//! assert_eq!(m.rebound_ratio, Some(0.0)); // painting: α = 0
//! let panel = &sim.targets()[0];
//! assert!((panel.field.volume() - panel.stuck.volume).abs() < 1e-9 * panel.stuck.volume);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod bench;
pub mod calibration;
pub mod cohesion;
pub mod collision;
pub mod emitter;
pub mod erosion;
pub mod heightfield;
pub mod impact;
pub mod integrator;
pub mod io;
pub mod metrics;
pub mod nozzle;
pub mod pipeline;
pub mod rng;
pub mod scenario;
pub mod swarm;
pub mod target;
pub mod validation;

pub use metrics::Metrics;
pub use pipeline::{SetupError, Simulation};
pub use scenario::{Scenario, ScenarioError};
