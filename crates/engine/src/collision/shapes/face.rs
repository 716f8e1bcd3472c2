//! Finite rectangles: target faces and wall panels.

use super::plane::{facing, plane_crossing, plane_hit};
use super::{Primitive, Tessellation};
use crate::collision::flight::Flight;
use crate::collision::{Aabb, Hit};
use glam::DVec3;

/// Finite rectangle: a target's face or a wall panel; two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Centre, m.
    pub center: DVec3,
    /// Unit normal (for targets: towards the side that receives spray).
    pub normal: DVec3,
    /// Unit vector in the face along its height (rows grow along it).
    pub up: DVec3,
    /// Unit vector in the face along its width: `up × normal` (columns grow along it).
    pub right: DVec3,
    /// Half width along `right`, m.
    pub half_width: f64,
    /// Half height along `up`, m.
    pub half_height: f64,
}

impl Face {
    /// Builds a face from centre, normal, up and full size `[width, height]` (m). `normal` and
    /// `up` are normalised; `up` is made exactly perpendicular to `normal`.
    pub fn new(center: DVec3, normal: DVec3, up: DVec3, size: [f64; 2]) -> Self {
        let normal = normal.normalize();
        let up = (up - normal * up.dot(normal)).normalize();
        Face {
            center,
            normal,
            up,
            right: up.cross(normal),
            half_width: size[0] / 2.0,
            half_height: size[1] / 2.0,
        }
    }

    /// In-face coordinates `(along right, along up)` of a point, m, measured from the centre.
    #[inline]
    pub fn local(&self, p: DVec3) -> (f64, f64) {
        let d = p - self.center;
        (d.dot(self.right), d.dot(self.up))
    }

    /// The point at in-face coordinates `(u, v)` (m from the centre) raised by `height` (m)
    /// along the normal.
    #[inline]
    pub fn point(&self, u: f64, v: f64, height: f64) -> DVec3 {
        self.center + self.right * u + self.up * v + self.normal * height
    }

    /// True if in-face coordinates `(u, v)` lie on the rectangle (edges included).
    #[inline]
    pub fn covers(&self, u: f64, v: f64) -> bool {
        u.abs() <= self.half_width && v.abs() <= self.half_height
    }
}

impl Primitive for Face {
    #[inline]
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.center, self.normal, p0, p1)?;
        let point = p0.lerp(p1, t);
        let (u, v) = self.local(point);
        self.covers(u, v).then(|| Hit { t, point, normal: facing(self.normal, d0) })
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        plane_hit(arc, self.center, self.normal, |q| {
            let (u, v) = self.local(q);
            self.covers(u, v)
        })
    }

    fn aabb(&self) -> Option<Aabb> {
        let e = (self.right * self.half_width).abs() + (self.up * self.half_height).abs();
        Some(Aabb { min: self.center - e, max: self.center + e })
    }

    fn tessellate(&self, _around: DVec3, _extent: f64) -> Option<Tessellation> {
        let (u, v) = (self.right * self.half_width, self.up * self.half_height);
        let c = self.center;
        let mut t = Tessellation::default();
        t.quad([c - u - v, c + u - v, c + u + v, c - u + v], self.normal);
        Some(t)
    }
}
