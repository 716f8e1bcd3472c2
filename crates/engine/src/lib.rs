//! # spraysim-engine
//!
//! The particle engine of spraysim, a simulator of construction spraying processes (shotcrete,
//! spray painting, abrasive blasting) after Yazdi Samadi et al.: one engine whose processes
//! differ only in parameters. SI units throughout (m, s, kg), z up, gravity −9.81 m/s² along z;
//! angles are in radians in code.
//!
//! The engine knows no file format. A [`SimulationConfig`] holds every resolved parameter as
//! plain data; [`Simulation::new`] builds the data sets from it, and [`Simulation::step`] runs
//! the stages of one time step over them (see [`pipeline`]). Layers, from the bottom:
//!
//! - [`particles`]: structure-of-arrays particle storage and per-particle random streams;
//! - [`motion`]: flight under gravity and drag; [`tally`]: running totals;
//! - [`collision`]: the shapes particles strike (one file each, behind the [`collision::Primitive`]
//!   trait), exact ballistic arcs and the grid broad phase;
//! - [`deposit`]: surfaces that collect material (the [`deposit::DepositSurface`] trait; a
//!   rectangle with a heightfield today);
//! - [`emission`]: the nozzle's path and its emitter;
//! - [`process`]: process behaviour as small modules tagged by stage: per impact (rebound laws,
//!   erosion laws, the impact model) and per layer (cohesion, drip);
//! - [`world`]: what has happened on each target and obstacle; [`events`]: the observer seam;
//! - [`config`]: the resolved parameters; [`pipeline`]: the [`Simulation`] and its stages;
//! - [`metrics`]: the results of a run so far.
//!
//! ```
//! use spraysim_engine::{SimulationConfig, Simulation};
//!
//! let config = SimulationConfig::example_wall(0.05); // 50 ms of shotcrete onto a wall
//! let mut sim = Simulation::new(config)?;
//! sim.run(|_| {});
//! let m = sim.metrics();
//! assert_eq!(m.emitted.count, m.fates.total().count);
//! # Ok::<(), spraysim_engine::SetupError>(())
//! ```

pub mod checkpoint;
pub mod collision;
pub mod config;
pub mod deposit;
pub mod emission;
pub mod events;
pub mod metrics;
pub mod motion;
pub mod particles;
pub mod pipeline;
pub mod process;
pub mod tally;
pub mod world;

pub use config::SimulationConfig;
pub use metrics::Metrics;
pub use pipeline::{SetupError, Simulation, check_threads, max_threads};
