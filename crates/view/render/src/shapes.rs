//! Obstacles and the nozzle, drawn from the engine's shapes: each shape gives its own triangles
//! (`Primitive::tessellate`), so a new kind of shape draws without a change here; one that
//! gives none is drawn as the edges of its bounding box.

use crate::scene::{ColorVertex, Mesh};
use glam::DVec3;
use spraysim::collision::shapes::Tessellation;
use spraysim::collision::{Aabb, Cylinder, Primitive, Shape};

/// Adds `shape` to `mesh` in `color`; an unbounded shape (a plane) is drawn within `extent` (m)
/// of its point nearest `center`; a shape without triangles of its own (see
/// [`Primitive::tessellate`]) is drawn as the edges of its bounding box into `lines`.
pub(crate) fn add_shape(
    mesh: &mut Mesh,
    lines: &mut Vec<ColorVertex>,
    shape: &Shape,
    color: [u8; 4],
    (center, extent): (DVec3, f64),
) {
    match shape.tessellate(center, extent) {
        Some(t) => add_tessellation(mesh, &t, color),
        None => {
            if let Some(b) = shape.aabb() {
                add_box_edges(lines, &b, color);
            }
        }
    }
}

/// Adds a bar (the nozzle's body) to `mesh` in `color`.
pub(crate) fn add_cylinder(mesh: &mut Mesh, c: &Cylinder, color: [u8; 4]) {
    if let Some(t) = c.tessellate(c.a, 0.0) {
        add_tessellation(mesh, &t, color);
    }
}

/// Appends a shape's triangles to `mesh`, every vertex in `color`.
fn add_tessellation(mesh: &mut Mesh, t: &Tessellation, color: [u8; 4]) {
    let base = mesh.vertices.len() as u32;
    for (&p, &n) in t.positions.iter().zip(&t.normals) {
        mesh.push_vertex(p, n, color);
    }
    mesh.indices.extend(t.triangles.iter().flatten().map(|&i| base + i));
}

/// The twelve edges of a box as line segments.
pub(crate) fn add_box_edges(lines: &mut Vec<ColorVertex>, b: &Aabb, color: [u8; 4]) {
    let corner = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { b.min.x } else { b.max.x },
            if i & 2 == 0 { b.min.y } else { b.max.y },
            if i & 4 == 0 { b.min.z } else { b.max.z },
        )
    };
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                lines.push(ColorVertex::new(corner(i), color));
                lines.push(ColorVertex::new(corner(i | bit), color));
            }
        }
    }
}
