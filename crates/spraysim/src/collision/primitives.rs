//! Geometric primitives and their algebraic segment intersections.

use super::Hit;
use glam::DVec3;

/// Axis-aligned bounding box, m.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Aabb {
    /// Lower corner, m.
    pub min: DVec3,
    /// Upper corner, m.
    pub max: DVec3,
}

impl Aabb {
    /// Box spanning two points.
    pub fn from_points(a: DVec3, b: DVec3) -> Self {
        Self { min: a.min(b), max: a.max(b) }
    }

    /// Grows the box by `margin` (m) on every side.
    pub fn inflate(self, margin: f64) -> Self {
        Self { min: self.min - DVec3::splat(margin), max: self.max + DVec3::splat(margin) }
    }

    /// True if the two boxes overlap (touching counts).
    #[inline]
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.cmple(other.max).all() && other.min.cmple(self.max).all()
    }

    /// True if `p` lies inside or on the box.
    #[inline]
    pub fn contains(&self, p: DVec3) -> bool {
        self.min.cmple(p).all() && p.cmple(self.max).all()
    }
}

/// Infinite plane through `point` with unit `normal`; two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point on the plane, m.
    pub point: DVec3,
    /// Unit normal.
    pub normal: DVec3,
}

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

/// Flat disk; two-sided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    /// Centre, m.
    pub center: DVec3,
    /// Unit normal.
    pub normal: DVec3,
    /// Radius, m.
    pub radius: f64,
}

/// Solid sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, m.
    pub center: DVec3,
    /// Radius, m.
    pub radius: f64,
}

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

    /// Earliest hit of the segment `p0 → p1`.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.corners[0], self.normal, p0, p1)?;
        let point = p0.lerp(p1, t);
        self.covers(point).then(|| Hit { t, point, normal: facing(self.normal, d0) })
    }
}

/// Any collision primitive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Infinite plane.
    Plane(Plane),
    /// Finite rectangle.
    Face(Face),
    /// Disk.
    Disk(Disk),
    /// Sphere.
    Sphere(Sphere),
    /// Oriented box.
    Box(OrientedBox),
    /// Capped cylinder.
    Cylinder(Cylinder),
    /// Mesh triangle.
    Triangle(Triangle),
}

impl Shape {
    /// Earliest hit of the segment `p0 → p1`, if any.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        match self {
            Shape::Plane(s) => s.intersect(p0, p1),
            Shape::Face(s) => s.intersect(p0, p1),
            Shape::Disk(s) => s.intersect(p0, p1),
            Shape::Sphere(s) => s.intersect(p0, p1),
            Shape::Box(s) => s.intersect(p0, p1),
            Shape::Cylinder(s) => s.intersect(p0, p1),
            Shape::Triangle(s) => s.intersect(p0, p1),
        }
    }

    /// Bounding box, or `None` for an unbounded plane.
    pub fn aabb(&self) -> Option<Aabb> {
        match self {
            Shape::Plane(_) => None,
            Shape::Face(f) => {
                let e = (f.right * f.half_width).abs() + (f.up * f.half_height).abs();
                Some(Aabb { min: f.center - e, max: f.center + e })
            }
            Shape::Disk(d) => {
                // Extent of a disk along world axis i is r·sqrt(1 − n_i²).
                let e = (DVec3::ONE - d.normal * d.normal).max(DVec3::ZERO).map(f64::sqrt) * d.radius;
                Some(Aabb { min: d.center - e, max: d.center + e })
            }
            Shape::Sphere(s) => {
                Some(Aabb { min: s.center - DVec3::splat(s.radius), max: s.center + DVec3::splat(s.radius) })
            }
            Shape::Box(b) => {
                let e = (b.axes[0] * b.half_extents.x).abs()
                    + (b.axes[1] * b.half_extents.y).abs()
                    + (b.axes[2] * b.half_extents.z).abs();
                Some(Aabb { min: b.center - e, max: b.center + e })
            }
            Shape::Triangle(t) => {
                let [a, b, c] = t.corners;
                Some(Aabb { min: a.min(b).min(c), max: a.max(b).max(c) })
            }
            Shape::Cylinder(c) => {
                let axis = (c.b - c.a).normalize_or_zero();
                let e = (DVec3::ONE - axis * axis).max(DVec3::ZERO).map(f64::sqrt) * c.radius;
                Some(Aabb { min: c.a.min(c.b) - e, max: c.a.max(c.b) + e })
            }
        }
    }

    /// True if `p` lies strictly inside a closed solid (always false for thin surfaces).
    pub fn contains(&self, p: DVec3) -> bool {
        match self {
            Shape::Plane(_) | Shape::Face(_) | Shape::Disk(_) | Shape::Triangle(_) => false,
            Shape::Sphere(s) => (p - s.center).length_squared() < s.radius * s.radius,
            Shape::Box(b) => {
                let d = p - b.center;
                (0..3).all(|i| d.dot(b.axes[i]).abs() < b.half_extents[i])
            }
            Shape::Cylinder(c) => {
                let axis = c.b - c.a;
                let len = axis.length();
                let u = axis / len;
                let s = (p - c.a).dot(u);
                let radial = (p - c.a) - u * s;
                s > 0.0 && s < len && radial.length_squared() < c.radius * c.radius
            }
        }
    }
}

