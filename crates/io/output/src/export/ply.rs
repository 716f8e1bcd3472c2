//! PLY: a deposit's mesh and the particles in flight as binary little-endian PLY.

use super::{Deposit, f32s};
use glam::DVec3;

/// Binary little-endian PLY: vertices with position (m), normal, thickness (m) and colour;
/// faces with their thickness (m) and impacts.
pub fn ply(d: &Deposit, name: &str) -> Vec<u8> {
    let m = &d.mesh;
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment spraysim deposit of {name}; lengths in m\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\nproperty float thickness\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\n\
         element face {}\nproperty list uchar uint vertex_indices\nproperty float thickness\n\
         property uint hits\nend_header\n",
        m.positions.len(),
        m.triangles.len()
    )
    .into_bytes();
    for (i, p) in m.positions.iter().enumerate() {
        for x in f32s(*p).into_iter().chain(f32s(m.normals[i])).chain([m.thickness[i] as f32]) {
            out.extend(x.to_le_bytes());
        }
        out.extend(d.colors[i]);
    }
    for (k, t) in m.triangles.iter().enumerate() {
        out.push(3);
        t.iter().for_each(|i| out.extend(i.to_le_bytes()));
        out.extend((d.face_thickness[k] as f32).to_le_bytes());
        out.extend(d.face_hits[k].to_le_bytes());
    }
    out
}

/// A point cloud of `points` (m) with their velocities (m/s), as binary PLY.
pub fn ply_points(points: &[(DVec3, DVec3)]) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment spraysim particles in flight; m and m/s\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         property float vx\nproperty float vy\nproperty float vz\nend_header\n",
        points.len()
    )
    .into_bytes();
    for (p, v) in points {
        for x in f32s(*p).into_iter().chain(f32s(*v)) {
            out.extend(x.to_le_bytes());
        }
    }
    out
}
