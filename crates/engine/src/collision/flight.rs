//! Exact impacts of a ballistic arc `x(τ) = x₀ + v₀ τ + ½ g τ²` with the primitives: the
//! earliest root in `(0, T]` of the polynomial (degree ≤ 4) that says where the arc meets each
//! surface, with the same conventions as the segment tests.

use super::Hit;
use glam::DVec3;

/// First `τ ≥ 0` at which `h(τ) = a τ² + b τ + c` becomes positive (0 if it already is or is
/// rising from 0; infinite if it never does).
fn first_rise(a: f64, b: f64, c: f64) -> f64 {
    if c > 0.0 || (c == 0.0 && (b > 0.0 || (b == 0.0 && a > 0.0))) {
        return 0.0;
    }
    if a == 0.0 {
        return if b > 0.0 { -c / b } else { f64::INFINITY };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 || (a < 0.0 && b <= 0.0) {
        // Never reaches 0, or (concave) falling from its start.
        return f64::INFINITY;
    }
    // Both roots without cancellation; with c ≤ 0, a convex h has one positive root and a
    // rising concave one two, of which the first counts.
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    let (r1, r2) = (q / a, if q != 0.0 { c / q } else { 0.0 });
    if a > 0.0 { r1.max(r2) } else { r1.min(r2) }
}

/// A flight under constant acceleration over `[0, duration]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// Start position, m.
    pub x0: DVec3,
    /// Start velocity, m/s.
    pub v0: DVec3,
    /// Acceleration, m/s².
    pub g: DVec3,
    /// Flight time, s.
    pub duration: f64,
}

impl Flight {
    /// Position at time `tau` (s).
    #[inline]
    pub fn at(&self, tau: f64) -> DVec3 {
        self.x0 + self.v0 * tau + 0.5 * self.g * tau * tau
    }

    /// Velocity at time `tau` (s).
    #[inline]
    pub fn velocity(&self, tau: f64) -> DVec3 {
        self.v0 + self.g * tau
    }

    /// First time (s) at which the arc, started inside `b`, leaves it (0 if it starts outside;
    /// infinite if it never leaves). The duration plays no part.
    pub fn exit_time(&self, b: &super::Aabb) -> f64 {
        let mut first = f64::INFINITY;
        for a in 0..3 {
            let (x, v, half_g) = (self.x0[a], self.v0[a], 0.5 * self.g[a]);
            // Past the upper bound: h = x(τ) − max > 0; past the lower: h = min − x(τ) > 0.
            first = first.min(first_rise(half_g, v, x - b.max[a]));
            first = first.min(first_rise(-half_g, -v, b.min[a] - x));
        }
        first
    }

    /// Bounding box of the arc: endpoints and, per axis, the apex if it falls inside.
    // Inlined everywhere: the arc is built just before, and reading it back from memory as
    // vectors stalls on the fields just written (once a tenth of a run's samples).
    #[inline(always)]
    pub fn aabb(&self) -> super::Aabb {
        let end = self.at(self.duration);
        let mut b = super::Aabb::from_points(self.x0, end);
        for a in 0..3 {
            if self.g[a] != 0.0 {
                let apex = -self.v0[a] / self.g[a];
                if apex > 0.0 && apex < self.duration {
                    let p = self.at(apex)[a];
                    b.min[a] = b.min[a].min(p);
                    b.max[a] = b.max[a].max(p);
                }
            }
        }
        b
    }

    /// Bounding boxes of the arc's `N` equal stretches, which together hold it more tightly
    /// than its one box.
    pub fn piece_boxes<const N: usize>(&self) -> [super::Aabb; N] {
        let step = self.duration / N as f64;
        std::array::from_fn(|k| {
            let t = step * k as f64;
            Flight { x0: self.at(t), v0: self.velocity(t), g: self.g, duration: step }.aabb()
        })
    }

    /// `(q(τ) − origin)·dir` as a quadratic `[c₀, c₁, c₂]` in τ.
    #[inline]
    pub(crate) fn along(&self, origin: DVec3, dir: DVec3) -> [f64; 3] {
        [(self.x0 - origin).dot(dir), self.v0.dot(dir), 0.5 * self.g.dot(dir)]
    }

    /// Component of `q(τ) − origin` perpendicular to unit `axis`, as vector coefficients.
    #[inline]
    pub(crate) fn perpendicular(&self, origin: DVec3, axis: DVec3) -> [DVec3; 3] {
        let rej = |v: DVec3| v - axis * v.dot(axis);
        [rej(self.x0 - origin), rej(self.v0), rej(0.5 * self.g)]
    }
}

