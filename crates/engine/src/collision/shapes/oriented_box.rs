//! Solid boxes with any orientation.

use super::{Primitive, Tessellation};
use crate::collision::flight::{Flight, derivative, eval, hit_at, roots};
use crate::collision::{Aabb, Hit};
use glam::DVec3;

/// Solid box with arbitrary orientation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrientedBox {
    /// Centre, m.
    pub center: DVec3,
    /// Orthonormal local axes (columns of the box's rotation).
    pub axes: [DVec3; 3],
    /// Half extents along each local axis, m.
    pub half_extents: DVec3,
}

impl Primitive for OrientedBox {
    /// Earliest hit of the segment `p0 → p1` (slab method); `t = 0` if `p0` is inside.
    #[inline]
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let rel = p0 - self.center;
        let d = p1 - p0;
        let mut t_enter = f64::NEG_INFINITY;
        let mut t_exit = f64::INFINITY;
        let mut enter_axis = 0;
        let mut enter_sign = 1.0;
        let mut inside = true;
        for i in 0..3 {
            let o = rel.dot(self.axes[i]);
            let v = d.dot(self.axes[i]);
            let h = self.half_extents[i];
            if o.abs() >= h {
                inside = false;
            }
            if v == 0.0 {
                if o.abs() > h {
                    return None;
                }
                continue;
            }
            let (mut t0, mut t1) = ((-h - o) / v, (h - o) / v);
            // The slab is entered through the face on the side the particle is coming from.
            let mut sign = -1.0;
            if t0 > t1 {
                std::mem::swap(&mut t0, &mut t1);
                sign = 1.0;
            }
            if t0 > t_enter {
                t_enter = t0;
                enter_axis = i;
                enter_sign = sign;
            }
            t_exit = t_exit.min(t1);
        }
        if inside {
            return Some(self.push_out(p0, rel));
        }
        if t_enter > t_exit || !(0.0..=1.0).contains(&t_enter) {
            return None;
        }
        Some(Hit { t: t_enter, point: p0 + d * t_enter, normal: self.axes[enter_axis] * enter_sign })
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        if let Some(h) = super::inside_start(self, arc) {
            return Some(h);
        }
        let local: [[f64; 3]; 3] = std::array::from_fn(|i| arc.along(self.center, self.axes[i]));
        let mut best: Option<Hit> = None;
        for i in 0..3 {
            let h = self.half_extents[i];
            let d = derivative(&local[i]);
            for sign in [-1.0, 1.0] {
                let shifted = [local[i][0] - sign * h, local[i][1], local[i][2]];
                for &tau in roots(&shifted, 0.0, arc.duration).iter() {
                    // Entering through the face at sign·h: moving against its outward normal.
                    let slope = eval(&d, tau) * sign;
                    let on_face = (0..3)
                        .filter(|&j| j != i)
                        .all(|j| eval(&local[j], tau).abs() <= self.half_extents[j]);
                    if tau > 0.0 && slope < 0.0 && on_face {
                        if best.is_none_or(|bh| tau / arc.duration < bh.t) {
                            best = Some(hit_at(arc, tau, self.axes[i] * sign));
                        }
                        break;
                    }
                }
            }
        }
        best
    }

    fn aabb(&self) -> Option<Aabb> {
        let e = (self.axes[0] * self.half_extents.x).abs()
            + (self.axes[1] * self.half_extents.y).abs()
            + (self.axes[2] * self.half_extents.z).abs();
        Some(Aabb { min: self.center - e, max: self.center + e })
    }

    fn contains(&self, p: DVec3) -> bool {
        let d = p - self.center;
        (0..3).all(|i| d.dot(self.axes[i]).abs() < self.half_extents[i])
    }

    /// Six quads, each with its outward normal.
    fn tessellate(&self, _around: DVec3, _extent: f64) -> Option<Tessellation> {
        let e = [
            self.axes[0] * self.half_extents.x,
            self.axes[1] * self.half_extents.y,
            self.axes[2] * self.half_extents.z,
        ];
        let mut t = Tessellation::default();
        for i in 0..3 {
            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
            for sign in [-1.0, 1.0] {
                let c = self.center + e[i] * sign;
                let (p, q) = (e[j], e[k] * sign);
                t.quad([c - p - q, c + p - q, c + p + q, c - p + q], self.axes[i] * sign);
            }
        }
        Some(t)
    }
}

impl OrientedBox {
    /// A hit at the start that pushes a particle inside out through the nearest face.
    fn push_out(&self, p0: DVec3, rel: DVec3) -> Hit {
        let (i, o) = (0..3)
            .map(|i| (i, rel.dot(self.axes[i])))
            .min_by(|x, y| {
                (self.half_extents[x.0] - x.1.abs()).total_cmp(&(self.half_extents[y.0] - y.1.abs()))
            })
            .unwrap_or((0, 0.0));
        Hit { t: 0.0, point: p0, normal: self.axes[i] * o.signum() }
    }
}
