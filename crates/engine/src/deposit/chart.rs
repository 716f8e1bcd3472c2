//! Charts: how a heightfield lies on its bare surface, unrolled. A chart maps points in space
//! to the grid's coordinates `(u, v)` (m along the unrolled width and height, from the middle)
//! and a height above the bare surface on the receiving side, and back.

use super::MapAxis;
use crate::collision::{Aabb, CylinderShell, Face, Shape};
use glam::DVec3;
use std::f64::consts::PI;

/// How a heightfield lies on its bare surface.
pub trait Chart: Clone + Send + Sync + std::fmt::Debug + 'static {
    /// Width (along `u`) and height (along `v`) of the unrolled surface, m.
    fn size(&self) -> (f64, f64);

    /// Unrolled coordinates `(u, v)` of `p` (m from the middle) and its height above the bare
    /// surface on the receiving side (m; negative behind it).
    fn local(&self, p: DVec3) -> (f64, f64, f64);

    /// The point at `(u, v)` raised by `height` (m) on the receiving side.
    fn point(&self, u: f64, v: f64, height: f64) -> DVec3;

    /// At `(u, v)`: the receiving unit normal, and the unit directions of growing `u` (the
    /// viewer's right, looking at the receiving side with `v` up) and of growing `v`.
    fn frame(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3);

    /// Distance along the surface between the footprints of `p0` and `p1`, m.
    fn along(&self, p0: DVec3, p1: DVec3) -> f64;

    /// How far the chord `p0 → p1` may dip below the heights of its ends, m (0 where the
    /// surface does not curve towards the chord).
    fn sag(&self, p0: DVec3, p1: DVec3) -> f64 {
        let _ = (p0, p1);
        0.0
    }

    /// The normal shared by every point, for flat charts.
    fn uniform_normal(&self) -> Option<DVec3> {
        None
    }

    /// Least and greatest `(u, v, height)` over the box `b`, for flat charts (where they are
    /// affine, so the box's corners bound them): each component as [`Chart::local`] gives it.
    fn box_range(&self, b: &Aabb) -> (DVec3, DVec3) {
        corner_range(self, b)
    }

    /// The bare surface as a collision shape.
    fn shape(&self) -> Shape;

    /// What the map's columns (growing `u`) and rows (growing `v`) run along.
    fn axes(&self) -> [MapAxis; 2];

    /// True if the map's first and last columns meet (a full turn of a shell): the layer runs
    /// on across that seam, which is no edge.
    fn wraps(&self) -> bool {
        false
    }

    /// True if `(u, v)` lies on the surface.
    #[inline]
    fn covers(&self, u: f64, v: f64) -> bool {
        let (w, h) = self.size();
        u.abs() <= 0.5 * w && v.abs() <= 0.5 * h
    }
}

/// Least and greatest `(u, v, height)` of `chart` over the eight corners of the box `b`.
fn corner_range(chart: &impl Chart, b: &Aabb) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
    for k in 0..8 {
        let pick = |bit: usize, a: usize| if k & bit == 0 { b.min[a] } else { b.max[a] };
        let l = DVec3::from(chart.local(DVec3::new(pick(1, 0), pick(2, 1), pick(4, 2))));
        (lo, hi) = (lo.min(l), hi.max(l));
    }
    (lo, hi)
}

impl Chart for Face {
    fn size(&self) -> (f64, f64) {
        (2.0 * self.half_width, 2.0 * self.half_height)
    }

    #[inline]
    fn box_range(&self, b: &Aabb) -> (DVec3, DVec3) {
        // Each coordinate is a dot product with a fixed axis: extreme at the box's centre
        // plus or minus its half extent weighted by the axis's absolute components.
        let (mid, half) = (0.5 * (b.min + b.max) - self.center, 0.5 * (b.max - b.min));
        let at = DVec3::new(mid.dot(self.right), mid.dot(self.up), mid.dot(self.normal));
        let reach =
            DVec3::new(half.dot(self.right.abs()), half.dot(self.up.abs()), half.dot(self.normal.abs()));
        (at - reach, at + reach)
    }

