//! Mesh triangles.

use super::plane::{facing, plane_crossing, plane_hit};
use super::{Primitive, Tessellation};
use crate::collision::flight::Flight;
use crate::collision::{Aabb, Hit};
use glam::DVec3;

/// Triangle of a mesh; two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Corners, m.
    pub corners: [DVec3; 3],
    /// Unit normal (right-handed in the corner order).
    pub normal: DVec3,
}

impl Triangle {
    /// A triangle from its corners, or `None` if they are (nearly) collinear.
    pub fn new(a: DVec3, b: DVec3, c: DVec3) -> Option<Triangle> {
        let n = (b - a).cross(c - a);
        let scale = (b - a).length_squared().max((c - a).length_squared());
        (n.length_squared() > 1e-24 * scale * scale)
            .then(|| Triangle { corners: [a, b, c], normal: n.normalize() })
    }

    /// True if `q`, a point in the triangle's plane, lies inside it or on its edges.
    #[inline]
    pub fn covers(&self, q: DVec3) -> bool {
        let [a, b, c] = self.corners;
        let n = self.normal;
        (b - a).cross(q - a).dot(n) >= 0.0
            && (c - b).cross(q - b).dot(n) >= 0.0
            && (a - c).cross(q - c).dot(n) >= 0.0
    }

    /// Area, m².
    pub fn area(&self) -> f64 {
        let [a, b, c] = self.corners;
        0.5 * (b - a).cross(c - a).length()
    }
}

impl Primitive for Triangle {
    #[inline]
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.corners[0], self.normal, p0, p1)?;
        let point = p0.lerp(p1, t);
        self.covers(point).then(|| Hit { t, point, normal: facing(self.normal, d0) })
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        plane_hit(arc, self.corners[0], self.normal, |q| self.covers(q))
    }

    fn aabb(&self) -> Option<Aabb> {
        let [a, b, c] = self.corners;
        Some(Aabb { min: a.min(b).min(c), max: a.max(b).max(c) })
    }

    fn tessellate(&self, _around: DVec3, _extent: f64) -> Option<Tessellation> {
        let mut t = Tessellation::default();
        for c in self.corners {
            t.vertex(c, self.normal);
        }
        t.triangles.push([0, 1, 2]);
        Some(t)
    }
}
