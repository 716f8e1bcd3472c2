//! The sections of a resolved scenario: every parameter with its unit, as plain data whose
//! types rule out impossible combinations (a tagged enum wherever a key like `shape` decides
//! which other keys apply). Each section's reader checks every value as it reads it.

mod emitter;
mod nozzle;
mod process;
mod run;
mod surfaces;

pub use emitter::{Aperture, DirectionLaw, EmitterParams};
pub(crate) use emitter::{ApertureKind, DirectionKind, EmitterDefaults};
pub use nozzle::{NozzleMotion, NozzleParams, RasterParams, WaypointParams};
pub use process::{
    CohesionParams, ErosionParams, FinnieLayer, ImpactParams, OkaLayer, Preset, ProcessParams, ReboundParams,
    SlumpParams, WindowParams,
};
pub(crate) use process::{
    ErosionDefaults, ErosionKind, ImpactDefaults, LayerDefaults, ProcessDefaults, ReboundKind,
};
pub use run::{Colormap, DomainParams, ExportFormat, OutputParams, SimulationParams};
pub use surfaces::{
    Edges, MeshParams, MeshSide, ObstacleParams, ObstacleShape, OpeningParams, ShellSide, TargetParams,
    TargetShape, mean_plane, opening,
};

pub(crate) mod read {
    //! The section readers.
    pub(crate) use super::emitter::read as emitter;
    pub(crate) use super::nozzle::read as nozzle;
    pub(crate) use super::process::read as process;
    pub(crate) use super::run::{
        read_domain as domain, read_output as output, read_simulation as simulation,
    };
    pub(crate) use super::surfaces::{read_obstacle as obstacle, read_target as target};
}
