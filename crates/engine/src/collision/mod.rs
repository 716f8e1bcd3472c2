//! Collision: the shapes particles strike, exact ballistic arcs, and the scene that indexes
//! every surface for the earliest-hit query.
//!
//! Each time step moves a particle along a straight segment from `p0` to `p1` (the paper's
//! "trajectories approximated as straight-line segments per timestep"), or along its exact
//! parabola. Every shape answers the same question algebraically: the earliest point of the
//! path that touches it, as a fraction `t ∈ [0, 1]` of the path, with the surface normal facing
//! the side the particle came from.

pub(crate) mod broad_phase;
mod flight;
mod scene;
pub mod shapes;

pub use flight::{Flight, ShortList, roots};
pub use scene::{Scene, SurfaceId, SurfaceKind, SurfaceRef};
pub use shapes::{
    Aabb, Cylinder, CylinderShell, Disk, Face, OrientedBox, Plane, Primitive, Shape, Sphere, Triangle,
};

use glam::DVec3;

/// Where a path first touches a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Fraction of the path travelled before the hit, in `[0, 1]`.
    pub t: f64,
    /// Hit point, m.
    pub point: DVec3,
    /// Unit surface normal at the hit point, facing the side the path came from.
    pub normal: DVec3,
}

/// Distance (m) by which a particle is lifted off a surface after an impact, so that the next
/// segment starts strictly on the outer side. Far below any cell or particle scale, far above
/// double-precision rounding at scene scale.
pub const SURFACE_OFFSET: f64 = 1e-9;

/// What the collision tests share.
#[cfg(test)]
pub(crate) mod testing {
    /// Uniform numbers in [−1, 1) from a xorshift generator seeded with `seed`.
    pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut x = seed;
        move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        }
    }
}
