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
    /// The specified thickness band `[min, max]`, m: the metrics report the share of the area
    /// within it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<[f64; 2]>,
    /// Cells closer than this to the surface's edges or openings are left out of the thickness
    /// statistics, m.
    pub margin: f64,
    /// Impact parameters of this target, where they differ from the process's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub impact: Option<ImpactParams>,
}

/// The geometry of a target.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum TargetShape {
    /// A rectangle with a regular heightfield, optionally with openings.
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
        /// Openings cut out of the face (`[[target.opening]]`).
        #[serde(rename = "opening", skip_serializing_if = "Vec::is_empty")]
        openings: Vec<OpeningParams>,
    },
    /// A cylindrical shell with a heightfield on its unrolled surface: a tunnel lining, a
    /// shaft, a pipe, a tank.
    Cylinder {
        /// Centre of the axis segment, m.
        center: [f64; 3],
        /// Direction of the axis.
        axis: [f64; 3],
        /// Radius, m.
        radius: f64,
        /// Length along the axis, m.
        length: f64,
        /// `[start, end]` about the axis, degrees, from `reference` towards `reference × axis`.
        angles: [f64; 2],
        /// Direction of angle 0 (made perpendicular to the axis).
        reference: [f64; 3],
        /// `"inside"` (a lining) or `"outside"` (a tank) receives the spray.
        side: ShellSide,
        /// Heightfield cells `[around, along]`.
        resolution: [u32; 2],
        /// Radius over which each stuck particle's volume is spread, m (0: one cell).
        splat_radius: f64,
        /// What the shell's edges do to a slumping layer.
        edges: Edges,
    },
    /// A triangle mesh from a file, with a thickness per triangle.
    Mesh {
        /// The file and its placement.
        #[serde(flatten)]
        mesh: MeshParams,
        /// `"front"`: the side each triangle's normal points to (right-handed in its corners, the
        /// outside of a closed STL or OBJ) receives the spray; `"back"`: the other.
        side: MeshSide,
    },
}

/// Which side of a cylindrical shell receives spray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ShellSide {
    /// The inside: a tunnel lining, a shaft.
    #[default]
    Inside,
    /// The outside: a tank, a pipe.
    Outside,
}

choices!(ShellSide { "inside" => ShellSide::Inside, "outside" => ShellSide::Outside });

/// Which side of a mesh's triangles receives spray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MeshSide {
    /// The side the triangles' normals point to.
    #[default]
    Front,
    /// The other side.
    Back,
}

choices!(MeshSide { "front" => MeshSide::Front, "back" => MeshSide::Back });

/// An opening cut out of a rectangle target, in the face's coordinates: m right of and up from
/// its centre.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum OpeningParams {
    /// A rectangle (a window, a door).
    Rectangle {
        /// Centre, `[right, up]` from the face's centre, m.
        center: [f64; 2],
        /// `[width, height]`, m.
        size: [f64; 2],
    },
    /// A polygon (a box-out), corners in order.
    Polygon {
        /// Corners, `[right, up]` from the face's centre, m.
        corners: Vec<[f64; 2]>,
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
    /// `[width, height]` of the target's unrolled surface, m: a rectangle's size, a shell's arc
    /// length and length, a mesh's extent on its mean plane (see [`mean_plane`]).
    pub fn size(&self) -> [f64; 2] {
        match &self.shape {
            TargetShape::Rectangle { size, .. } => *size,
            TargetShape::Cylinder { radius, length, angles, .. } => {
                [radius * (angles[1] - angles[0]).to_radians(), *length]
            }
            TargetShape::Mesh { mesh, .. } => mean_plane(&mesh.triangles).3,
        }
    }
}

