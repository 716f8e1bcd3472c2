//! `[[target]]` and `[[obstacle]]`: the surfaces particles strike, tagged by `shape`.

use super::process::{ImpactDefaults, ImpactParams, read_impact};
use crate::reader::{Check, Choice, Read, Section, bad, choices};
use glam::DVec3;
use serde::Serialize;
use spraysim_engine::collision::Triangle;
use spraysim_engine::world::Role;
use std::path::Path;
use std::sync::Arc;

choices!(Role { "substrate" => Role::Substrate, "collector" => Role::Collector });

/// One `[[target]]`: a surface that records deposition.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TargetParams {
    /// Name, used for output files (letters, digits, `-` and `_`).
    pub name: String,
    /// `"substrate"` or `"collector"`.
    pub role: Role,
    /// Geometry and deposit grid.
    #[serde(flatten)]
    pub shape: TargetShape,
    /// Thickness of a coating on the surface at the start, which erosion removes, m.
    pub coating: f64,
    /// Impact parameters of this target, where they differ from the process's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub impact: Option<ImpactParams>,
}

/// The geometry of a target.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum TargetShape {
    /// A rectangle with a regular heightfield.
    Rectangle {
        /// Centre, m.
        center: [f64; 3],
        /// Normal, towards the side that receives spray.
        normal: [f64; 3],
        /// A direction in the face (made perpendicular to `normal`); rows grow along it.
        up: [f64; 3],
        /// `[width, height]`, m; width along `up × normal`, height along `up`.
        size: [f64; 2],
        /// Heightfield cells `[cols, rows]`.
        resolution: [u32; 2],
        /// Radius over which each stuck particle's volume is spread, m (0: one cell).
        splat_radius: f64,
        /// `"free"`: a slumping layer runs off over the edges; `"held"`: formwork (or a floor
        /// under a wall) holds it.
        edges: Edges,
    },
}

/// What a target's edges do to a slumping layer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Edges {
    /// The layer runs off over them.
    #[default]
    Free,
    /// Formwork, or a floor under a wall, holds it.
    Held,
}

choices!(Edges { "free" => Edges::Free, "held" => Edges::Held });

