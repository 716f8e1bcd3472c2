//! Bounding boxes of the obstacle shapes, as the kernels read them to skip the shapes that a
//! step's path cannot meet: each shape's own box (in its words), and the box round every shape
//! of a member (at the start of its shapes' table). A step whose path's box overlaps neither
//! tests no shape; most steps are far from all of them.

use glam::DVec3;
use spraysim_engine::collision::{Aabb, Primitive, Shape};

/// Words of a bounding box as the kernels read it: the lower corner (m, f32) and a spare word,
/// then the upper corner and a spare word.
pub const BOX_WORDS: usize = 8;

/// How far a box is widened on every side, m, beyond the exact box: a path that the kernel's
/// f32 test finds on a shape must not be skipped because its own rounding put the contact just
/// outside the exact box (that rounding is a few µm on coordinates of a few metres). A wider
/// box costs only a few more exact tests near the shape.
pub const BOX_MARGIN: f64 = 1e-3;

/// The words of `aabb` (`None`: unbounded, a box that every path overlaps), widened by
/// [`BOX_MARGIN`] and by a millionth of its largest coordinate (far above f32's rounding of it).
pub fn box_words(aabb: Option<Aabb>) -> [u32; BOX_WORDS] {
    let (lo, hi) = match aabb {
        Some(b) => {
            let margin = DVec3::splat(BOX_MARGIN) + 1e-6 * b.min.abs().max(b.max.abs());
            (b.min - margin, b.max + margin)
        }
        None => (DVec3::splat(-f64::from(f32::MAX)), DVec3::splat(f64::from(f32::MAX))),
    };
    corners(lo, hi)
}

/// The box round every bounded shape of `shapes`: every path overlaps it where one is unbounded,
/// none where there is no shape (its lower corner above its upper one).
pub fn shapes_box<'a>(shapes: impl Iterator<Item = &'a Shape>) -> [u32; BOX_WORDS] {
    // `None` for no shape; `Some(None)` once one is unbounded.
    match shapes.map(Primitive::aabb).reduce(|a, b| a.zip(b).map(|(a, b)| a.union(b))) {
        Some(b) => box_words(b),
        None => corners(DVec3::splat(f64::from(f32::MAX)), DVec3::splat(-f64::from(f32::MAX))),
    }
}

/// The words of the box from `lo` to `hi` (m), each corner rounded to the f32 outside it.
fn corners(lo: DVec3, hi: DVec3) -> [u32; BOX_WORDS] {
    let mut w = [0u32; BOX_WORDS];
    for k in 0..3 {
        w[k] = down(lo[k]).to_bits();
        w[4 + k] = up(hi[k]).to_bits();
    }
    w
}

/// The largest f32 not above `x` (finite `x` within f32's range).
fn down(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) > x { r.next_down() } else { r }
}

