//! Solid spheres.

use super::{Primitive, Tessellation, entry_root, tessellation::ROUND};
use crate::collision::flight::{Flight, first_entry, hit_at, squared_norm};
use crate::collision::{Aabb, Hit};
use glam::DVec3;

/// Solid sphere (a ball, a boulder): a path that starts inside it is pushed out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, m.
    pub center: DVec3,
    /// Radius, m.
    pub radius: f64,
}

impl Primitive for Sphere {
    /// Earliest hit of the segment `p0 → p1`; `t = 0` if `p0` is inside.
    #[inline]
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let m = p0 - self.center;
        let c = m.length_squared() - self.radius * self.radius;
        if c < 0.0 {
            return Some(Hit { t: 0.0, point: p0, normal: m.normalize_or(DVec3::Z) });
        }
        let d = p1 - p0;
        let t = entry_root(d.length_squared(), m.dot(d), c)?;
        let point = p0 + d * t;
        Some(Hit { t, point, normal: (point - self.center).normalize_or(DVec3::Z) })
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        if let Some(h) = super::inside_start(self, arc) {
            return Some(h);
        }
        let f = squared_norm([arc.x0 - self.center, arc.v0, 0.5 * arc.g], self.radius);
        let tau = first_entry(arc, &f, |_| true)?;
        let q = arc.at(tau);
        Some(hit_at(arc, tau, (q - self.center).normalize_or(DVec3::Z)))
    }

    fn aabb(&self) -> Option<Aabb> {
        Some(Aabb {
            min: self.center - DVec3::splat(self.radius),
            max: self.center + DVec3::splat(self.radius),
        })
    }

    fn contains(&self, p: DVec3) -> bool {
        (p - self.center).length_squared() < self.radius * self.radius
    }

    /// A latitude-longitude grid: `ROUND / 2` bands of `ROUND` quads from pole to pole.
    fn tessellate(&self, _around: DVec3, _extent: f64) -> Option<Tessellation> {
        let rows = ROUND / 2;
        let mut t = Tessellation::default();
        for i in 0..=rows {
            let polar = std::f64::consts::PI * i as f64 / rows as f64;
            for k in 0..=ROUND {
                let a = std::f64::consts::TAU * k as f64 / ROUND as f64;
                let n = DVec3::new(polar.sin() * a.cos(), polar.sin() * a.sin(), polar.cos());
                t.vertex(self.center + n * self.radius, n);
            }
        }
        let w = ROUND as u32 + 1;
        for i in 0..rows as u32 {
            for k in 0..ROUND as u32 {
                let (a, b) = (i * w + k, (i + 1) * w + k);
                t.triangles.extend([[a, b, b + 1], [a, b + 1, a + 1]]);
            }
        }
        Some(t)
    }
}
