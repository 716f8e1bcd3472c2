//! `[[obstacle]]`: surfaces without a deposit (rebar, formwork, a floor), tagged by `shape`.
//!
//! Each shape is a file here declaring its keys (units and defaults in its reader), how it is
//! written back (its `Serialize`) and the engine shapes it builds; the list in [`ObstacleShape`]
//! names each once. A new shape is its file, its `mod` line and its line in that list.

mod cylinder;
mod disk;
mod face;
#[cfg(test)]
mod ledge;
mod mesh;
mod oriented_box;
mod plane;
mod sphere;

pub use cylinder::CylinderObstacle;
pub use disk::DiskObstacle;
pub use face::FaceObstacle;
pub use oriented_box::BoxObstacle;
pub use plane::PlaneObstacle;
pub use sphere::SphereObstacle;

use super::mesh::MeshParams;
use super::process::ImpactParams;
use super::registry::kinds;
use super::surface::{impact_override, name};
use crate::budget::Storage;
use crate::reader::{Choice, Read, Section};
use serde::Serialize;
use spraysim_engine::collision::{Aabb, Primitive, Shape};
use std::path::Path;

/// What each obstacle shape declares besides its keys: the engine's collision shapes it
/// builds, and what follows from them.
pub(crate) trait ObstacleGeometry {
    /// Reads the shape's keys from `s`; a file it names is read relative to `base`.
    fn read(s: &Section<'_>, base: &Path) -> Read<Self>
    where
        Self: Sized;

    /// The engine's collision shapes of the obstacle (one, or a mesh's triangles).
    fn shapes(&self) -> Vec<Shape>;

    /// Bounding box of its bounded shapes, m (`None` when all are unbounded, as a plane is):
    /// by default, of the boxes [`Primitive::aabb`] gives for [`ObstacleGeometry::shapes`].
    fn bounds(&self) -> Option<Aabb> {
        self.shapes().iter().filter_map(Primitive::aabb).reduce(Aabb::union)
    }

    /// The memory it takes in a run beyond a few shapes, for the budget (`None`: none worth
    /// counting).
    fn storage(&self) -> Option<Storage> {
        None
    }
}

kinds! {
    /// The geometry of an obstacle; positions and sizes in m.
    pub enum ObstacleShape, tagged "shape", kinds ObstacleKind, read with &Path, as dyn ObstacleGeometry {
        /// An infinite plane.
        "plane" => Plane(PlaneObstacle),
        /// A rectangle.
        "face" => Face(FaceObstacle),
        /// A flat disk.
        "disk" => Disk(DiskObstacle),
        /// A solid sphere.
        "sphere" => Sphere(SphereObstacle),
        /// A solid box on axes of its own.
        "box" => Box(BoxObstacle),
        /// A solid cylinder with flat caps (rebar).
        "cylinder" => Cylinder(CylinderObstacle),
        /// A triangle mesh from a file.
        "mesh" => Mesh(MeshParams),
        /// A shape only the tests know: it shows that a new shape is its file and this line.
        #[cfg(test)]
        "ledge" => Ledge(ledge::LedgeObstacle),
    }
}

/// One `[[obstacle]]`: a surface without a deposit (rebar, formwork, a floor).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObstacleParams {
    /// Name, used in metrics (letters, digits, `-` and `_`).
    pub name: String,
    /// Geometry: `shape` and its keys.
    #[serde(flatten)]
    pub shape: ObstacleShape,
    /// Impact parameters of this obstacle, where they differ from the process's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub impact: Option<ImpactParams>,
}

impl ObstacleShape {
    /// The engine's collision shapes of this obstacle.
    pub fn shapes(&self) -> Vec<Shape> {
        self.as_dyn().shapes()
    }

    /// Bounding box of its bounded shapes, m; `None` for an unbounded one (a plane).
    pub fn bounds(&self) -> Option<Aabb> {
        self.as_dyn().bounds()
    }
}

/// Reads an `[[obstacle]]` (its `name` added to `seen`); a mesh is read from `base`.
pub(crate) fn read_obstacle(
    s: &Section<'_>,
    seen: &mut Vec<String>,
    process: &ImpactParams,
    base: &Path,
) -> Read<ObstacleParams> {
    let name = name(s, seen)?;
    let kind = s.choice::<ObstacleKind>("shape", None)?;
    let shape = ObstacleShape::read(kind, s, base).map_err(|mut e| {
        if e.message == "is required" {
            e.message = format!("is required for a {} obstacle", kind.name());
        }
        e
    })?;
    let impact = impact_override(s, process)?;
    s.finish(&format!("a {} obstacle", kind.name()))?;
    Ok(ObstacleParams { name, shape, impact })
}