/// Crossing of the segment with the plane through `point` with unit `normal`: the fraction `t`
/// and the signed start distance. A segment that starts exactly on the plane does not cross it
/// (particles are always lifted off a surface after an impact).
#[inline]
fn plane_crossing(point: DVec3, normal: DVec3, p0: DVec3, p1: DVec3) -> Option<(f64, f64)> {
    let d0 = (p0 - point).dot(normal);
    let d1 = (p1 - point).dot(normal);
    let crosses = (d0 > 0.0 && d1 <= 0.0) || (d0 < 0.0 && d1 >= 0.0);
    if !crosses {
        return None;
    }
    Some(((d0 / (d0 - d1)).clamp(0.0, 1.0), d0))
}

#[inline]
fn facing(normal: DVec3, d0: f64) -> DVec3 {
    if d0 > 0.0 { normal } else { -normal }
}

impl Plane {
    /// Earliest hit of the segment `p0 → p1`.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.point, self.normal, p0, p1)?;
        Some(Hit { t, point: p0.lerp(p1, t), normal: facing(self.normal, d0) })
    }
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

    /// Earliest hit of the segment `p0 → p1`.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.center, self.normal, p0, p1)?;
        let point = p0.lerp(p1, t);
        let (u, v) = self.local(point);
        (u.abs() <= self.half_width && v.abs() <= self.half_height).then(|| Hit {
            t,
            point,
            normal: facing(self.normal, d0),
        })
    }
}

impl Disk {
    /// Earliest hit of the segment `p0 → p1`.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (t, d0) = plane_crossing(self.center, self.normal, p0, p1)?;
        let point = p0.lerp(p1, t);
        ((point - self.center).length_squared() <= self.radius * self.radius).then(|| Hit {
            t,
            point,
            normal: facing(self.normal, d0),
        })
    }
}

/// Smallest root in `[0, 1]` of `a t² + 2 b t + c = 0` for a segment entering a quadric from
/// outside (`c > 0`), using the half-b form, which loses less precision.
#[inline]
fn entry_root(a: f64, b: f64, c: f64) -> Option<f64> {
    if a <= 0.0 || b >= 0.0 {
        // Not moving, or moving away from the surface.
        return None;
    }
    let disc = b * b - a * c;
    if disc < 0.0 {
        return None;
    }
    // -b > 0 here, so this form avoids cancellation: t = c / (-b + sqrt(disc)).
    let t = c / (-b + disc.sqrt());
    (0.0..=1.0).contains(&t).then_some(t)
}

impl Sphere {
    /// Earliest hit of the segment `p0 → p1`; `t = 0` if `p0` is inside.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
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
}

impl OrientedBox {
    /// Earliest hit of the segment `p0 → p1` (slab method); `t = 0` if `p0` is inside.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
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
            // Push out through the nearest face.
            let (i, o) = (0..3)
                .map(|i| (i, rel.dot(self.axes[i])))
                .min_by(|x, y| {
                    (self.half_extents[x.0] - x.1.abs()).total_cmp(&(self.half_extents[y.0] - y.1.abs()))
                })
                .unwrap_or((0, 0.0));
            return Some(Hit { t: 0.0, point: p0, normal: self.axes[i] * o.signum() });
        }
        if t_enter > t_exit || !(0.0..=1.0).contains(&t_enter) {
            return None;
        }
        Some(Hit { t: t_enter, point: p0 + d * t_enter, normal: self.axes[enter_axis] * enter_sign })
    }
}

impl Cylinder {
    /// Earliest hit of the segment `p0 → p1` with the mantle or either cap; `t = 0` if `p0` is
    /// inside.
    #[inline]
    pub fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
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
}