/// `|c₀ + c₁ τ + c₂ τ²|² − r²` as a quartic.
pub(crate) fn squared_norm(c: [DVec3; 3], r: f64) -> [f64; 5] {
    [
        c[0].dot(c[0]) - r * r,
        2.0 * c[0].dot(c[1]),
        c[1].dot(c[1]) + 2.0 * c[0].dot(c[2]),
        2.0 * c[1].dot(c[2]),
        c[2].dot(c[2]),
    ]
}

/// The polynomial `c` (low to high) at `t`.
#[inline]
pub(crate) fn eval(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &ci| acc * t + ci)
}

/// A short list of at most eight numbers kept on the stack (a polynomial's coefficients, its
/// roots in an interval): the root finder runs once per candidate surface per step, where heap
/// vectors would cost more than the arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShortList {
    items: [f64; 8],
    len: usize,
}

impl ShortList {
    fn push(&mut self, x: f64) {
        // Degree ≤ 4 keeps every list within 6 (roots and the knots between them).
        debug_assert!(self.len < self.items.len());
        if self.len < self.items.len() {
            self.items[self.len] = x;
            self.len += 1;
        }
    }

    /// Drops consecutive repeats.
    fn dedup(&mut self) {
        let mut n = 0;
        for i in 0..self.len {
            if n == 0 || self.items[i] != self.items[n - 1] {
                self.items[n] = self.items[i];
                n += 1;
            }
        }
        self.len = n;
    }
}

impl std::ops::Deref for ShortList {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        &self.items[..self.len]
    }
}

/// The derivative of the polynomial `c` (low to high).
pub(crate) fn derivative(c: &[f64]) -> ShortList {
    let mut d = ShortList::default();
    c.iter().enumerate().skip(1).for_each(|(i, &ci)| d.push(i as f64 * ci));
    d
}

/// Real roots of the polynomial `c` (low to high, degree ≤ 4) in `[lo, hi]`, ascending. Roots
/// of the derivative split the interval into monotone pieces, each narrowed to adjacent
/// floats, so no root is missed whatever the step; a root where the polynomial only touches
/// zero counts. Quadratics are solved in closed form.
pub fn roots(c: &[f64], lo: f64, hi: f64) -> ShortList {
    let deg = c.iter().rposition(|&x| x != 0.0).unwrap_or(0);
    let c = &c[..=deg];
    let mut out = ShortList::default();
    if deg == 0 {
        return out;
    }
    if deg == 1 {
        let r = -c[0] / c[1];
        if (lo..=hi).contains(&r) {
            out.push(r);
        }
        return out;
    }
    if deg == 2 {
        return quadratic_roots(c, lo, hi);
    }
    let mut knots = ShortList::default();
    knots.push(lo);
    let dc = derivative(c);
    roots(&dc, lo, hi).iter().filter(|&&r| r > lo && r < hi).for_each(|&r| knots.push(r));
    knots.push(hi);
    for w in knots.windows(2) {
        let (a, b) = (w[0], w[1]);
        let (fa, fb) = (eval(c, a), eval(c, b));
        if fa == 0.0 {
            out.push(a);
            continue;
        }
        if fa.signum() == fb.signum() {
            continue;
        }
        if fb == 0.0 {
            continue; // the next piece starts at b and records it
        }
        out.push(narrow(c, &dc, (a, fa), (b, fb)));
    }
    if eval(c, hi) == 0.0 && out.last() != Some(&hi) {
        out.push(hi);
    }
    out.dedup();
    out
}

/// Roots of the quadratic `c` (low to high, `c[2] ≠ 0`) in `[lo, hi]`, ascending, without
/// cancellation; a double root counts once.
fn quadratic_roots(c: &[f64], lo: f64, hi: f64) -> ShortList {
    let mut out = ShortList::default();
    let disc = c[1] * c[1] - 4.0 * c[2] * c[0];
    if disc < 0.0 {
        return out;
    }
    let q = -0.5 * (c[1] + disc.sqrt().copysign(c[1]));
    let (r1, r2) = (q / c[2], if q != 0.0 { c[0] / q } else { 0.0 });
    for r in [r1.min(r2), r1.max(r2)] {
        if (lo..=hi).contains(&r) {
            out.push(r);
        }
    }
    out.dedup();
    out
}

/// Newton steps [`narrow`] takes before it leaves the root to the bracketing method.
const NEWTON_STEPS: usize = 12;

/// Floats [`narrow`] steps over, one by one, from where Newton's method settled.
const FLOAT_STEPS: usize = 8;

