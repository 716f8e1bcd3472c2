//! The sections of a resolved scenario: every parameter with its unit, as plain data whose
//! types rule out impossible combinations (a tagged enum wherever a key like `shape` decides
//! which other keys apply). Each section's reader checks every value as it reads it.
//!
//! The kinds a key chooses among (target shapes, obstacle shapes, rebound laws) are one file
//! each under `targets/`, `obstacles/` and `rebound/`, listed once per family with
//! [`registry::kinds!`](registry).

mod air;
mod emitter;
pub(crate) mod mesh;
mod nozzle;
mod obstacles;
mod process;
mod rebound;
pub(crate) mod registry;
mod render;
mod run;
mod surface;
mod targets;

pub(crate) use air::{AirDefaults, AirKind};
pub use air::{AirParams, DragLawName, JetParams};
pub use emitter::{Aperture, DirectionLaw, DropletsLaw, EmitterParams};
pub(crate) use emitter::{ApertureKind, DirectionKind, DropletsKind, EmitterDefaults};
pub use mesh::MeshParams;
pub(crate) use nozzle::LengthUnit;
pub use nozzle::{NozzleMotion, NozzleParams, RasterParams, WaypointParams};
pub use obstacles::{
    BoxObstacle, CylinderObstacle, DiskObstacle, FaceObstacle, ObstacleParams, ObstacleShape, PlaneObstacle,
    SphereObstacle,
};
pub use process::{
    CohesionParams, ErosionParams, FinnieLayer, ImpactParams, OkaLayer, Preset, ProcessParams, SlumpParams,
    WindowParams,
};
pub(crate) use process::{ErosionDefaults, ErosionKind, ImpactDefaults, LayerDefaults, ProcessDefaults};
pub(crate) use rebound::ReboundKind;
pub use rebound::{
    AlwaysLaw, CushionLaw, NeverLaw, PolynomialLaw, ReboundParams, SHOTCRETE_REBOUND_POLYNOMIAL,
};
pub use render::{ParticleColoring, RenderCamera, RenderParams, RenderTime, ViewPreset, point_size};
pub use run::{
    Backend, Colormap, DEFAULT_LAYER_EPOCH, DomainParams, ExportFormat, OutputParams, SimulationParams,
};
pub use targets::{
    CylinderTarget, Edges, MAX_SPLAT_CELLS, MeshSide, MeshTarget, OpeningParams, PARTICLES_PER_SPLAT,
    RectangleTarget, ShellSide, SplatRadius, TargetParams, TargetShape, mean_plane, opening,
};
pub(crate) use targets::{RasterChart, smallest_radius};

/// A point or vector of a file as the engine's vector.
pub(crate) fn v3(a: [f64; 3]) -> glam::DVec3 {
    glam::DVec3::from_array(a)
}

pub(crate) mod read {
    //! The section readers.
    pub(crate) use super::air::read as air;
    pub(crate) use super::emitter::read as emitter;
    pub(crate) use super::nozzle::read as nozzle;
    pub(crate) use super::obstacles::read_obstacle as obstacle;
    pub(crate) use super::process::read as process;
    pub(crate) use super::run::{
        read_domain as domain, read_output as output, read_simulation as simulation,
    };
    pub(crate) use super::targets::read_target as target;
}
