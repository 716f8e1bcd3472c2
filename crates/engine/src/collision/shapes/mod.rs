//! The shapes a particle can strike, one file each, behind one trait.
//!
//! A shape answers four questions ([`Primitive`]): the earliest hit of a straight segment, the
//! earliest hit of a ballistic arc, its bounding box, and whether a point lies inside it; it
//! may also give the triangles that draw it ([`Primitive::tessellate`]). The built-in shapes
//! are listed once, in the `shapes!` invocation below, which generates the [`Shape`] enum and
//! its dispatch; a shape defined outside the engine goes in [`Shape::Custom`]. Adding a
//! built-in shape is a file here and a line (with its `mod`) in that list; a scenario names it
//! through a file in the scenario crate's `params/obstacles/`.

mod aabb;
mod cylinder;
mod disk;
mod face;
mod oriented_box;
mod plane;
mod shell;
mod sphere;
mod tessellation;
mod triangle;

pub use aabb::Aabb;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use face::Face;
pub use oriented_box::OrientedBox;
pub use plane::Plane;
pub use shell::CylinderShell;
pub use sphere::Sphere;
pub use tessellation::Tessellation;
pub use triangle::Triangle;

use tessellation::basis;

use super::Hit;
use super::flight::Flight;
use glam::DVec3;

/// What every collidable shape answers. Thin surfaces (plane, face, disk, triangle) are
/// two-sided; solids (sphere, box, capped cylinder) are closed, and a path that starts inside
/// one reports a hit at `t = 0` so that the caller can push the particle back out.
pub trait Primitive: Send + Sync + std::fmt::Debug {
    /// Earliest point of the segment `p0 → p1` on the shape: `Hit::t` is the fraction of the
    /// segment, the normal faces the side the segment came from.
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit>;

    /// Earliest hit of a ballistic arc within its duration; `Hit::t` is the fraction of the
    /// duration.
    fn intersect_arc(&self, arc: &Flight) -> Option<Hit>;

    /// Bounding box, m, or `None` for an unbounded shape (tested on every query).
    fn aabb(&self) -> Option<Aabb>;

    /// True if `p` lies strictly inside a closed solid (always false for thin surfaces).
    fn contains(&self, p: DVec3) -> bool {
        let _ = p;
        false
    }

    /// Triangles that draw the shape, for viewers; an unbounded shape draws the part of it within
    /// `extent` (m) of its point nearest `around`. `None` (the default): the shape gives none,
    /// and a viewer draws the edges of its bounding box instead.
    fn tessellate(&self, around: DVec3, extent: f64) -> Option<Tessellation> {
        let _ = (around, extent);
        None
    }
}

/// Declares the built-in shapes: the [`Shape`] enum, its dispatch to [`Primitive`] and its
/// equality.
macro_rules! shapes {
    ($( $(#[$doc:meta])* $variant:ident($ty:ty), )*) => {
        /// Any collision shape: a built-in one, or one defined outside the engine.
        #[derive(Clone, Debug)]
        pub enum Shape {
            $( $(#[$doc])* $variant($ty), )*
            /// A shape defined outside the engine.
            Custom(std::sync::Arc<dyn Primitive>),
        }

        impl Primitive for Shape {
            #[inline]
            fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
                match self {
                    $( Shape::$variant(s) => s.intersect(p0, p1), )*
                    Shape::Custom(s) => s.intersect(p0, p1),
                }
            }

            fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
                match self {
                    $( Shape::$variant(s) => s.intersect_arc(arc), )*
                    Shape::Custom(s) => s.intersect_arc(arc),
                }
            }

            fn aabb(&self) -> Option<Aabb> {
                match self {
                    $( Shape::$variant(s) => s.aabb(), )*
                    Shape::Custom(s) => s.aabb(),
                }
            }

            fn contains(&self, p: DVec3) -> bool {
                match self {
                    $( Shape::$variant(s) => s.contains(p), )*
                    Shape::Custom(s) => s.contains(p),
                }
            }

            fn tessellate(&self, around: DVec3, extent: f64) -> Option<Tessellation> {
                match self {
                    $( Shape::$variant(s) => s.tessellate(around, extent), )*
                    Shape::Custom(s) => s.tessellate(around, extent),
                }
            }
        }

        impl PartialEq for Shape {
            /// Built-in shapes compare by value, custom ones by identity.
            fn eq(&self, other: &Shape) -> bool {
                match (self, other) {
                    $( (Shape::$variant(a), Shape::$variant(b)) => a == b, )*
                    (Shape::Custom(a), Shape::Custom(b)) => std::sync::Arc::ptr_eq(a, b),
                    _ => false,
                }
            }
        }
    };
}

shapes! {
    /// An infinite plane, two-sided.
    Plane(Plane),
    /// A finite rectangle, two-sided.
    Face(Face),
    /// A flat disk, two-sided.
    Disk(Disk),
    /// A solid sphere.
    Sphere(Sphere),
    /// A solid box on axes of its own.
    Box(OrientedBox),
    /// A solid cylinder with flat caps (a bar).
    Cylinder(Cylinder),
    /// One triangle of a mesh, two-sided.
    Triangle(Triangle),
    /// An open cylindrical shell over a range of angles.
    Shell(CylinderShell),
}

/// Smallest root in `[0, 1]` of `a t² + 2 b t + c = 0` for a segment entering a quadric from
/// outside (`c > 0`), using the half-b form, which loses less precision.
#[inline]
pub(crate) fn entry_root(a: f64, b: f64, c: f64) -> Option<f64> {
    if a <= 0.0 || b >= 0.0 {
        // Not moving, or moving away from the surface.
        return None;
    }
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    // -b > 0 here, so this form avoids cancellation: t = c / (-b + sqrt(disc)).
    let t = c / (-b + disc.sqrt());
    (0.0..=1.0).contains(&t).then_some(t)
}

/// The start-inside case of a solid for arcs: the segment test's push-out, at the arc's start.
pub(crate) fn inside_start(shape: &dyn Primitive, arc: &Flight) -> Option<Hit> {
    shape.contains(arc.x0).then(|| shape.intersect(arc.x0, arc.x0)).flatten()
}
