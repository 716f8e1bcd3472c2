//! Cylindrical shells: tunnel linings, shafts, pipes and tanks, open at both ends and bounded
//! to a range of angles.

use super::{Primitive, Tessellation, tessellation::ROUND};
use crate::collision::flight::{Flight, derivative, eval, hit_at, roots, squared_norm};
use crate::collision::{Aabb, Hit};
use glam::DVec3;
use std::f64::consts::TAU;

/// The part of a cylinder's mantle (no caps) between two angles about its axis; two-sided.
///
/// Angles are measured about the axis from `e1` towards `e2` = `e1 × axis`: with `e1`
/// horizontal and the axis horizontal, 90° is straight up, so a tunnel arch is 0°–180°.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CylinderShell {
    /// Centre of the axis segment, m.
    pub center: DVec3,
    /// Unit direction of the axis (lengths along it are measured from `center`).
    pub axis: DVec3,
    /// Unit direction from the axis at angle 0.
    pub e1: DVec3,
    /// Unit direction from the axis at 90°, `e1 × axis`.
    pub e2: DVec3,
    /// Radius, m.
    pub radius: f64,
    /// Half the length along the axis, m.
    pub half_length: f64,
    /// `[start, end]`, rad, with `start < end ≤ start + 2π`.
    pub angles: [f64; 2],
}

impl CylinderShell {
    /// A shell about `axis` through `center`, of `radius` and `length` (m), spanning `angles`
    /// (rad) from `reference` (made perpendicular to the axis). `None` if the axis or the
    /// reference is degenerate, or the angles are out of order or span more than a turn.
    pub fn new(
        center: DVec3,
        axis: DVec3,
        reference: DVec3,
        radius: f64,
        length: f64,
        angles: [f64; 2],
    ) -> Option<CylinderShell> {
        let axis = axis.try_normalize()?;
        let e1 = (reference - axis * reference.dot(axis)).try_normalize()?;
        let ok =
            radius > 0.0 && length > 0.0 && angles[0] < angles[1] && angles[1] - angles[0] <= TAU + 1e-12;
        ok.then(|| CylinderShell {
            center,
            axis,
            e1,
            e2: e1.cross(axis),
            radius,
            half_length: length / 2.0,
            angles,
        })
    }

    /// Unit radial direction at angle `theta` (rad).
    #[inline]
    pub fn radial(&self, theta: f64) -> DVec3 {
        let (s, c) = theta.sin_cos();
        self.e1 * c + self.e2 * s
    }

    /// Unit tangent at angle `theta`, towards growing angles.
    #[inline]
    pub fn tangent(&self, theta: f64) -> DVec3 {
        let (s, c) = theta.sin_cos();
        self.e2 * c - self.e1 * s
    }

    /// The point at angle `theta` (rad), `z` (m) along the axis from the centre, `r` (m) from
    /// the axis.
    #[inline]
    pub fn point(&self, theta: f64, z: f64, r: f64) -> DVec3 {
        self.center + self.axis * z + self.radial(theta) * r
    }

    /// Cylindrical coordinates of `p`: angle in `[start, start + 2π)` (rad), position along the
    /// axis from the centre (m) and distance from the axis (m).
    #[inline]
    pub fn coordinates(&self, p: DVec3) -> (f64, f64, f64) {
        let d = p - self.center;
        let z = d.dot(self.axis);
        let (x, y) = (d.dot(self.e1), d.dot(self.e2));
        let phi = y.atan2(x);
        let theta = self.angles[0] + (phi - self.angles[0]).rem_euclid(TAU);
        (theta, z, x.hypot(y))
    }

    /// True if angle `theta` (as [`CylinderShell::coordinates`] gives it) and axial position
    /// `z` lie on the shell.
    #[inline]
    pub fn covers(&self, theta: f64, z: f64) -> bool {
        theta <= self.angles[1] && z.abs() <= self.half_length
    }

