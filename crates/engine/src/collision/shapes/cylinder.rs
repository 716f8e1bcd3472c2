//! Solid capped cylinders: rebar, pipes.

use super::{Primitive, Tessellation, basis, entry_root, tessellation::ROUND};
use crate::collision::flight::{Flight, derivative, eval, first_entry, hit_at, roots, squared_norm};
use crate::collision::{Aabb, Hit};
use glam::DVec3;

/// Solid cylinder with flat caps, from `a` to `b` (a rebar, a pipe).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    /// Centre of the first cap, m.
    pub a: DVec3,
    /// Centre of the second cap, m.
    pub b: DVec3,
    /// Radius, m.
    pub radius: f64,
}

/// A lower bound of the distance from the axis of `q(τ) = c₀ + c₁ τ + c₂ τ²` (its component
/// perpendicular to the axis, see [`Flight::perpendicular`]) over `[0, duration]`, m: the distance
/// of its chord less the most the curve strays from the chord, |c₂| T²/4.
#[inline]
fn axis_gap(c: &[DVec3; 3], duration: f64) -> f64 {
    let t = duration;
    let (p0, d) = (c[0], c[1] * t + c[2] * (t * t));
    let dd = d.length_squared();
    let k = if dd > 0.0 { (-p0.dot(d) / dd).clamp(0.0, 1.0) } else { 0.0 };
    (p0 + d * k).length() - 0.25 * c[2].length() * t * t
}

impl Primitive for Cylinder {
    /// Earliest hit of the segment `p0 → p1` with the mantle or either cap; `t = 0` if `p0` is
    /// inside.
    #[inline]
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let axis = self.b - self.a;
        let len = axis.length();
        let u = axis / len;
        let m = p0 - self.a;
        let d = p1 - p0;
        let ms = m.dot(u);
        let ds = d.dot(u);
        let m_perp = m - u * ms;
        let d_perp = d - u * ds;
        let r2 = self.radius * self.radius;
        let c = m_perp.length_squared() - r2;
        if c < 0.0 && ms > 0.0 && ms < len {
            // Inside: push out through the nearest of mantle and caps.
            let to_mantle = self.radius - m_perp.length();
            let normal = if to_mantle <= ms.min(len - ms) {
                m_perp.normalize_or(u.any_orthonormal_vector())
            } else if ms < len - ms {
                -u
            } else {
                u
            };
            return Some(Hit { t: 0.0, point: p0, normal });
        }
        let mut best: Option<Hit> = None;
        if c >= 0.0
            && let Some(t) = entry_root(d_perp.length_squared(), m_perp.dot(d_perp), c)
        {
            let s = ms + ds * t;
            if (0.0..=len).contains(&s) {
                let radial = m_perp + d_perp * t;
                best = Some(Hit { t, point: p0 + d * t, normal: radial.normalize_or(u) });
            }
        }
        // Caps: entered from outside along the axis.
        for (cap_s, normal) in [(0.0, -u), (len, u)] {
            let outside = if cap_s == 0.0 { ms < 0.0 } else { ms > len };
            if !outside || ds == 0.0 {
                continue;
            }
            let t = (cap_s - ms) / ds;
            if !(0.0..=1.0).contains(&t) || best.is_some_and(|h| h.t <= t) {
                continue;
            }
            let radial = m_perp + d_perp * t;
            if radial.length_squared() <= r2 {
                best = Some(Hit { t, point: p0 + d * t, normal });
            }
        }
        best
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        let (len, u) = self.axis();
        let perp = arc.perpendicular(self.a, u);
        // Every hit, and a start inside, needs the arc within the radius of the axis: most arcs
        // a broad phase hands over pass by, and a bound on their distance spares the quartic.
        if self.passes_by(&perp, arc.duration) {
            return None;
        }
        self.solve_arc(arc, (len, u), perp)
    }

    fn aabb(&self) -> Option<Aabb> {
        let axis = (self.b - self.a).normalize_or_zero();
        let e = (DVec3::ONE - axis * axis).max(DVec3::ZERO).map(f64::sqrt) * self.radius;
        Some(Aabb { min: self.a.min(self.b) - e, max: self.a.max(self.b) + e })
    }

    fn contains(&self, p: DVec3) -> bool {
        let axis = self.b - self.a;
        let len = axis.length();
        let u = axis / len;
        let s = (p - self.a).dot(u);
        let radial = (p - self.a) - u * s;
        s > 0.0 && s < len && radial.length_squared() < self.radius * self.radius
    }

    /// The mantle (a ring of vertices at each cap, radial normals) and the two caps; nothing for
    /// a bar of no length.
    fn tessellate(&self, _around: DVec3, _extent: f64) -> Option<Tessellation> {
        let mut t = Tessellation::default();
        let Some(n) = (self.b - self.a).try_normalize() else { return Some(t) };
        let (u, v) = basis(n);
        let ring = |k: usize| {
            let a = std::f64::consts::TAU * k as f64 / ROUND as f64;
            u * a.cos() + v * a.sin()
        };
        for k in 0..ROUND {
            let r = ring(k);
            t.vertex(self.a + r * self.radius, r);
            t.vertex(self.b + r * self.radius, r);
        }
        for k in 0..ROUND as u32 {
            let (a0, b0) = (2 * k, 2 * k + 1);
            let next = (k + 1) % ROUND as u32;
            let (a1, b1) = (2 * next, 2 * next + 1);
            t.triangles.extend([[a0, a1, b1], [a0, b1, b0]]);
        }
        for (centre, normal) in [(self.a, -n), (self.b, n)] {
            t.disk(centre, (u, v), self.radius, normal);
        }
        Some(t)
    }
}