    #[inline]
    fn local(&self, p: DVec3) -> (f64, f64, f64) {
        let d = p - self.center;
        (d.dot(self.right), d.dot(self.up), d.dot(self.normal))
    }

    #[inline]
    fn point(&self, u: f64, v: f64, height: f64) -> DVec3 {
        Face::point(self, u, v, height)
    }

    fn frame(&self, _u: f64, _v: f64) -> (DVec3, DVec3, DVec3) {
        (self.normal, self.right, self.up)
    }

    #[inline]
    fn along(&self, p0: DVec3, p1: DVec3) -> f64 {
        let d = p1 - p0;
        (d - self.normal * d.dot(self.normal)).length()
    }

    fn uniform_normal(&self) -> Option<DVec3> {
        Some(self.normal)
    }

    fn shape(&self) -> Shape {
        Shape::Face(*self)
    }

    fn axes(&self) -> [MapAxis; 2] {
        let (w, h) = (self.half_width, self.half_height);
        [
            MapAxis { label: "right of centre [m]", from: -w, to: w },
            MapAxis { label: "up from centre [m]", from: -h, to: h },
        ]
    }
}

/// A cylindrical shell unrolled: `u` is the arc length around the axis (growing towards the
/// viewer's right, seen from the receiving side), `v` the position along the axis; a layer
/// grows towards the axis on an inside face, away from it on an outside one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShellChart {
    /// The bare shell.
    pub shell: CylinderShell,
    /// The receiving side is the inside (a tunnel lining) rather than the outside (a tank).
    pub inside: bool,
}

impl ShellChart {
    /// The angle in the middle of the shell's range, rad.
    #[inline]
    fn middle(&self) -> f64 {
        0.5 * (self.shell.angles[0] + self.shell.angles[1])
    }

    /// +1 inside (u grows with the angle), −1 outside.
    #[inline]
    fn sense(&self) -> f64 {
        if self.inside { 1.0 } else { -1.0 }
    }

    /// The angle at arc position `u`, rad.
    #[inline]
    pub fn angle(&self, u: f64) -> f64 {
        self.middle() + self.sense() * u / self.shell.radius
    }
}

impl Chart for ShellChart {
    fn size(&self) -> (f64, f64) {
        let s = &self.shell;
        (s.radius * (s.angles[1] - s.angles[0]), 2.0 * s.half_length)
    }

    #[inline]
    fn local(&self, p: DVec3) -> (f64, f64, f64) {
        let (theta, z, r) = self.shell.coordinates(p);
        // Angles beyond the range wrap round to its far side; measured from the middle they
        // stay outside the unrolled surface either way.
        let mut d = theta - self.middle();
        if d > PI {
            d -= 2.0 * PI;
        }
        let height = if self.inside { self.shell.radius - r } else { r - self.shell.radius };
        (self.sense() * self.shell.radius * d, z, height)
    }

    #[inline]
    fn point(&self, u: f64, v: f64, height: f64) -> DVec3 {
        let r = self.shell.radius - self.sense() * height;
        self.shell.point(self.angle(u), v, r)
    }

    fn frame(&self, u: f64, _v: f64) -> (DVec3, DVec3, DVec3) {
        let theta = self.angle(u);
        let radial = self.shell.radial(theta);
        (-self.sense() * radial, self.sense() * self.shell.tangent(theta), self.shell.axis)
    }

    fn along(&self, p0: DVec3, p1: DVec3) -> f64 {
        let (t0, z0, _) = self.shell.coordinates(p0);
        let (t1, z1, _) = self.shell.coordinates(p1);
        let dt = (t1 - t0 + PI).rem_euclid(2.0 * PI) - PI;
        (self.shell.radius * dt).hypot(z1 - z0)
    }