/// The root of `c` (derivative `dc`) in `(a, b)`, where it changes sign once (`fa`, `fb`:
/// its values at the ends, neither 0): the first float at which it has `fb`'s sign, with the
/// bracket narrowed down to adjacent floats. Newton's method, started at the secant point
/// and kept inside the bracket (which every value it computes narrows), settles on the root
/// in a few evaluations; the float where the sign turns is then found by stepping over the
/// floats next to it. Where either stalls, [`narrow_bracket`] finishes. As long as the
/// computed sign turns once in the bracket (the values rounding makes of the polynomial do
/// not flicker about its root), that float is the same whichever way it is found.
fn narrow(c: &[f64], dc: &[f64], (mut a, mut fa): (f64, f64), (mut b, mut fb): (f64, f64)) -> f64 {
    let up = fb > 0.0;
    // Whether `f` has `fb`'s sign (0 counts with `fa`'s when rising, with `fb`'s when falling).
    let b_side = |f: f64| (f > 0.0) == up;
    let secant = (a * fb - b * fa) / (fb - fa);
    let mut x = if secant > a && secant < b { secant } else { 0.5 * (a + b) };
    let mut settled = false;
    for _ in 0..NEWTON_STEPS {
        let fx = eval(c, x);
        if b_side(fx) {
            (b, fb) = (x, fx);
        } else {
            (a, fa) = (x, fx);
        }
        let mut next = x - fx / eval(dc, x);
        // Settled when the step is within rounding (it then often lands on `x` itself, an end
        // of the bracket).
        if (next - x).abs() <= 4.0 * f64::EPSILON * x.abs() {
            settled = true;
            break;
        }
        if !(next > a && next < b) {
            next = 0.5 * (a + b);
            if next <= a || next >= b {
                return b;
            }
        }
        x = next;
    }
    if settled {
        // `x` is an end of the bracket: step from it towards the other end until the sign
        // turns.
        for _ in 0..FLOAT_STEPS {
            let p = if x == b { b.next_down() } else { a.next_up() };
            if p <= a || p >= b {
                return b;
            }
            let fp = eval(c, p);
            if b_side(fp) {
                (b, fb) = (p, fp);
            } else {
                (a, fa) = (p, fp);
            }
            if x == b && p == a || x == a && p == b {
                return b;
            }
            x = p;
        }
    }
    narrow_bracket(c, (a, fa), (b, fb))
}

/// [`narrow`] by false position with the Illinois rule, and every third step by bisection,
/// down to adjacent floats.
fn narrow_bracket(c: &[f64], (mut a, mut fa): (f64, f64), (mut b, mut fb): (f64, f64)) -> f64 {
    let up = fb > 0.0;
    // Which end the last step moved (-1: a, 1: b), to halve the other's value when one end
    // moves twice in a row.
    let mut moved = 0;
    for k in 0.. {
        let secant = (a * fb - b * fa) / (fb - fa);
        let mut m = if k % 3 == 2 || !(secant > a && secant < b) { 0.5 * (a + b) } else { secant };
        if m <= a || m >= b {
            m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
        }
        let fm = eval(c, m);
        if (fm > 0.0) == up {
            (b, fb) = (m, fm);
            if moved == 1 {
                fa *= 0.5;
            }
            moved = 1;
        } else {
            (a, fa) = (m, fm);
            if moved == -1 {
                fb *= 0.5;
            }
            moved = -1;
        }
    }
    b
}

/// A hit at time `tau` (s) of the arc, with `Hit::t` the fraction of its duration.
pub(crate) fn hit_at(arc: &Flight, tau: f64, normal: DVec3) -> Hit {
    Hit { t: (tau / arc.duration).clamp(0.0, 1.0), point: arc.at(tau), normal }
}

