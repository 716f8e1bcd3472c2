//! Triangles that draw a shape, for viewers: what [`super::Primitive::tessellate`] gives, and
//! the pieces the shapes build it from.

use glam::DVec3;

/// Segments around a round shape: a cylinder, a disk, a sphere, a full turn of a shell.
pub(crate) const ROUND: usize = 24;

/// A triangle mesh that draws a shape.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tessellation {
    /// Vertex positions, m.
    pub positions: Vec<DVec3>,
    /// Vertex normals, one per position, outwards from a solid (a viewer lights thin surfaces
    /// from both sides); a viewer normalises them.
    pub normals: Vec<DVec3>,
    /// Triangles, as three indices into `positions` each.
    pub triangles: Vec<[u32; 3]>,
}

impl Tessellation {
    /// Adds a vertex at `p` (m) with `normal`; returns its index.
    pub fn vertex(&mut self, p: DVec3, normal: DVec3) -> u32 {
        self.positions.push(p);
        self.normals.push(normal);
        (self.positions.len() - 1) as u32
    }

    /// Adds a quad from its four corners in order around it, all with `normal`: two triangles.
    pub fn quad(&mut self, corners: [DVec3; 4], normal: DVec3) {
        let base = self.positions.len() as u32;
        for c in corners {
            self.vertex(c, normal);
        }
        self.triangles.extend([[base, base + 1, base + 2], [base, base + 2, base + 3]]);
    }

    /// Adds a flat disk of 24 segments (`ROUND`) about `centre`, radius `radius` (m), in the plane
    /// spanned by the unit vectors `u` and `v`, with `normal`.
    pub fn disk(&mut self, centre: DVec3, (u, v): (DVec3, DVec3), radius: f64, normal: DVec3) {
        let mid = self.vertex(centre, normal);
        for k in 0..ROUND {
            let a = std::f64::consts::TAU * k as f64 / ROUND as f64;
            self.vertex(centre + (u * a.cos() + v * a.sin()) * radius, normal);
        }
        for k in 0..ROUND as u32 {
            self.triangles.push([mid, mid + 1 + k, mid + 1 + (k + 1) % ROUND as u32]);
        }
    }
}

/// Two unit vectors perpendicular to the unit vector `n` and to each other.
pub(crate) fn basis(n: DVec3) -> (DVec3, DVec3) {
    let a = n.any_orthonormal_vector();
    (a, n.cross(a))
}