    /// The hit at `point` crossing the mantle while moving along `dir`: its normal faces the
    /// side the motion came from.
    fn hit(&self, t: f64, point: DVec3, dir: DVec3) -> Option<Hit> {
        let (theta, z, _) = self.coordinates(point);
        if !self.covers(theta, z) {
            return None;
        }
        let radial = self.radial(theta);
        let normal = if dir.dot(radial) > 0.0 { -radial } else { radial };
        Some(Hit { t, point, normal })
    }
}

impl Primitive for CylinderShell {
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (m, d) = (p0 - self.center, p1 - p0);
        let m_perp = m - self.axis * m.dot(self.axis);
        let d_perp = d - self.axis * d.dot(self.axis);
        let a = d_perp.length_squared();
        let b = m_perp.dot(d_perp);
        let c = m_perp.length_squared() - self.radius * self.radius;
        let disc = b * b - a * c;
        if a <= 0.0 || disc <= 0.0 {
            return None;
        }
        // Stable roots of a t² + 2 b t + c: q = −(b + sign(b) √disc).
        let q = -(b + b.signum() * disc.sqrt());
        let (r1, r2) = (q / a, c / q);
        let (lo, hi) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
        // Crossings alternate between entering and leaving the cylinder, starting from the side
        // the start lies on; one the other way (at t ≈ 0 by rounding) is the surface just left.
        let mut outside = c > 0.0;
        for t in [lo, hi] {
            let entering = (m_perp + d_perp * t).dot(d_perp) < 0.0;
            if entering != outside {
                continue;
            }
            if (0.0..=1.0).contains(&t)
                && let Some(hit) = self.hit(t, p0 + d * t, d)
            {
                return Some(hit);
            }
            outside = !outside;
        }
        None
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        let perp = arc.perpendicular(self.center, self.axis);
        let f = squared_norm(perp, self.radius);
        let mut outside = f[0] > 0.0;
        let df = derivative(&f);
        for &tau in roots(&f, 0.0, arc.duration).iter() {
            let slope = eval(&df, tau);
            // Entering from outside (f falls through 0) or leaving from inside (f rises), in
            // turn; a touch, or a crossing the other way at τ ≈ 0, is no crossing.
            if slope == 0.0 || (slope < 0.0) != outside {
                continue;
            }
            let h = hit_at(arc, tau, DVec3::ZERO);
            if tau > 0.0
                && let Some(hit) = self.hit(h.t, h.point, arc.velocity(tau))
            {
                return Some(hit);
            }
            outside = !outside;
        }
        None
    }

    fn aabb(&self) -> Option<Aabb> {
        // The arc's ends and, per axis, its extreme points where they lie within the range.
        let mut thetas = vec![self.angles[0], self.angles[1]];
        for k in 0..3 {
            let star = self.e2[k].atan2(self.e1[k]);
            for candidate in [star, star + std::f64::consts::PI] {
                let theta = self.angles[0] + (candidate - self.angles[0]).rem_euclid(TAU);
                if theta <= self.angles[1] {
                    thetas.push(theta);
                }
            }
        }
        let ends = self.axis * self.half_length;
        let mut b = Aabb { min: DVec3::INFINITY, max: DVec3::NEG_INFINITY };
        for theta in thetas {
            let p = self.center + self.radial(theta) * self.radius;
            for q in [p - ends, p + ends] {
                b = Aabb { min: b.min.min(q), max: b.max.max(q) };
            }
        }
        Some(b)
    }

    /// The angular range in strips of at most a `ROUND`th of a turn, normals outwards.
    fn tessellate(&self, _around: DVec3, _extent: f64) -> Option<Tessellation> {
        let [a0, a1] = self.angles;
        let strips = ((a1 - a0) / TAU * ROUND as f64).ceil().max(1.0) as usize;
        let mut t = Tessellation::default();
        for k in 0..strips {
            let (t0, t1) =
                (a0 + (a1 - a0) * k as f64 / strips as f64, a0 + (a1 - a0) * (k + 1) as f64 / strips as f64);
            let l = self.half_length;
            let corners = [
                self.point(t0, -l, self.radius),
                self.point(t1, -l, self.radius),
                self.point(t1, l, self.radius),
                self.point(t0, l, self.radius),
            ];
            t.quad(corners, self.radial(0.5 * (t0 + t1)));
        }
        Some(t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A tunnel arch: axis along y, 2 m radius, 4 m long, 0°–180° from +x through +z.
    fn arch() -> CylinderShell {
        CylinderShell::new(DVec3::ZERO, DVec3::Y, DVec3::X, 2.0, 4.0, [0.0, PI]).expect("valid")
    }

    #[test]
    fn angles_run_from_the_reference_over_the_top() {
        let s = arch();
        assert!(s.radial(0.5 * PI).abs_diff_eq(DVec3::Z, 1e-12), "90° is straight up");
        let (theta, z, r) = s.coordinates(DVec3::new(-2.0, 1.0, 0.0));
        assert!((theta - PI).abs() < 1e-12 && (z - 1.0).abs() < 1e-12 && (r - 2.0).abs() < 1e-12);
        let (below, _, _) = s.coordinates(DVec3::new(0.0, 0.0, -2.0));
        assert!(!s.covers(below, 0.0), "the invert is not part of the arch");
    }

    #[test]
    fn a_ray_from_the_axis_meets_the_lining_from_inside_and_misses_the_open_invert() {
        let s = arch();
        let up = s.intersect(DVec3::new(0.0, 0.5, 0.0), DVec3::new(0.0, 0.5, 5.0)).expect("hits the crown");
        assert!((up.point.z - 2.0).abs() < 1e-12 && up.normal.abs_diff_eq(-DVec3::Z, 1e-12));
        assert!(s.intersect(DVec3::ZERO, DVec3::new(0.0, 0.0, -5.0)).is_none(), "no invert");
        // From outside, the crown is met from above, its normal facing up.
        let down = s.intersect(DVec3::new(0.3, 0.0, 5.0), DVec3::new(0.3, 0.0, -5.0)).expect("hits");
        assert!(down.normal.z > 0.9 && (down.point.length() - 2.0).abs() < 1e-12);
        // Past the ends of the tunnel, nothing.
        assert!(s.intersect(DVec3::new(0.0, 2.5, 0.0), DVec3::new(0.0, 2.5, 5.0)).is_none());
        // Leaving the surface it has just struck, a path does not strike it again.
        let off = up.point + up.normal * 1e-9;
        assert!(s.intersect(off, off + DVec3::new(0.1, 0.0, -1.0)).is_none());
    }

    #[test]
    fn arcs_meet_the_shell_where_segments_do() {
        let s = arch();
        let arc = Flight {
            x0: DVec3::new(0.5, 0.2, 0.0),
            v0: DVec3::new(0.0, 0.0, 9.0),
            g: DVec3::new(0.0, 0.0, -9.81),
            duration: 1.0,
        };
        let hit = s.intersect_arc(&arc).expect("reaches the crown");
        assert!((hit.point.x.hypot(hit.point.z) - 2.0).abs() < 1e-9 && hit.normal.z < 0.0);
        // Rising 9 m/s against g, it reaches √(4 − 0.25) m after τ with z(τ) = 1.936.
        let z = (4.0f64 - 0.25).sqrt();
        let tau = (9.0 - (81.0 - 2.0 * 9.81 * z).sqrt()) / 9.81;
        assert!((hit.t - tau).abs() < 1e-9, "{} vs {tau}", hit.t);
    }

    #[test]
    fn the_bounding_box_is_the_arch_not_the_whole_cylinder() {
        let b = arch().aabb().expect("bounded");
        assert!(b.min.abs_diff_eq(DVec3::new(-2.0, -2.0, 0.0), 1e-9), "{b:?}");
        assert!(b.max.abs_diff_eq(DVec3::new(2.0, 2.0, 2.0), 1e-9), "{b:?}");
    }
}