    fn sag(&self, p0: DVec3, p1: DVec3) -> f64 {
        // Outside, a chord cuts towards the axis by its sagitta, L²/(8R) to leading order (the
        // steps are far shorter than the radius).
        if self.inside { 0.0 } else { p0.distance_squared(p1) / (8.0 * self.shell.radius) }
    }

    fn shape(&self) -> Shape {
        Shape::Shell(self.shell)
    }

    fn wraps(&self) -> bool {
        self.shell.angles[1] - self.shell.angles[0] >= 2.0 * PI - 1e-9
    }

    fn axes(&self) -> [MapAxis; 2] {
        let [a, b] = self.shell.angles.map(f64::to_degrees);
        let (from, to) = if self.inside { (a, b) } else { (b, a) };
        let l = self.shell.half_length;
        [MapAxis { label: "angle [°]", from, to }, MapAxis { label: "along the axis [m]", from: -l, to: l }]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A face's range over a box, from its centre and half extent, is the range of its
    /// corners (which the generic chart takes): to rounding, for faces turned every way.
    #[test]
    fn a_face_ranges_over_a_box_as_its_corners_do() {
        let mut uniform = crate::deposit::testing::uniform(3);
        let mut next = || uniform() - 0.5;
        for _ in 0..2000 {
            let mut v = || DVec3::new(next(), next(), next());
            let (normal, up) = (v(), v());
            if normal.cross(up).length() < 1e-3 {
                continue;
            }
            let face = Face::new(v(), normal, up, [1.0, 2.0]);
            let (a, b) = (v(), v() * 1e-2);
            let b = Aabb { min: a.min(a + b), max: a.max(a + b) };
            let (lo, hi) = face.box_range(&b);
            let (c_lo, c_hi) = corner_range(&face, &b);
            assert!((lo - c_lo).abs().max_element() < 1e-14, "{lo} against the corners' {c_lo}");
            assert!((hi - c_hi).abs().max_element() < 1e-14, "{hi} against the corners' {c_hi}");
        }
    }

    fn lining(inside: bool) -> ShellChart {
        let shell = CylinderShell::new(DVec3::ZERO, DVec3::Y, DVec3::X, 2.0, 4.0, [0.0, PI]).expect("valid");
        ShellChart { shell, inside }
    }

    #[test]
    fn a_shell_unrolls_with_the_viewer_s_right_and_heights_towards_the_receiving_side() {
        for inside in [true, false] {
            let c = lining(inside);
            assert!((c.size().0 - 2.0 * PI).abs() < 1e-12 && (c.size().1 - 4.0).abs() < 1e-12);
            // The crown is the middle of the map.
            let crown = c.point(0.0, 0.5, 0.1);
            let expected = if inside { DVec3::new(0.0, 0.5, 1.9) } else { DVec3::new(0.0, 0.5, 2.1) };
            assert!(crown.abs_diff_eq(expected, 1e-12), "{crown}");
            let (u, v, h) = c.local(crown);
            assert!(u.abs() < 1e-12 && (v - 0.5).abs() < 1e-12 && (h - 0.1).abs() < 1e-12);
            // right × up = normal, as on a face.
            let (n, right, up) = c.frame(0.3, 0.0);
            assert!((right.cross(up) - n).length() < 1e-12, "inside {inside}");
            // Round trip off the crown.
            let p = c.point(1.2, -1.0, 0.05);
            let (u, v, h) = c.local(p);
            assert!((u - 1.2).abs() < 1e-12 && (v + 1.0).abs() < 1e-12 && (h - 0.05).abs() < 1e-12);
        }
        // The invert lies off an arch's map, on whichever side it wraps to.
        let (u, _, _) = lining(true).local(DVec3::new(0.0, 0.0, -2.0));
        assert!(!lining(true).covers(u, 0.0));
    }
}