/// The plane a mesh mostly faces: its centre (of the mesh's extent on the plane, on the plane
/// through its farthest point along the normal), the unit normal (the area-weighted mean of
/// the triangles'), a unit direction in the plane (up: +z projected, or +x for a mesh facing up
/// or down), and the extent `[width, height]` of the mesh on it, m.
pub fn mean_plane(triangles: &[Triangle]) -> (DVec3, DVec3, DVec3, [f64; 2]) {
    let weighted = triangles.iter().map(|t| t.normal * t.area()).sum::<DVec3>();
    let normal = weighted.try_normalize().unwrap_or(DVec3::Z);
    let z = DVec3::Z - normal * normal.z;
    let up = if z.length() > 0.1 { z.normalize() } else { (DVec3::X - normal * normal.x).normalize() };
    let right = up.cross(normal);
    let corners = triangles.iter().flat_map(|t| t.corners);
    let (lo, hi) = corners.fold(([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]), |(lo, hi), p| {
        let q = [p.dot(right), p.dot(up), p.dot(normal)];
        (std::array::from_fn(|k| lo[k].min(q[k])), std::array::from_fn(|k| hi[k].max(q[k])))
    });
    let mid = |k: usize| 0.5 * (lo[k] + hi[k]);
    let centre = right * mid(0) + up * mid(1) + normal * hi[2];
    (centre, normal, up, [hi[0] - lo[0], hi[1] - lo[1]])
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum TargetKind {
    Rectangle,
    Cylinder,
    Mesh,
}

choices!(TargetKind {
    "rectangle" => TargetKind::Rectangle,
    "cylinder" => TargetKind::Cylinder,
    "mesh" => TargetKind::Mesh,
});

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
/// Longest name of a target or obstacle, characters.
pub const MAX_NAME: usize = 64;

fn name(s: &Section<'_>, seen: &mut Vec<String>) -> Read<String> {
    let n = s.string("name", None)?;
    let key = s.key("name");
    if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return bad(&key, format!("must be non-empty and use only letters, digits, '-' and '_', got {n:?}"));
    }
    if n.len() > MAX_NAME {
        // The name begins output file names (`NAME_thickness.npy`), which file systems cap at
        // 255 bytes: refused now rather than after the run.
        return bad(&key, format!("must be at most {MAX_NAME} characters, got {}", n.len()));
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

/// Reads a `[[target]]`; a mesh is read from `base`.
pub(crate) fn read_target(
    s: &Section<'_>,
    seen: &mut Vec<String>,
    process: &ImpactParams,
    preset: &ImpactDefaults,
    base: &Path,
) -> Read<TargetParams> {
    let name = name(s, seen)?;
    let role = s.choice("role", Some(Role::Substrate))?;
    let kind = s.choice("shape", Some(TargetKind::Rectangle))?;
    let shape = match kind {
        TargetKind::Rectangle => read_rectangle(s)?,
        TargetKind::Cylinder => read_cylinder(s)?,
        TargetKind::Mesh => {
            TargetShape::Mesh { mesh: read_mesh(s, base)?, side: s.choice("side", Some(MeshSide::Front))? }
        }
    };
    let coating = s.number("coating", Some(0.0), Check::Within(0.0, 1.0), "m")?;
    let tolerance = if s.has("tolerance") {
        let band = s.numbers("tolerance", None, Check::Within(0.0, 100.0), "m")?;
        if band[0] > band[1] {
            return bad(&s.key("tolerance"), format!("must be [min, max] with min ≤ max, got {band:?}"));
        }
        Some(band)
    } else {
        None
    };
    let margin = s.number("margin", Some(0.0), Check::Within(0.0, 1e3), "m")?;
    let impact = impact_override(s, process, preset)?;
    s.finish(&format!("a {} target", kind.name()))?;
    Ok(TargetParams { name, role, shape, coating, tolerance, margin, impact })
}

/// Heightfield cells `[cols, rows]`, whole numbers in 1–4096.
fn resolution(s: &Section<'_>, default: [f64; 2]) -> Read<[u32; 2]> {
    let [cols, rows] =
        s.numbers("resolution", Some(default), Check::Within(1.0, 4096.0), "cells per side")?;
    if cols.fract() != 0.0 || rows.fract() != 0.0 {
        return bad(&s.key("resolution"), format!("must be whole numbers of cells, got [{cols}, {rows}]"));
    }
    Ok([cols as u32, rows as u32])
}

/// The splat radius for a grid of `size` (m) and `resolution`: at most half the smaller side
/// and 32 cells.
fn splat_radius(s: &Section<'_>, size: [f64; 2], resolution: [u32; 2]) -> Read<f64> {
    let r = s.number("splat_radius", Some(0.0), Check::Within(0.0, size[0].min(size[1]) / 2.0), "m")?;
    let cells = r / (size[0] / f64::from(resolution[0])).min(size[1] / f64::from(resolution[1]));
    if cells > 32.0 {
        return bad(&s.key("splat_radius"), "spans more than 32 cells; lower it or the resolution");
    }
    Ok(r)
}

fn read_rectangle(s: &Section<'_>) -> Read<TargetShape> {
    let center = s.point("center", None)?;
    let normal = s.direction("normal", None)?;
    let up = s.direction("up", None)?;
    not_parallel(&s.key("up"), up, normal, "normal")?;
    let size = s.numbers("size", None, Check::Positive(1e3), "m")?;
    let resolution = resolution(s, [1024.0, 1024.0])?;
    let splat_radius = splat_radius(s, size, resolution)?;
    let edges = s.choice("edges", Some(Edges::Free))?;
    let openings = s.tables("opening")?.iter().map(|o| read_opening(o, size)).collect::<Read<Vec<_>>>()?;
    Ok(TargetShape::Rectangle { center, normal, up, size, resolution, splat_radius, edges, openings })
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum OpeningKind {
    Rectangle,
    Polygon,
}

choices!(OpeningKind { "rectangle" => OpeningKind::Rectangle, "polygon" => OpeningKind::Polygon });

/// Reads one `[[target.opening]]` of a face of `size` (m).
fn read_opening(s: &Section<'_>, size: [f64; 2]) -> Read<OpeningParams> {
    let o = match s.choice("shape", Some(OpeningKind::Rectangle))? {
        OpeningKind::Rectangle => OpeningParams::Rectangle {
            center: s.numbers("center", None, Check::Within(-1e3, 1e3), "m")?,
            size: s.numbers("size", None, Check::Positive(1e3), "m")?,
        },
        OpeningKind::Polygon => {
            let corners = s.pairs("corners", None, 1024)?;
            if corners.len() < 3 {
                return bad(&s.key("corners"), "must list at least 3 corners");
            }
            OpeningParams::Polygon { corners }
        }
    };
    let polygon = opening(&o);
    let is_rectangle = matches!(o, OpeningParams::Rectangle { .. });
    if polygon.area() <= 1e-12 {
        return bad(&s.key(if is_rectangle { "size" } else { "corners" }), "must enclose an area");
    }
    // Some of the opening must lie on the face: a corner on it, a face corner in it, or an
    // edge across it (a slot from side to side).
    let (hw, hh) = (size[0] / 2.0, size[1] / 2.0);
    let n = polygon.corners.len();
    let on_face = polygon.corners.iter().any(|&(u, v)| u.abs() < hw && v.abs() < hh)
        || [(-hw, -hh), (hw, -hh), (hw, hh), (-hw, hh)].iter().any(|&(u, v)| polygon.contains(u, v))
        || (0..n).any(|k| crosses_box(polygon.corners[k], polygon.corners[(k + 1) % n], hw, hh));
    if !on_face {
        return bad(
            &s.key(if is_rectangle { "center" } else { "corners" }),
            "puts the opening outside the face",
        );
    }
    s.finish("an opening")?;
    Ok(o)
}

/// True if the segment `a → b` passes through the open box |u| < `hw`, |v| < `hh`
/// (Liang–Barsky clipping).
fn crosses_box(a: (f64, f64), b: (f64, f64), hw: f64, hh: f64) -> bool {
    let (du, dv) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-du, a.0 + hw), (du, hw - a.0), (-dv, a.1 + hh), (dv, hh - a.1)] {
        if p == 0.0 {
            if q <= 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 < t1
}

/// The engine's polygon of an opening.
pub fn opening(o: &OpeningParams) -> spraysim_engine::deposit::Opening {
    use spraysim_engine::deposit::Opening;
    match o {
        OpeningParams::Rectangle { center, size } => {
            Opening::rectangle((center[0], center[1]), (size[0], size[1]))
        }
        OpeningParams::Polygon { corners } => {
            Opening { corners: corners.iter().map(|c| (c[0], c[1])).collect() }
        }
    }
}

fn read_cylinder(s: &Section<'_>) -> Read<TargetShape> {
    let center = s.point("center", None)?;
    let axis = s.direction("axis", None)?;
    let radius = s.number("radius", None, Check::Positive(1e3), "m")?;
    let length = s.number("length", None, Check::Positive(1e4), "m")?;
    let angles = s.numbers("angles", Some([0.0, 360.0]), Check::Within(-720.0, 720.0), "degrees")?;
    if angles[1] <= angles[0] || angles[1] - angles[0] > 360.0 {
        let message = format!("must be [start, end] with start < end ≤ start + 360, got {angles:?}");
        return bad(&s.key("angles"), message);
    }
    // Angle 0 horizontal across the axis by default, so that 90° is straight up.
    let a = DVec3::from_array(axis).normalize();
    let default = if a.cross(DVec3::Z).length() > 1e-6 { a.cross(DVec3::Z).normalize() } else { DVec3::X };
    let reference = s.direction("reference", Some(default.to_array()))?;
    not_parallel(&s.key("reference"), reference, axis, "axis")?;
    let side = s.choice("side", Some(ShellSide::Inside))?;
    let resolution = resolution(s, [1024.0, 512.0])?;
    let size = [radius * (angles[1] - angles[0]).to_radians(), length];
    let splat_radius = splat_radius(s, size, resolution)?;
    let edges = s.choice("edges", Some(Edges::Free))?;
    Ok(TargetShape::Cylinder {
        center,
        axis,
        radius,
        length,
        angles,
        reference,
        side,
        resolution,
        splat_radius,
        edges,
    })
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
