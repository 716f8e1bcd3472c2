//! Infinite planes, and the plane crossing every flat shape is built on.

use super::{Face, Primitive, Tessellation, basis};
use crate::collision::flight::{Flight, eval, hit_at, roots};
use crate::collision::{Aabb, Hit};
use glam::DVec3;

/// Infinite plane through `point` with unit `normal`; two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point on the plane, m.
    pub point: DVec3,
    /// Unit normal.
    pub normal: DVec3,
}

impl Plane {
    /// The least and the greatest signed distance (m, along the normal) of the points of box
    /// `b` from the plane.
    pub fn signed_range(&self, b: &Aabb) -> (f64, f64) {
        let centre = 0.5 * (b.min + b.max);
        let half = 0.5 * (b.max - b.min);
        let d = (centre - self.point).dot(self.normal);
        let reach = half.dot(self.normal.abs());
        (d - reach, d + reach)
    }
}

impl Primitive for Plane {
    #[inline]
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.point, self.normal, p0, p1)?;
        Some(Hit { t, point: p0.lerp(p1, t), normal: facing(self.normal, d0) })
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        plane_hit(arc, self.point, self.normal, |_| true)
    }

    fn aabb(&self) -> Option<Aabb> {
        None
    }

    /// The square of half-side `extent` (m) on the plane, centred on its point nearest `around`.
    fn tessellate(&self, around: DVec3, extent: f64) -> Option<Tessellation> {
        let center = around - self.normal * (around - self.point).dot(self.normal);
        let (right, up) = basis(self.normal);
        let square = Face { center, normal: self.normal, up, right, half_width: extent, half_height: extent };
        square.tessellate(around, extent)
    }
}

/// Crossing of the segment with the plane through `point` with unit `normal`: the fraction `t`
/// and the signed start distance. A segment that starts exactly on the plane does not cross it
/// (particles are always lifted off a surface after an impact).
#[inline]
pub(crate) fn plane_crossing(point: DVec3, normal: DVec3, p0: DVec3, p1: DVec3) -> Option<(f64, f64)> {
    let d0 = (p0 - point).dot(normal);
    let d1 = (p1 - point).dot(normal);
    let crosses = (d0 > 0.0 && d1 <= 0.0) || (d0 < 0.0 && d1 >= 0.0);
    if !crosses {
        return None;
    }
    Some(((d0 / (d0 - d1)).clamp(0.0, 1.0), d0))
}

/// `normal`, turned to face the side at signed distance `d0`.
#[inline]
pub(crate) fn facing(normal: DVec3, d0: f64) -> DVec3 {
    if d0 > 0.0 { normal } else { -normal }
}

/// First crossing of an arc with a (two-sided) plane whose crossing point passes `within`.
pub(crate) fn plane_hit(
    arc: &Flight,
    point: DVec3,
    normal: DVec3,
    within: impl Fn(DVec3) -> bool,
) -> Option<Hit> {
    let s = arc.along(point, normal);
    if s[0] == 0.0 {
        return None; // starts on the plane: particles are always lifted off surfaces
    }
    for &tau in roots(&s, 0.0, arc.duration).iter() {
        if tau <= 0.0 {
            continue;
        }
        let q = arc.at(tau);
        // The side it comes from: the sign of s just before the root.
        let side = eval(&s, tau * (1.0 - 1e-9)).signum();
        if side != 0.0 && within(q) {
            return Some(hit_at(arc, tau, normal * side));
        }
    }
    None
}
