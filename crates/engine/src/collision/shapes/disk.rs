//! Flat disks.

use super::plane::{facing, plane_crossing, plane_hit};
use super::{Primitive, Tessellation, basis};
use crate::collision::flight::Flight;
use crate::collision::{Aabb, Hit};
use glam::DVec3;

/// Flat disk (a round plate); two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    /// Centre, m.
    pub center: DVec3,
    /// Unit normal.
    pub normal: DVec3,
    /// Radius, m.
    pub radius: f64,
}

impl Primitive for Disk {
    #[inline]
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.center, self.normal, p0, p1)?;
        let point = p0.lerp(p1, t);
        ((point - self.center).length_squared() <= self.radius * self.radius).then(|| Hit {
            t,
            point,
            normal: facing(self.normal, d0),
        })
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        plane_hit(arc, self.center, self.normal, |q| {
            (q - self.center).length_squared() <= self.radius * self.radius
        })
    }

    fn aabb(&self) -> Option<Aabb> {
        // Extent of a disk along world axis i is r·sqrt(1 − n_i²).
        let e = (DVec3::ONE - self.normal * self.normal).max(DVec3::ZERO).map(f64::sqrt) * self.radius;
        Some(Aabb { min: self.center - e, max: self.center + e })
    }

    fn tessellate(&self, _around: DVec3, _extent: f64) -> Option<Tessellation> {
        let mut t = Tessellation::default();
        t.disk(self.center, basis(self.normal), self.radius, self.normal);
        Some(t)
    }
}