/// First root of `f` in `(0, T]` at which `f` goes from positive to non-positive and `accept`
/// holds at the hit point.
pub(crate) fn first_entry(arc: &Flight, f: &[f64], accept: impl Fn(f64) -> bool) -> Option<f64> {
    let df = derivative(f);
    roots(f, 0.0, arc.duration).iter().copied().find(|&tau| tau > 0.0 && eval(&df, tau) <= 0.0 && accept(tau))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots_of_a_quartic_are_found_in_order_and_to_full_precision() {
        // (t − 0.1)(t − 0.2)(t − 0.7)(t + 3)
        let r = [0.1, 0.2, 0.7, -3.0];
        let mut c = [1.0, 0.0, 0.0, 0.0, 0.0];
        for root in r {
            let mut next = [0.0; 5];
            for k in 0..5 {
                next[k] = -root * c[k] + if k > 0 { c[k - 1] } else { 0.0 };
            }
            c = next;
        }
        let found = roots(&c, 0.0, 1.0);
        assert_eq!(found.len(), 3, "{found:?}");
        for (f, want) in found.iter().zip([0.1, 0.2, 0.7]) {
            assert!((f - want).abs() < 1e-14, "{f} vs {want}");
        }
        // A double root (touching zero) counts once.
        let touch = roots(&[0.25, -1.0, 1.0], 0.0, 1.0);
        assert_eq!(touch.len(), 1);
        assert!((touch[0] - 0.5).abs() < 1e-7);
    }

    /// The coefficients (low to high) of the monic polynomial with roots `r`.
    fn from_roots(r: &[f64]) -> Vec<f64> {
        let mut c = vec![1.0];
        for &root in r {
            let mut next = vec![0.0; c.len() + 1];
            for (k, &ck) in c.iter().enumerate() {
                next[k + 1] += ck;
                next[k] -= root * ck;
            }
            c = next;
        }
        c
    }

    /// Newton's method with the float-by-float finish settles on a float where the computed
    /// sign turns, as the bracketing method does, and where the polynomial is zero as far as
    /// it can be evaluated (within the rounding of Horner's scheme). Where the sign turns once
    /// the two find the same float; where rounding makes it flicker about the root they may
    /// settle on different floats of that zone (the rounding over the slope either side of
    /// the root), equally good: on these polynomials more than half the roots are the same to
    /// the bit. Checked on the monotone pieces of 20 000 random cubics and quartics with roots
    /// within a flight's duration, every fifth with two roots a nanosecond apart.
    #[test]
    fn newton_settles_on_a_float_where_the_sign_turns() {
        // In [0, 1): exactly the generator's numbers mapped back from [−1, 1).
        let mut uniform = crate::collision::testing::uniform(0x9E37_79B9_7F4A_7C15);
        let mut next = move || 0.5 + 0.5 * uniform();
        let (mut pieces, mut same) = (0, 0);
        for k in 0..20_000 {
            let degree = 3 + k % 2;
            let mut r: Vec<f64> = (0..degree).map(|_| 0.1 * next() - 0.02).collect();
            if k % 5 == 0 {
                r[1] = r[0] + 1e-9 * next();
            }
            let scale = 10f64.powf(6.0 * next() - 3.0);
            let c: Vec<f64> = from_roots(&r).iter().map(|ci| ci * scale).collect();
            let dc = derivative(&c);
            let mut knots = vec![0.0];
            knots.extend(roots(&dc, 0.0, 0.1).iter().filter(|&&t| t > 0.0 && t < 0.1));
            knots.push(0.1);
            for w in knots.windows(2) {
                let (a, b) = (w[0], w[1]);
                let (fa, fb) = (eval(&c, a), eval(&c, b));
                if fa == 0.0 || fb == 0.0 || fa.signum() == fb.signum() {
                    continue;
                }
                pieces += 1;
                let fast = narrow(&c, &dc, (a, fa), (b, fb));
                let plain = narrow_bracket(&c, (a, fa), (b, fb));
                let b_side = |t: f64| (eval(&c, t) > 0.0) == (fb > 0.0);
                for t in [fast, plain] {
                    assert!(t > a && t <= b, "{t} outside ({a}, {b}]");
                    assert!(b_side(t) && !b_side(t.next_down()), "the sign does not turn at {t}");
                    let size: f64 = c.iter().rev().fold(0.0, |acc, ci| acc * t + ci.abs());
                    let rounding = 4.0 * c.len() as f64 * f64::EPSILON * size;
                    assert!(eval(&c, t).abs() <= rounding, "{t} is no root in ({a}, {b})");
                }
                // Both lie within the zone where rounding hides the sign: about the rounding
                // over the slope either side of the root.
                let size = c.iter().rev().fold(0.0, |acc: f64, ci| acc * plain + ci.abs());
                let zone = 4.0 * c.len() as f64 * f64::EPSILON * size / eval(&dc, plain).abs();
                let ulp = plain.next_up() - plain;
                assert!(
                    (fast - plain).abs() <= 2.0 * zone + 4.0 * ulp,
                    "{fast} against {plain} in ({a}, {b})"
                );
                same += usize::from(fast == plain);
            }
        }
        assert!(pieces > 20_000 && same > pieces / 4, "{same} of {pieces} the same");
    }

    use crate::collision::{Plane, Primitive, Shape};

    #[test]
    fn a_dropped_particle_meets_the_floor_at_the_closed_form_time() {
        let arc = Flight {
            x0: DVec3::new(0.0, 0.0, 1.0),
            v0: DVec3::new(2.0, 0.0, 0.0),
            g: DVec3::new(0.0, 0.0, -9.81),
            duration: 1.0,
        };
        let floor = Shape::Plane(Plane { point: DVec3::ZERO, normal: DVec3::Z });
        let h = floor.intersect_arc(&arc).expect("lands");
        let t = (2.0 / 9.81_f64).sqrt();
        assert!((h.t - t).abs() < 1e-15 && h.normal == DVec3::Z);
        assert!((h.point.x - 2.0 * t).abs() < 1e-14 && h.point.z.abs() < 1e-14);
    }
}