/// The smallest f32 not below `x`.
fn up(x: f64) -> f32 {
    let r = x as f32;
    if f64::from(r) < x { r.next_up() } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;
    use spraysim_engine::collision::{Cylinder, Disk, Face, OrientedBox, Plane, Sphere};

    /// The box of `w` as the kernels read it.
    fn read(w: &[u32; BOX_WORDS]) -> ([f32; 3], [f32; 3]) {
        let f = |k: usize| f32::from_bits(w[k]);
        ([f(0), f(1), f(2)], [f(4), f(5), f(6)])
    }

    /// The kernels' test: the box of `w` overlaps the one from `lo` to `hi` (touching counts).
    fn overlaps(w: &[u32; BOX_WORDS], lo: [f32; 3], hi: [f32; 3]) -> bool {
        let (min, max) = read(w);
        (0..3).all(|k| lo[k] <= max[k] && min[k] <= hi[k])
    }

    /// A uniform draw in [0, 1) from a 64-bit state (xorshift).
    fn draw(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    fn shapes() -> Vec<Shape> {
        let tilted = DVec3::new(1.0, 2.0, 3.0).normalize();
        let across = tilted.cross(DVec3::X).normalize();
        vec![
            Shape::Sphere(Sphere { center: DVec3::new(0.3, -1.2, 1.7), radius: 0.05 }),
            Shape::Cylinder(Cylinder {
                a: DVec3::new(-0.05, -1.0, 1.3),
                b: DVec3::new(-0.05, 1.0, 1.3) + 0.2 * tilted,
                radius: 0.008,
            }),
            Shape::Disk(Disk { center: DVec3::new(2.5, 0.4, 0.2), normal: tilted, radius: 0.3 }),
            Shape::Box(OrientedBox {
                center: DVec3::new(-1.0, 0.5, 2.0),
                axes: [tilted, across, tilted.cross(across)],
                half_extents: DVec3::new(0.1, 0.2, 0.05),
            }),
            Shape::Face(Face::new(DVec3::new(0.0, 3.0, 1.0), DVec3::Y, DVec3::Z, [0.4, 0.3])),
        ]
    }

    #[test]
    fn every_path_that_meets_a_shape_overlaps_its_box_with_room_for_f32_rounding() {
        let mut state = 0x9e37_79b9_7f4a_7c15;
        for shape in shapes() {
            let exact = shape.aabb().expect("a bounded shape");
            let w = box_words(Some(exact));
            let (min, max) = read(&w);
            let (mut met, mut tried) = (0, 0);
            while met < 2000 {
                tried += 1;
                assert!(tried < 2_000_000, "{shape:?}: too few paths meet it");
                // Paths of up to 10 cm around the shape's box widened by 20 cm.
                let span = exact.max - exact.min + DVec3::splat(0.4);
                let p0 = exact.min - DVec3::splat(0.2)
                    + DVec3::new(draw(&mut state), draw(&mut state), draw(&mut state)) * span;
                let step = DVec3::new(draw(&mut state), draw(&mut state), draw(&mut state)) - 0.5;
                let p1 = p0 + 0.2 * step;
                let Some(hit) = shape.intersect(p0, p1) else { continue };
                met += 1;
                let (a, b) = (p0.as_vec3().to_array(), p1.as_vec3().to_array());
                let lo = [a[0].min(b[0]), a[1].min(b[1]), a[2].min(b[2])];
                let hi = [a[0].max(b[0]), a[1].max(b[1]), a[2].max(b[2])];
                assert!(overlaps(&w, lo, hi), "{shape:?}: a path from {p0} to {p1} that meets it is skipped");
                // The contact lies inside the box by at least 0.5 mm on every side: a hundred
                // times the kernel's f32 rounding of it.
                for k in 0..3 {
                    let (c, room) = (hit.point[k], 5e-4);
                    assert!(
                        f64::from(min[k]) <= c - room && c + room <= f64::from(max[k]),
                        "{shape:?}: contact {} lies within {room} m of its box's side {k}",
                        hit.point
                    );
                }
            }
        }
    }

    #[test]
    fn the_box_round_all_shapes_holds_each_and_is_unbounded_with_a_plane() {
        let all = shapes();
        let w = shapes_box(all.iter());
        let (min, max) = read(&w);
        for s in &all {
            let (lo, hi) = read(&box_words(s.aabb()));
            assert!((0..3).all(|k| min[k] <= lo[k] && hi[k] <= max[k]), "{s:?} is not inside the box of all");
        }
        // Far from every shape: outside the box of all.
        assert!(!overlaps(&w, [10.0; 3], [10.1; 3]));
        let plane = Shape::Plane(Plane { point: DVec3::ZERO, normal: DVec3::Z });
        let with_plane: Vec<Shape> = all.iter().cloned().chain([plane]).collect();
        assert!(overlaps(&shapes_box(with_plane.iter()), [10.0; 3], [10.1; 3]), "a plane is met anywhere");
        // No shape: no path overlaps the box, however large.
        let none = shapes_box(std::iter::empty());
        assert!(!overlaps(&none, [-1e30; 3], [1e30; 3]));
    }
}
