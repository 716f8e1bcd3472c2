//! Straight-segment collision tests against the scene's surfaces.
//!
//! Each time step moves a particle along a straight segment from `p0` to `p1` (the paper's
//! "trajectories approximated as straight-line segments per timestep"). Every primitive answers
//! the same question algebraically: the earliest point of the segment that touches it, as a
//! fraction `t ∈ [0, 1]` of the segment, with the surface normal facing the side the particle came
//! from. Thin surfaces (plane, face, disk) are two-sided; solids (sphere, box, capped cylinder)
//! are closed, and a segment that starts inside one reports a hit at `t = 0` so that the caller
//! can push the particle back out.

mod arc;
mod broad_phase;
mod primitives;
mod scene;

pub use arc::{Arc, roots};
pub use primitives::{Aabb, Cylinder, Disk, Face, OrientedBox, Plane, Shape, Sphere, Triangle};
pub use scene::{Scene, SurfaceKind, SurfaceRef};

use glam::DVec3;

/// Where a segment first touches a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Fraction of the segment travelled before the hit, in `[0, 1]`.
    pub t: f64,
    /// Hit point, m.
    pub point: DVec3,
    /// Unit surface normal at the hit point, facing the side the segment came from.
    pub normal: DVec3,
}

/// Distance (m) by which a particle is lifted off a surface after an impact, so that the next
/// segment starts strictly on the outer side. Far below any cell or particle scale, far above
/// double-precision rounding at scene scale.
pub const SURFACE_OFFSET: f64 = 1e-9;
