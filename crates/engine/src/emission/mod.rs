//! Where particles come from: the nozzle's path and pose, and the emitter that samples start
//! positions and velocities in the nozzle's frame.

mod droplets;
mod emitter;
mod nozzle;
mod paths;

pub use droplets::{DropletSizes, SizeDistribution, TABLE as SIZE_TABLE};
pub use emitter::{
    Aperture, Direction, Emitter, Sampler, inverse_normal_cdf, normal_cdf, normal_sf, truncated_normal_mass,
    truncated_normal_unit,
};
pub use nozzle::{Circle, NozzleFrame, NozzlePath, Waypoint, slerp};
pub use paths::{PassDirection, RasterPlan, circling, raster, raster_waypoints};
