//! Nozzle paths generated from a few parameters: a nozzle circling a point, and a raster
//! (zig-zag) over a rectangle of a face, the robot tasks of the paper's Figure 4.

use super::{NozzleFrame, Waypoint};
use crate::collision::Face;
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
    /// Pass direction.
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

/// Waypoints of a static nozzle circling `position` (radius m, frequency Hz) in the plane
/// perpendicular to `axis` until `until` (s), sampled 36 times a revolution.
pub fn circling_waypoints(
    position: DVec3,
    axis: DVec3,
    radius: f64,
    frequency: f64,
    until: f64,
) -> Vec<Waypoint> {
    let axis = axis.normalize();
    let frame = NozzleFrame::new(position, axis, 0.0);
    let step = 1.0 / (36.0 * frequency);
    let n = (until / step).ceil() as usize + 1;
    (0..=n)
        .map(|k| {
            let t = k as f64 * step;
            let phase = std::f64::consts::TAU * frequency * t;
            let offset = (frame.width_axis * phase.cos() + frame.height_axis * phase.sin()) * radius;
            Waypoint { time: t, position: position + offset, axis, spray: true }
        })
        .collect()
}

/// Waypoints of a raster over `face`: passes from the bottom (horizontal) or the left
/// (vertical), alternating direction, the nozzle at the standoff along the face's normal,
/// spraying against it; a circular motion, if any, is sampled 36 times per revolution.
pub fn raster_waypoints(face: &Face, r: &RasterPlan) -> Vec<Waypoint> {
    let [w, h] = r.size;
    let centre = face.center + face.right * r.offset[0] + face.up * r.offset[1] + face.normal * r.standoff;
    // `along`: the pass direction; `across`: the step-over direction.
    let (along, across, length, span) = match r.passes {
        PassDirection::Horizontal => (face.right, face.up, w, h),
        PassDirection::Vertical => (face.up, face.right, h, w),
    };
    let passes = (span / r.step_over + 1e-9).floor() as usize + 1;
    let half = length / 2.0 + r.lead;
    // Corners of the zig-zag, with the spray state of the leg that starts there.
    let mut corners: Vec<(DVec3, bool)> = Vec::new();
    for k in 0..passes {
        let b = -span / 2.0 + k as f64 * r.step_over;
        let (from, to) = if k % 2 == 0 { (-half, half) } else { (half, -half) };
        corners.push((centre + across * b + along * from, true));
        corners.push((centre + across * b + along * to, r.spray_on_turns && k + 1 < passes));
    }
    // Times at the corners, at constant travel speed.
    let mut times = vec![r.start_time];
    for pair in corners.windows(2) {
        let last = times[times.len() - 1];
        times.push(last + pair[0].0.distance(pair[1].0) / r.speed);
    }
    let axis = -face.normal;
    let circle = |t: f64| {
        let phase = std::f64::consts::TAU * r.circle_frequency * (t - r.start_time);
        (along * phase.cos() + across * phase.sin()) * r.circle_radius
    };
    let mut out = Vec::new();
    let sample = if r.circle_radius > 0.0 && r.circle_frequency > 0.0 {
        1.0 / (36.0 * r.circle_frequency)
    } else {
        f64::INFINITY
    };
    for (i, pair) in corners.windows(2).enumerate() {
        let (t0, t1) = (times[i], times[i + 1]);
        let n = ((t1 - t0) / sample).ceil().max(1.0) as usize;
        for j in 0..n {
            let f = j as f64 / n as f64;
            let t = t0 + f * (t1 - t0);
            out.push(Waypoint {
                time: t,
                position: pair[0].0.lerp(pair[1].0, f) + circle(t),
                axis,
                spray: pair[0].1,
            });
        }
    }
    let (end, t_end) = (corners[corners.len() - 1].0, times[times.len() - 1]);
    out.push(Waypoint { time: t_end, position: end + circle(t_end), axis, spray: false });
    out
}
