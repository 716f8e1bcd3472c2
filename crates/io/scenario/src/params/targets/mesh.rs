//! `shape = "mesh"`: a triangle mesh from an STL or OBJ file, with a thickness per triangle (a
//! door panel, a car body part).

use super::{RasterChart, TargetGeometry};
use crate::budget::{PER_TRIANGLE, Storage};
use crate::params::DirectionLaw;
use crate::params::mesh::{MeshParams, read_mesh};
use crate::reader::{Read, Section, choices};
use crate::sanity::EnclosingBox;
use crate::scenario::Scenario;
use glam::DVec3;
use serde::Serialize;
use spraysim_engine::collision::{Face, Triangle};
use spraysim_engine::deposit::{MeshSurface, Surface};
use std::path::Path;

/// A triangle mesh from a file, with a thickness per triangle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshTarget {
    /// The file and its placement.
    #[serde(flatten)]
    pub mesh: MeshParams,
    /// `"front"`: the side each triangle's normal points to (right-handed in its corners, the
    /// outside of a closed STL or OBJ) receives the spray; `"back"`: the other.
    pub side: MeshSide,
}

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

impl TargetGeometry for MeshTarget {
    fn read(s: &Section<'_>, base: &Path) -> Read<Self> {
        Ok(MeshTarget { mesh: read_mesh(s, base)?, side: s.choice("side", Some(MeshSide::Front))? })
    }

    /// The mesh's extent on its mean plane (see [`mean_plane`]), m.
    fn size(&self) -> [f64; 2] {
        mean_plane(&self.mesh.triangles).3
    }

    fn surface(&self) -> Surface {
        let triangles: Vec<Triangle> = (self.mesh.triangles.iter())
            .map(|&t| match self.side {
                MeshSide::Front => t,
                MeshSide::Back => {
                    Triangle { corners: [t.corners[0], t.corners[2], t.corners[1]], normal: -t.normal }
                }
            })
            .collect();
        // A mesh file with no triangle is refused when read.
        Surface::Mesh(MeshSurface::new(triangles).unwrap_or_else(|e| unreachable!("checked when read: {e}")))
    }

    /// The plane the mesh mostly faces, on the receiving side.
    fn raster_chart(&self) -> Option<RasterChart> {
        let triangles = &self.mesh.triangles;
        let (centre, normal, up, size) = mean_plane(triangles);
        Some(if self.side == MeshSide::Back {
            // The plane touches the mesh on its back: the nozzle stands off behind it.
            let corners = triangles.iter().flat_map(|t| t.corners);
            let deepest = corners.map(|p| (p - centre).dot(normal)).fold(0.0, f64::min);
            RasterChart::Face(Face::new(centre + normal * deepest, -normal, up, size))
        } else {
            RasterChart::Face(Face::new(centre, normal, up, size))
        })
    }

    /// Every vertex, exactly.
    fn reach(&self) -> (Vec<[f64; 3]>, f64) {
        (self.mesh.triangles.iter().flat_map(|t| t.corners.map(|c| c.to_array())).collect(), 0.0)
    }

    /// The axis-aligned box of its vertices.
    fn enclosing_box(&self) -> EnclosingBox {
        let corners = self.mesh.triangles.iter().flat_map(|t| t.corners);
        let (min, max) =
            corners.fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)));
        EnclosingBox::aligned(min, max)
    }

    /// The sum of its triangles' areas.
    fn area(&self) -> f64 {
        self.mesh.triangles.iter().map(Triangle::area).sum()
    }

    fn cells(&self) -> u64 {
        self.mesh.triangles.len() as u64
    }

    fn storage(&self) -> Storage {
        let n = self.mesh.triangles.len() as f64;
        Storage { key: "file", what: format!("{n} triangles"), bytes: n * PER_TRIANGLE }
    }

    fn warnings(&self, name: &str, sc: &Scenario) -> Vec<String> {
        coarse_mesh(sc, name, &self.mesh.triangles).into_iter().collect()
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

/// A warning when a mesh's triangles are much larger than the spray's footprint: each triangle
/// holds the mean of the spray over it, so a footprint needs several triangles across.
fn coarse_mesh(sc: &Scenario, name: &str, triangles: &[Triangle]) -> Option<String> {
    let mut sizes: Vec<f64> = triangles.iter().map(|t| (2.0 * t.area()).sqrt()).collect();
    sizes.sort_by(f64::total_cmp);
    let median = *sizes.get(sizes.len() / 2)?;
    // The footprint's radius at the distance from the nozzle's start to the mesh's mean plane.
    let (centre, ..) = mean_plane(triangles);
    let nozzle = crate::build::nozzle_path(sc).at(0.0).0.position;
    let e = sc.emitter();
    let half = match e.direction {
        DirectionLaw::UniformPolar { cone_angle }
        | DirectionLaw::TruncatedNormal { cone_angle, .. }
        | DirectionLaw::UniformSolidAngle { cone_angle } => cone_angle / 2.0,
        DirectionLaw::Fan { fan_narrow_angle, .. } => fan_narrow_angle / 2.0,
    };
    let footprint = nozzle.distance(centre) * half.to_radians().tan().max(1e-3);
    (median > footprint).then(|| {
        format!(
            "target `{name}`: its triangles (median {median:.3} m across) are larger than the spray's footprint \
             (about {footprint:.3} m in radius): each holds the mean of the spray over it; remesh finer, to \
             about {:.3} m or less, for a thickness map",
            footprint / 3.0
        )
    })
}
