//! Nozzle paths generated from a few parameters: a nozzle circling a point, and a raster
//! (zig-zag) over a rectangle of a face, the robot tasks of the paper's Figure 4.

use super::{Circle, NozzleFrame, NozzlePath, Waypoint};
use crate::deposit::Chart;
use glam::DVec3;

/// Direction of a raster's passes in the face.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum PassDirection {
    /// Passes along the face's width (`right`), stepping up from the bottom edge.
    #[default]
    Horizontal,
    /// Passes along the face's height (`up`), stepping right from the left edge.
    Vertical,
}

/// A zig-zag pass over a rectangle of a face at a standoff, with an optional circular motion
/// superposed (the shotcrete nozzle technique). The default covers 1 m × 1 m at 1 m standoff,
/// 0.5 m/s, 0.1 m step-over, with 0.1 m lead.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct RasterPlan {
    /// `[width, height]` of the covered rectangle, m.
    pub size: [f64; 2],
    /// Centre of the rectangle from the face's centre, `[right, up]`, m.
    pub offset: [f64; 2],
    /// Distance of the nozzle from the face along its normal, m.
    pub standoff: f64,
    /// Travel speed along the path, m/s.
    pub speed: f64,
    /// Distance between neighbouring passes, m.
    pub step_over: f64,
    /// Whether the passes run along the face's width or its height.
    pub passes: PassDirection,
    /// Travel beyond the rectangle's edge at each end of a pass, spraying, m.
    pub lead: f64,
    /// Whether the nozzle sprays while stepping over between passes.
    pub spray_on_turns: bool,
    /// Radius of a circular motion superposed on the path, m (0: none).
    pub circle_radius: f64,
    /// Revolutions per second of that circular motion, Hz.
    pub circle_frequency: f64,
    /// Time at which the raster starts, s.
    pub start_time: f64,
}

impl Default for RasterPlan {
    fn default() -> Self {
        RasterPlan {
            size: [1.0, 1.0],
            offset: [0.0, 0.0],
            standoff: 1.0,
            speed: 0.5,
            step_over: 0.1,
            passes: PassDirection::Horizontal,
            lead: 0.1,
            spray_on_turns: false,
            circle_radius: 0.0,
            circle_frequency: 0.0,
            start_time: 0.0,
        }
    }
}

/// A static nozzle at `position` spraying along `axis`, circling in the plane perpendicular to
/// the axis with `radius` (m) at `frequency` (Hz), its aperture rolled by `roll` (rad).
pub fn circling(position: DVec3, axis: DVec3, radius: f64, frequency: f64, roll: f64) -> NozzlePath {
    let frame = NozzleFrame::new(position, axis, 0.0);
    let circle = Circle {
        radius,
        frequency,
        start: 0.0,
        first: frame.width_axis,
        second: frame.height_axis,
        axis: frame.axis,
    };
    NozzlePath::fixed(position, axis, roll).with_circle(circle)
}

/// A raster over the surface `chart` unrolls (see [`raster_waypoints`]) with its circle, if
/// any, superposed in the plane perpendicular to the spray axis; the aperture rolled by `roll`
/// (rad).
pub fn raster(chart: &impl Chart, r: &RasterPlan, roll: f64) -> NozzlePath {
    let path = NozzlePath::through(raster_waypoints(chart, r), roll);
    if r.circle_radius > 0.0 && r.circle_frequency > 0.0 {
        let (normal, right, up) = chart.frame(r.offset[0], r.offset[1]);
        let (first, second) = match r.passes {
            PassDirection::Horizontal => (right, up),
            PassDirection::Vertical => (up, right),
        };
        let circle = Circle {
            radius: r.circle_radius,
            frequency: r.circle_frequency,
            start: r.start_time,
            first,
            second,
            axis: -normal,
        };
        path.with_circle(circle)
    } else {
        path
    }
}

/// Longest leg of a raster on a curved surface, m along it: the nozzle follows the surface in
/// steps of this (1° of a 3 m tunnel), so that its standoff stays within 0.02 % of the plan.
const CURVED_STEP: f64 = 0.05;

