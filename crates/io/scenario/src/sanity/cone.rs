//! Whether a spray cone can meet a box: the geometry behind the check that some particle can
//! reach a target.

use glam::DVec3;

/// An oriented box around a target, m: `center`, three unit `axes` and the half sizes along
/// them (0 along a flat target's normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnclosingBox {
    /// Centre, m.
    pub center: DVec3,
    /// Unit axes, perpendicular to each other.
    pub axes: [DVec3; 3],
    /// Half sizes along `axes`, m.
    pub half: [f64; 3],
}

impl EnclosingBox {
    /// An axis-aligned box from its corners `min` and `max`, m.
    pub fn aligned(min: DVec3, max: DVec3) -> EnclosingBox {
        let h = 0.5 * (max - min);
        EnclosingBox { center: 0.5 * (min + max), axes: [DVec3::X, DVec3::Y, DVec3::Z], half: h.to_array() }
    }

    /// This box grown by `margin` (m) along each axis: it holds every point within `margin` of
    /// the box.
    pub fn grown(self, margin: f64) -> EnclosingBox {
        EnclosingBox { half: self.half.map(|h| h + margin.max(0.0)), ..self }
    }

    /// The eight corners, m.
    pub fn corners(&self) -> [DVec3; 8] {
        std::array::from_fn(|k| {
            let sign = |bit: usize| if k >> bit & 1 == 1 { 1.0 } else { -1.0 };
            self.center + (0..3).map(|i| self.axes[i] * self.half[i] * sign(i)).sum::<DVec3>()
        })
    }

    /// Distance from `p` to the box, m (0 inside).
    pub fn distance(&self, p: DVec3) -> f64 {
        let d = p - self.center;
        (0..3).map(|i| (d.dot(self.axes[i]).abs() - self.half[i]).max(0.0).powi(2)).sum::<f64>().sqrt()
    }

    /// The distance from `p` to the farthest corner, m.
    pub fn farthest(&self, p: DVec3) -> f64 {
        self.corners().iter().map(|c| c.distance(p)).fold(0.0, f64::max)
    }
}

/// True if the cone with its apex at `apex`, unit `axis` and half-angle `half_angle` (rad)
/// meets `b`. A convex box meets the cone exactly when the apex is inside it, or the axis ray
/// enters it, or one of its twelve edges enters the cone; a cone of 90° or more is taken to
/// meet everything.
pub fn cone_meets_box(apex: DVec3, axis: DVec3, half_angle: f64, b: &EnclosingBox) -> bool {
    if half_angle >= 0.5 * std::f64::consts::PI - 1e-6 || b.distance(apex) == 0.0 {
        return true;
    }
    if ray_enters(apex, axis, b) {
        return true;
    }
    let corners = b.corners();
    let cos = half_angle.cos();
    (0..8).any(|k| {
        (0..3).filter(|bit| k >> bit & 1 == 0).any(|bit| {
            let (q0, q1) = (corners[k], corners[k | 1 << bit]);
            edge_enters(apex, axis, cos, q0, q1)
        })
    })
}

/// True if the ray from `apex` along unit `axis` enters `b` (slab test in the box's axes).
fn ray_enters(apex: DVec3, axis: DVec3, b: &EnclosingBox) -> bool {
    let d = apex - b.center;
    let (mut near, mut far) = (0.0_f64, f64::INFINITY);
    for i in 0..3 {
        let (o, v, h) = (d.dot(b.axes[i]), axis.dot(b.axes[i]), b.half[i]);
        if v.abs() < 1e-12 {
            if o.abs() > h {
                return false;
            }
        } else {
            let (t1, t2) = ((-h - o) / v, (h - o) / v);
            near = near.max(t1.min(t2));
            far = far.min(t1.max(t2));
        }
    }
    near <= far
}

/// True if some point of the segment `q0 → q1` lies within the cone at `apex` about unit
/// `axis` whose half-angle has cosine `cos` (≥ 0). Along the segment, a·v − cos·|v| is concave,
/// so its largest value is found by ternary search.
fn edge_enters(apex: DVec3, axis: DVec3, cos: f64, q0: DVec3, q1: DVec3) -> bool {
    let (v0, e) = (q0 - apex, q1 - q0);
    let g = |s: f64| {
        let v = v0 + e * s;
        axis.dot(v) - cos * v.length()
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if g(a) < g(b) {
            lo = a;
        } else {
            hi = b;
        }
    }
    let tolerance = 1e-12 * (v0.length() + e.length());
    [0.0, 0.5 * (lo + hi), 1.0].into_iter().any(|s| g(s) >= -tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 m × 2 m wall in the plane x = 0, centred at (0, 0, 1).
    fn wall() -> EnclosingBox {
        EnclosingBox {
            center: DVec3::new(0.0, 0.0, 1.0),
            axes: [DVec3::Y, DVec3::Z, DVec3::X],
            half: [1.0, 1.0, 0.0],
        }
    }

    #[test]
    fn a_cone_aimed_at_the_wall_meets_it_and_one_aimed_away_does_not() {
        let apex = DVec3::new(-1.0, 0.0, 1.0);
        let half = 9f64.to_radians();
        assert!(cone_meets_box(apex, DVec3::X, half, &wall()));
        assert!(!cone_meets_box(apex, -DVec3::X, half, &wall()));
        // Aimed along the wall (parallel to it, 1 m off): misses at 9°, meets at 60°.
        assert!(!cone_meets_box(apex, DVec3::Y, half, &wall()));
        assert!(cone_meets_box(apex, DVec3::Y, 60f64.to_radians(), &wall()));
    }

    #[test]
    fn a_cone_grazing_an_edge_meets_the_box_even_when_its_axis_misses() {
        // From 1 m in front, aimed 0.2 m past the wall's edge: the cone meets the wall once its
        // half-angle exceeds the angle from the axis to the edge's nearest point, (0, 1, 1).
        let apex = DVec3::new(-1.0, 0.0, 1.0);
        let axis = (DVec3::new(0.0, 1.2, 1.0) - apex).normalize();
        let edge = (DVec3::new(0.0, 1.0, 1.0) - apex).normalize();
        let angle = axis.angle_between(edge);
        assert!(!cone_meets_box(apex, axis, angle - 1e-3, &wall()));
        assert!(cone_meets_box(apex, axis, angle + 1e-3, &wall()));
    }

    #[test]
    fn an_apex_inside_the_grown_box_always_meets_it() {
        let apex = DVec3::new(-0.05, 0.0, 1.0);
        assert!(!cone_meets_box(apex, -DVec3::X, 0.1, &wall()));
        assert!(cone_meets_box(apex, -DVec3::X, 0.1, &wall().grown(0.1)));
    }
}