impl Cylinder {
    /// Length of the axis (m) and its unit direction from `a` to `b`.
    #[inline]
    fn axis(&self) -> (f64, DVec3) {
        let axis = self.b - self.a;
        let len = axis.length();
        (len, axis / len)
    }

    /// True if an arc whose component perpendicular to the axis is `perp` (see
    /// [`Flight::perpendicular`]) stays, over `duration` (s), certainly farther from the axis
    /// than the radius: it can neither hit the bar nor start inside it.
    #[inline]
    fn passes_by(&self, perp: &[DVec3; 3], duration: f64) -> bool {
        axis_gap(perp, duration) > self.radius * (1.0 + 1e-9) + 1e-12
    }

    /// The earliest hit of the arc with the mantle or either cap, solved in full (the quartic
    /// of the mantle, the caps' quadratics), without the distance bound that
    /// [`Primitive::intersect_arc`] rejects passing arcs by first; `(len, u)` is
    /// [`Cylinder::axis`] and `perp` the arc's component perpendicular to it.
    fn solve_arc(&self, arc: &Flight, (len, u): (f64, DVec3), perp: [DVec3; 3]) -> Option<Hit> {
        if let Some(h) = super::inside_start(self, arc) {
            return Some(h);
        }
        let s = arc.along(self.a, u);
        let radial2 = |tau: f64| (perp[0] + perp[1] * tau + perp[2] * tau * tau).length_squared();
        let r2 = self.radius * self.radius;
        let mut best: Option<Hit> = None;
        let mantle = squared_norm(perp, self.radius);
        if let Some(tau) = first_entry(arc, &mantle, |tau| (0.0..=len).contains(&eval(&s, tau))) {
            let radial = perp[0] + perp[1] * tau + perp[2] * tau * tau;
            best = Some(hit_at(arc, tau, radial.normalize_or(u)));
        }
        let ds = derivative(&s);
        for (level, normal, entering_up) in [(0.0, -u, true), (len, u, false)] {
            let shifted = [s[0] - level, s[1], s[2]];
            for &tau in roots(&shifted, 0.0, arc.duration).iter() {
                let slope = eval(&ds, tau);
                let entering = if entering_up { slope > 0.0 } else { slope < 0.0 };
                if tau > 0.0 && entering && radial2(tau) <= r2 {
                    if best.is_none_or(|b| hit_at(arc, tau, normal).t < b.t) {
                        best = Some(hit_at(arc, tau, normal));
                    }
                    break;
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::testing::uniform;

    /// The rejection bound never exceeds the arc's true least distance from the axis, so a
    /// rejected arc can hit nothing: checked on random quadratics against a fine sampling.
    #[test]
    fn the_axis_gap_is_a_lower_bound_of_the_distance_from_the_axis() {
        let mut next = uniform(0x2545_F491_4F6C_DD1D);
        let mut tight = 0;
        for _ in 0..2000 {
            let c = [
                DVec3::new(next(), next(), 0.0) * 0.1,
                DVec3::new(next(), next(), 0.0) * 30.0,
                DVec3::new(next(), next(), 0.0) * 5.0,
            ];
            let t = 0.002 + 0.06 * (next() + 1.0);
            let gap = axis_gap(&c, t);
            let least = (0..=4000)
                .map(|k| t * f64::from(k) / 4000.0)
                .map(|tau| (c[0] + c[1] * tau + c[2] * tau * tau).length())
                .fold(f64::INFINITY, f64::min);
            assert!(gap <= least + 1e-12, "gap {gap} above the least distance {least}");
            tight += usize::from(least - gap < 0.01);
        }
        assert!(tight > 1000, "the bound is too loose to reject anything: {tight} of 2000 within 1 cm");
    }

    /// The rejection never changes the answer: arcs of every speed and direction near bars of
    /// every orientation (horizontal, vertical, oblique), many of them grazing, starting inside
    /// or ending on a cap, get exactly the hit the full solution finds, and most that miss are
    /// rejected without it.
    #[test]
    fn rejecting_passing_arcs_keeps_every_hit() {
        let mut next = uniform(0x9E37_79B9_7F4A_7C15);
        let g = DVec3::new(0.0, 0.0, -9.81);
        let (mut hits, mut rejected, mut misses) = (0, 0, 0);
        for k in 0..20_000 {
            let axis = match k % 3 {
                0 => DVec3::Y,
                1 => DVec3::Z,
                _ => DVec3::new(next(), next(), next()).normalize(),
            };
            let bar = Cylinder { a: -0.3 * axis, b: 0.3 * axis, radius: 0.008 };
            // Aimed at a point near the axis (some inside the bar, some at its ends), from up to
            // 5 cm away, at 0.5 to 30 m/s, over one to eight steps of 1 ms.
            let aim = axis * (0.35 * next()) + DVec3::new(next(), next(), next()) * 0.012;
            let speed = 0.5 + 29.5 * (0.5 + 0.5 * next());
            let dir = DVec3::new(next(), next(), next()).normalize();
            let arc = Flight {
                x0: aim - dir * (0.05 * (0.5 + 0.5 * next())),
                v0: dir * speed,
                g,
                duration: 1e-3 * f64::from(1 + k % 8),
            };
            let (len, u) = bar.axis();
            let perp = arc.perpendicular(bar.a, u);
            let full = bar.solve_arc(&arc, (len, u), perp);
            assert_eq!(bar.intersect_arc(&arc), full, "arc {arc:?}");
            match full {
                Some(_) => hits += 1,
                None if bar.passes_by(&perp, arc.duration) => rejected += 1,
                None => misses += 1,
            }
        }
        assert!(
            hits > 1000 && rejected > 2 * misses,
            "{hits} hits, {rejected} rejected, {misses} solved misses"
        );
    }
}