/// The waypoints of a raster over the surface `chart` unrolls, without its circle: passes from
/// the bottom (horizontal, along the unrolled width) or the left (vertical), alternating
/// direction, the nozzle at the standoff along the surface's normal, spraying against it at the
/// travel speed; each waypoint's spray flag holds for the leg that starts there. On a flat
/// surface the waypoints are the corners of the zig-zag; on a curved one the legs are cut so
/// that the nozzle follows the surface.
///
/// Every time is computed afresh from the pass's index (the distance travelled before leg `i` is
/// `⌈i/2⌉` passes and `⌊i/2⌋` step-overs), never by adding up the legs before it, so that no
/// rounding error accumulates along the path: a pass that should start at 0.75 s starts there.
pub fn raster_waypoints(chart: &impl Chart, r: &RasterPlan) -> Vec<Waypoint> {
    let [w, h] = r.size;
    // (u, v) unit steps along the passes and across them.
    let (along, across, length, span) = match r.passes {
        PassDirection::Horizontal => ((1.0, 0.0), (0.0, 1.0), w, h),
        PassDirection::Vertical => ((0.0, 1.0), (1.0, 0.0), h, w),
    };
    let passes = (span / r.step_over + 1e-9).floor() as usize + 1;
    let half = length / 2.0 + r.lead;
    let at =
        |a: f64, b: f64| (r.offset[0] + along.0 * a + across.0 * b, r.offset[1] + along.1 * a + across.1 * b);
    let pose = |(u, v): (f64, f64)| (chart.point(u, v, r.standoff), -chart.frame(u, v).0);
    // Corners of the zig-zag in (u, v), with the spray state of the leg that starts there: leg
    // 2k is pass k, leg 2k + 1 the step-over after it.
    let mut corners: Vec<((f64, f64), bool)> = Vec::new();
    for k in 0..passes {
        let b = -span / 2.0 + k as f64 * r.step_over;
        let (from, to) = if k % 2 == 0 { (-half, half) } else { (half, -half) };
        corners.push((at(from, b), true));
        corners.push((at(to, b), r.spray_on_turns && k + 1 < passes));
    }
    // Each leg cut into pieces: one on a flat surface, enough on a curved one for the nozzle to
    // follow it.
    let curved = chart.uniform_normal().is_none();
    let pieces = |(u0, v0): (f64, f64), (u1, v1): (f64, f64)| {
        if curved { ((u1 - u0).hypot(v1 - v0) / CURVED_STEP).ceil().max(1.0) as usize } else { 1 }
    };
    let cut = |from: (f64, f64), to: (f64, f64), n: usize, j: usize| {
        let f = j as f64 / n as f64;
        (from.0 + (to.0 - from.0) * f, from.1 + (to.1 - from.1) * f)
    };
    // The length of the nozzle's own path along a leg, m: on a flat surface the leg's length in
    // the face (the nozzle runs parallel to it), on a curved one the sum of its pieces' chords.
    // Every pass has the same length, and every step-over: the first of each stands for all.
    let leg_length = |from: (f64, f64), to: (f64, f64)| {
        let n = pieces(from, to);
        if !curved {
            return (to.0 - from.0).hypot(to.1 - from.1);
        }
        (0..n).map(|j| pose(cut(from, to, n, j)).0.distance(pose(cut(from, to, n, j + 1)).0)).sum::<f64>()
    };
    let pass_length = leg_length(corners[0].0, corners[1].0);
    let step_length = corners.get(2).map_or(0.0, |c| leg_length(corners[1].0, c.0));
    // Distance travelled before leg `i` starts, m: the passes and step-overs before it.
    let before = |i: usize| (i.div_ceil(2)) as f64 * pass_length + (i / 2) as f64 * step_length;
    let mut out: Vec<Waypoint> = Vec::with_capacity(corners.len());
    for (i, pair) in corners.windows(2).enumerate() {
        let ((from, spray), (to, _)) = (pair[0], pair[1]);
        let leg = if i % 2 == 0 { pass_length } else { step_length };
        let n = pieces(from, to);
        for j in 0..n {
            let (position, axis) = pose(cut(from, to, n, j));
            let travelled = before(i) + leg * j as f64 / n as f64;
            out.push(Waypoint { time: r.start_time + travelled / r.speed, position, axis, spray });
        }
    }
    // The path ends, spraying no more, at the last corner.
    if let Some(&(last, _)) = corners.last() {
        let (position, axis) = pose(last);
        let time = r.start_time + before(corners.len() - 1) / r.speed;
        out.push(Waypoint { time, position, axis, spray: false });
    }
    out
}