impl TargetParams {
    /// `[width, height]` of the target's face, m.
    pub fn size(&self) -> [f64; 2] {
        match &self.shape {
            TargetShape::Rectangle { size, .. } => *size,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TargetKind {
    Rectangle,
}

choices!(TargetKind { "rectangle" => TargetKind::Rectangle });

/// One `[[obstacle]]`: a surface without a deposit (rebar, formwork, a floor).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ObstacleParams {
    /// Name, used in metrics.
    pub name: String,
    /// Geometry.
    #[serde(flatten)]
    pub shape: ObstacleShape,
    /// Impact parameters of this obstacle, where they differ from the process's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub impact: Option<ImpactParams>,
}

/// The geometry of an obstacle; positions and sizes in m.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum ObstacleShape {
    /// Infinite plane through `center`.
    Plane {
        /// A point on the plane.
        center: [f64; 3],
        /// Normal.
        normal: [f64; 3],
    },
    /// Rectangle.
    Face {
        /// Centre.
        center: [f64; 3],
        /// Normal.
        normal: [f64; 3],
        /// A direction in the face.
        up: [f64; 3],
        /// `[width, height]`.
        size: [f64; 2],
    },
    /// Disk.
    Disk {
        /// Centre.
        center: [f64; 3],
        /// Normal.
        normal: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// Solid sphere.
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// Solid box with local axes.
    Box {
        /// Centre.
        center: [f64; 3],
        /// Full size along the local axes.
        size: [f64; 3],
        /// Local x axis.
        x_axis: [f64; 3],
        /// Local y axis (made perpendicular to `x_axis`).
        y_axis: [f64; 3],
    },
    /// Solid capped cylinder (rebar).
    Cylinder {
        /// First cap centre.
        start: [f64; 3],
        /// Second cap centre.
        end: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// Triangle mesh from a file.
    Mesh(MeshParams),
}

/// A triangle mesh read from an STL or OBJ file and placed in the scene: each vertex `p` of the
/// file goes to `R · (scale · p) + translate`, with `R` the rotation by `rotate`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshParams {
    /// The file (`.stl` or `.obj`); the resolved scenario holds its absolute path.
    pub file: String,
    /// Factor from the file's units to metres (0.001 for millimetres).
    pub scale: f64,
    /// Rotation, degrees about x, then y, then z (fixed axes).
    pub rotate: [f64; 3],
    /// Translation after scaling and rotating, m.
    pub translate: [f64; 3],
    /// The placed triangles.
    #[serde(skip)]
    pub triangles: Arc<Vec<Triangle>>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ObstacleKind {
    Plane,
    Face,
    Disk,
    Sphere,
    Box,
    Cylinder,
    Mesh,
}

choices!(ObstacleKind {
    "plane" => ObstacleKind::Plane,
    "face" => ObstacleKind::Face,
    "disk" => ObstacleKind::Disk,
    "sphere" => ObstacleKind::Sphere,
    "box" => ObstacleKind::Box,
    "cylinder" => ObstacleKind::Cylinder,
    "mesh" => ObstacleKind::Mesh,
});

/// Checks a name: non-empty, file-name safe, unique among `seen`.
fn name(s: &Section<'_>, seen: &mut Vec<String>) -> Read<String> {
    let n = s.string("name", None)?;
    let key = s.key("name");
    if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return bad(&key, format!("must be non-empty and use only letters, digits, '-' and '_', got {n:?}"));
    }
    if seen.contains(&n) {
        return bad(&key, format!("{n:?} is used twice; names must be unique"));
    }
    seen.push(n.clone());
    Ok(n)
}

/// Two directions that are not parallel (sine of their angle above 1e-6).
fn not_parallel(key: &str, a: [f64; 3], b: [f64; 3], what: &str) -> Read<()> {
    let (a, b) = (DVec3::from_array(a).normalize(), DVec3::from_array(b).normalize());
    if a.cross(b).length() < 1e-6 {
        return bad(key, format!("must not be parallel to {what}"));
    }
    Ok(())
}

/// A surface's own impact table, laid over the process's.
fn impact_override(
    s: &Section<'_>,
    process: &ImpactParams,
    preset: &ImpactDefaults,
) -> Read<Option<ImpactParams>> {
    s.table("impact")?.map(|t| read_impact(&t, &ImpactDefaults::over(process, preset))).transpose()
}

/// Reads a `[[target]]`.
pub(crate) fn read_target(
    s: &Section<'_>,
    seen: &mut Vec<String>,
    process: &ImpactParams,
    preset: &ImpactDefaults,
) -> Read<TargetParams> {
    let name = name(s, seen)?;
    let role = s.choice("role", Some(Role::Substrate))?;
    let kind = s.choice("shape", Some(TargetKind::Rectangle))?;
    let shape = match kind {
        TargetKind::Rectangle => read_rectangle(s)?,
    };
    let coating = s.number("coating", Some(0.0), Check::Within(0.0, 1.0), "m")?;
    let impact = impact_override(s, process, preset)?;
    s.finish(&format!("a {} target", kind.name()))?;
    Ok(TargetParams { name, role, shape, coating, impact })
}

fn read_rectangle(s: &Section<'_>) -> Read<TargetShape> {
    let center = s.point("center", None)?;
    let normal = s.direction("normal", None)?;
    let up = s.direction("up", None)?;
    not_parallel(&s.key("up"), up, normal, "normal")?;
    let size = s.numbers("size", None, Check::Positive(1e3), "m")?;
    let [cols, rows] =
        s.numbers("resolution", Some([1024.0, 1024.0]), Check::Within(1.0, 4096.0), "cells per side")?;
    if cols.fract() != 0.0 || rows.fract() != 0.0 {
        return bad(&s.key("resolution"), format!("must be whole numbers of cells, got [{cols}, {rows}]"));
    }
    let resolution = [cols as u32, rows as u32];
    let splat_radius =
        s.number("splat_radius", Some(0.0), Check::Within(0.0, size[0].min(size[1]) / 2.0), "m")?;
    let cells = splat_radius / (size[0] / cols).min(size[1] / rows);
    if cells > 32.0 {
        return bad(&s.key("splat_radius"), "spans more than 32 cells; lower it or the resolution");
    }
    let edges = s.choice("edges", Some(Edges::Free))?;
    Ok(TargetShape::Rectangle { center, normal, up, size, resolution, splat_radius, edges })
}

/// Reads an `[[obstacle]]`; a mesh is read from `base`.
pub(crate) fn read_obstacle(
    s: &Section<'_>,
    seen: &mut Vec<String>,
    process: &ImpactParams,
    preset: &ImpactDefaults,
    base: &Path,
) -> Read<ObstacleParams> {
    let name = name(s, seen)?;
    let kind = s.choice::<ObstacleKind>("shape", None)?;
    let shape = read_obstacle_shape(s, kind, base).map_err(|mut e| {
        if e.message == "is required" {
            e.message = format!("is required for a {} obstacle", kind.name());
        }
        e
    })?;
    let impact = impact_override(s, process, preset)?;
    s.finish(&format!("a {} obstacle", kind.name()))?;
    Ok(ObstacleParams { name, shape, impact })
}

fn read_obstacle_shape(s: &Section<'_>, kind: ObstacleKind, base: &Path) -> Read<ObstacleShape> {
    let radius = || s.number("radius", None, Check::Positive(1e3), "m");
    Ok(match kind {
        ObstacleKind::Plane => {
            ObstacleShape::Plane { center: s.point("center", None)?, normal: s.direction("normal", None)? }
        }
        ObstacleKind::Face => {
            let (center, normal, up) =
                (s.point("center", None)?, s.direction("normal", None)?, s.direction("up", None)?);
            not_parallel(&s.key("up"), up, normal, "normal")?;
            ObstacleShape::Face {
                center,
                normal,
                up,
                size: s.numbers("size", None, Check::Positive(1e4), "m")?,
            }
        }
        ObstacleKind::Disk => ObstacleShape::Disk {
            center: s.point("center", None)?,
            normal: s.direction("normal", None)?,
            radius: radius()?,
        },
        ObstacleKind::Sphere => ObstacleShape::Sphere { center: s.point("center", None)?, radius: radius()? },
        ObstacleKind::Box => {
            let center = s.point("center", None)?;
            let size = s.numbers("size", None, Check::Positive(1e4), "m")?;
            let x_axis = s.direction("x_axis", Some([1.0, 0.0, 0.0]))?;
            let y_axis = s.direction("y_axis", Some([0.0, 1.0, 0.0]))?;
            not_parallel(&s.key("y_axis"), y_axis, x_axis, "x_axis")?;
            ObstacleShape::Box { center, size, x_axis, y_axis }
        }
        ObstacleKind::Cylinder => {
            let (start, end) = (s.point("start", None)?, s.point("end", None)?);
            if DVec3::from_array(start).distance(DVec3::from_array(end)) < 1e-9 {
                return bad(&s.key("end"), "must differ from start");
            }
            ObstacleShape::Cylinder { start, end, radius: radius()? }
        }
        ObstacleKind::Mesh => ObstacleShape::Mesh(read_mesh(s, base)?),
    })
}

/// Reads and loads a mesh: `file` relative to `base`, `scale`, `rotate`, `translate`.
pub(crate) fn read_mesh(s: &Section<'_>, base: &Path) -> Read<MeshParams> {
    let file = s.string("file", None)?;
    let scale = s.number("scale", Some(1.0), Check::Positive(1e6), "")?;
    let rotate = s.numbers("rotate", Some([0.0; 3]), Check::Within(-360.0, 360.0), "degrees")?;
    let translate = s.point("translate", Some([0.0; 3]))?;
    let path = base.join(&file);
    let path = std::path::absolute(&path).unwrap_or(path);
    let triangles = crate::mesh::load(&path, scale, rotate, translate).map_err(|e| {
        crate::reader::Invalid { key: s.key("file"), message: format!("cannot be used: {e}") }
    })?;
    Ok(MeshParams {
        file: path.display().to_string(),
        scale,
        rotate,
        translate,
        triangles: Arc::new(triangles),
    })
}
