//! Triangle meshes of the collision shapes, for drawing obstacles and the nozzle.

use crate::scene::{ColorVertex, Mesh};
use glam::DVec3;
use spraysim::collision::{Aabb, Cylinder, CylinderShell, Disk, Face, OrientedBox, Shape, Sphere};

/// Segments around a cylinder, a disk or a sphere.
const ROUND: usize = 24;

/// Two unit vectors perpendicular to `n` and to each other.
pub(crate) fn basis(n: DVec3) -> (DVec3, DVec3) {
    let a = n.any_orthonormal_vector();
    (a, n.cross(a))
}

/// Adds `shape` to `mesh` in `color`; an unbounded plane is drawn as the square of side
/// `extent` (m) centred on the point of it nearest `center`; a shape defined outside the engine
/// is drawn as the edges of its bounding box into `lines`.
pub(crate) fn add_shape(
    mesh: &mut Mesh,
    lines: &mut Vec<ColorVertex>,
    shape: &Shape,
    color: [u8; 4],
    (center, extent): (DVec3, f64),
) {
    match shape {
        Shape::Cylinder(c) => add_cylinder(mesh, c, color),
        Shape::Shell(c) => add_shell(mesh, c, color),
        Shape::Box(b) => add_box(mesh, b, color),
        Shape::Sphere(s) => add_sphere(mesh, s, color),
        Shape::Disk(d) => add_disk(mesh, d, color),
        Shape::Face(f) => add_face(mesh, f, color),
        Shape::Triangle(t) => {
            let base = mesh.vertices.len() as u32;
            for c in t.corners {
                mesh.push_vertex(c, t.normal, color);
            }
            mesh.indices.extend([base, base + 1, base + 2]);
        }
        Shape::Plane(p) => {
            let c = center - p.normal * (center - p.point).dot(p.normal);
            let (u, v) = basis(p.normal);
            let f = Face {
                center: c,
                normal: p.normal,
                up: v,
                right: u,
                half_width: extent,
                half_height: extent,
            };
            add_face(mesh, &f, color);
        }
        Shape::Custom(s) => {
            if let Some(b) = s.aabb() {
                add_box_edges(lines, &b, color);
            }
        }
    }
}

/// A quad from four corners in counter-clockwise order seen from `normal`'s side.
fn quad(mesh: &mut Mesh, corners: [DVec3; 4], normal: DVec3, color: [u8; 4]) {
    let base = mesh.vertices.len() as u32;
    for c in corners {
        mesh.push_vertex(c, normal, color);
    }
    mesh.indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
}

pub(crate) fn add_face(mesh: &mut Mesh, f: &Face, color: [u8; 4]) {
    let (u, v) = (f.right * f.half_width, f.up * f.half_height);
    let c = f.center;
    quad(mesh, [c - u - v, c + u - v, c + u + v, c - u + v], f.normal, color);
}

/// A cylindrical shell's angular range, in strips of at most a `ROUND`th of a turn; the normals
/// point outwards (the lighting is two-sided).
fn add_shell(mesh: &mut Mesh, c: &CylinderShell, color: [u8; 4]) {
    let [a0, a1] = c.angles;
    let strips = ((a1 - a0) / std::f64::consts::TAU * ROUND as f64).ceil().max(1.0) as usize;
    for k in 0..strips {
        let (t0, t1) =
            (a0 + (a1 - a0) * k as f64 / strips as f64, a0 + (a1 - a0) * (k + 1) as f64 / strips as f64);
        let l = c.half_length;
        let corners = [
            c.point(t0, -l, c.radius),
            c.point(t1, -l, c.radius),
            c.point(t1, l, c.radius),
            c.point(t0, l, c.radius),
        ];
        quad(mesh, corners, c.radial(0.5 * (t0 + t1)), color);
    }
}

pub(crate) fn add_cylinder(mesh: &mut Mesh, c: &Cylinder, color: [u8; 4]) {
    let axis = c.b - c.a;
    let Some(n) = axis.try_normalize() else { return };
    let (u, v) = basis(n);
    let ring = |k: usize| {
        let a = std::f64::consts::TAU * k as f64 / ROUND as f64;
        u * a.cos() + v * a.sin()
    };
    // Mantle: one ring of vertices at each cap, with radial normals.
    let base = mesh.vertices.len() as u32;
    for k in 0..ROUND {
        let r = ring(k);
        mesh.push_vertex(c.a + r * c.radius, r, color);
        mesh.push_vertex(c.b + r * c.radius, r, color);
    }
    for k in 0..ROUND as u32 {
        let (a0, b0) = (base + 2 * k, base + 2 * k + 1);
        let next = (k + 1) % ROUND as u32;
        let (a1, b1) = (base + 2 * next, base + 2 * next + 1);
        mesh.indices.extend([a0, a1, b1, a0, b1, b0]);
    }
    // Caps.
    for (centre, normal) in [(c.a, -n), (c.b, n)] {
        let mid = mesh.vertices.len() as u32;
        mesh.push_vertex(centre, normal, color);
        for k in 0..ROUND {
            mesh.push_vertex(centre + ring(k) * c.radius, normal, color);
        }
        for k in 0..ROUND as u32 {
            mesh.indices.extend([mid, mid + 1 + k, mid + 1 + (k + 1) % ROUND as u32]);
        }
    }
}

pub(crate) fn add_box(mesh: &mut Mesh, b: &OrientedBox, color: [u8; 4]) {
    let e = [b.axes[0] * b.half_extents.x, b.axes[1] * b.half_extents.y, b.axes[2] * b.half_extents.z];
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        for sign in [-1.0, 1.0] {
            let c = b.center + e[i] * sign;
            let (p, q) = (e[j], e[k] * sign);
            let normal = b.axes[i] * sign;
            quad(mesh, [c - p - q, c + p - q, c + p + q, c - p + q], normal, color);
        }
    }
}

fn add_sphere(mesh: &mut Mesh, s: &Sphere, color: [u8; 4]) {
    let rows = ROUND / 2;
    let base = mesh.vertices.len() as u32;
    for i in 0..=rows {
        let polar = std::f64::consts::PI * i as f64 / rows as f64;
        for k in 0..=ROUND {
            let a = std::f64::consts::TAU * k as f64 / ROUND as f64;
            let n = DVec3::new(polar.sin() * a.cos(), polar.sin() * a.sin(), polar.cos());
            mesh.push_vertex(s.center + n * s.radius, n, color);
        }
    }
    let w = ROUND as u32 + 1;
    for i in 0..rows as u32 {
        for k in 0..ROUND as u32 {
            let (a, b) = (base + i * w + k, base + (i + 1) * w + k);
            mesh.indices.extend([a, b, b + 1, a, b + 1, a + 1]);
        }
    }
}

fn add_disk(mesh: &mut Mesh, d: &Disk, color: [u8; 4]) {
    let (u, v) = basis(d.normal);
    let mid = mesh.vertices.len() as u32;
    mesh.push_vertex(d.center, d.normal, color);
    for k in 0..ROUND {
        let a = std::f64::consts::TAU * k as f64 / ROUND as f64;
        mesh.push_vertex(d.center + (u * a.cos() + v * a.sin()) * d.radius, d.normal, color);
    }
    for k in 0..ROUND as u32 {
        mesh.indices.extend([mid, mid + 1 + k, mid + 1 + (k + 1) % ROUND as u32]);
    }
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
