//! Openings cut out of a deposit surface: windows, doors, box-outs. Material passes through
//! them; the cells they cover carry no surface.

use super::Chart;
use crate::collision::{Aabb, Flight, Hit, Primitive, Shape};
use glam::DVec3;

/// A polygon cut out of a surface, in its unrolled coordinates `(u, v)` (m from the middle).
#[derive(Clone, Debug, PartialEq)]
pub struct Opening {
    /// Corners in order (either orientation), m.
    pub corners: Vec<(f64, f64)>,
}

impl Opening {
    /// A rectangle centred on `(u, v)` with sides `(width, height)`, m.
    pub fn rectangle(center: (f64, f64), size: (f64, f64)) -> Opening {
        let (u, v, w, h) = (center.0, center.1, 0.5 * size.0, 0.5 * size.1);
        Opening { corners: vec![(u - w, v - h), (u + w, v - h), (u + w, v + h), (u - w, v + h)] }
    }

    /// The area enclosed, m² (the shoelace formula; positive whatever the orientation).
    pub fn area(&self) -> f64 {
        let c = &self.corners;
        let twice: f64 =
            (0..c.len()).map(|i| c[i].0 * c[(i + 1) % c.len()].1 - c[(i + 1) % c.len()].0 * c[i].1).sum();
        0.5 * twice.abs()
    }

    /// True if `(u, v)` lies inside (even–odd rule).
    pub fn contains(&self, u: f64, v: f64) -> bool {
        let c = &self.corners;
        let mut inside = false;
        for i in 0..c.len() {
            let ((x0, y0), (x1, y1)) = (c[i], c[(i + 1) % c.len()]);
            if (y0 > v) != (y1 > v) && u < x0 + (v - y0) * (x1 - x0) / (y1 - y0) {
                inside = !inside;
            }
        }
        inside
    }

    /// Distance from `(u, v)` to the opening's boundary, m.
    pub fn distance(&self, u: f64, v: f64) -> f64 {
        let c = &self.corners;
        (0..c.len())
            .map(|i| {
                let ((x0, y0), (x1, y1)) = (c[i], c[(i + 1) % c.len()]);
                let (dx, dy) = (x1 - x0, y1 - y0);
                let len2 = dx * dx + dy * dy;
                let f =
                    if len2 > 0.0 { (((u - x0) * dx + (v - y0) * dy) / len2).clamp(0.0, 1.0) } else { 0.0 };
                (u - x0 - f * dx).hypot(v - y0 - f * dy)
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// A surface with openings, as a collision shape: a hit inside an opening passes through.
#[derive(Debug)]
pub(crate) struct Perforated<C: Chart> {
    pub chart: C,
    pub shape: Shape,
    pub openings: Vec<Opening>,
}

/// Past this many openings crossed in one query (a path through several openings of a curved
/// surface), the rest of the path is taken to pass.
const MAX_PASSES: usize = 8;

/// How far past an opening's plane a query restarts, m: far below any cell, far above rounding.
const STEP_PAST: f64 = 1e-9;

impl<C: Chart> Perforated<C> {
    fn open_at(&self, p: DVec3) -> bool {
        let (u, v, _) = self.chart.local(p);
        self.openings.iter().any(|o| o.contains(u, v))
    }
}

impl<C: Chart> Primitive for Perforated<C> {
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let len = p0.distance(p1);
        let mut from = 0.0;
        for _ in 0..MAX_PASSES {
            let start = p0.lerp(p1, from);
            let hit = self.shape.intersect(start, p1)?;
            let t = from + (1.0 - from) * hit.t;
            if !self.open_at(hit.point) {
                return Some(Hit { t, ..hit });
            }
            from = (t + STEP_PAST / len.max(f64::MIN_POSITIVE)).min(1.0);
        }
        None
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        let mut tau0 = 0.0;
        for _ in 0..MAX_PASSES {
            let rest =
                Flight { x0: arc.at(tau0), v0: arc.velocity(tau0), g: arc.g, duration: arc.duration - tau0 };
            if rest.duration <= 0.0 {
                return None;
            }
            let hit = self.shape.intersect_arc(&rest)?;
            let tau = tau0 + hit.t * rest.duration;
            if !self.open_at(hit.point) {
                return Some(Hit { t: tau / arc.duration, ..hit });
            }
            let speed = arc.velocity(tau).length().max(f64::MIN_POSITIVE);
            tau0 = tau + STEP_PAST / speed;
        }
        None
    }

    fn aabb(&self) -> Option<Aabb> {
        self.shape.aabb()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::collision::Face;

    #[test]
    fn polygons_know_their_inside_area_and_boundary() {
        let window = Opening::rectangle((0.5, 1.0), (1.0, 0.6));
        assert!((window.area() - 0.6).abs() < 1e-12);
        assert!(window.contains(0.5, 1.0) && window.contains(0.01, 0.71) && !window.contains(1.01, 1.0));
        assert!((window.distance(0.5, 1.0) - 0.3).abs() < 1e-12);
        // An L-shaped box-out: the notch is outside.
        let l =
            Opening { corners: vec![(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)] };
        assert!((l.area() - 3.0).abs() < 1e-12);
        assert!(l.contains(0.5, 1.5) && !l.contains(1.5, 1.5));
    }

    #[test]
    fn paths_pass_through_an_opening_and_strike_around_it() {
        let face = Face::new(DVec3::ZERO, DVec3::NEG_X, DVec3::Z, [2.0, 2.0]);
        let p = Perforated {
            chart: face,
            shape: Shape::Face(face),
            openings: vec![Opening::rectangle((0.0, 0.0), (0.5, 0.5))],
        };
        let through = p.intersect(DVec3::new(-1.0, 0.1, 0.1), DVec3::new(1.0, 0.1, 0.1));
        assert!(through.is_none(), "the window lets it pass");
        let hit = p.intersect(DVec3::new(-1.0, 0.5, 0.5), DVec3::new(1.0, 0.5, 0.5)).expect("the wall");
        assert!((hit.t - 0.5).abs() < 1e-12);
        let arc = Flight {
            x0: DVec3::new(-1.0, 0.1, 0.1),
            v0: DVec3::new(10.0, 0.0, 0.0),
            g: DVec3::ZERO,
            duration: 0.3,
        };
        assert!(p.intersect_arc(&arc).is_none());
    }
}
