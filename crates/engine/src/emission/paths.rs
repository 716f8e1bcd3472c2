//! Nozzle paths generated from a few parameters: a nozzle circling a point, and a raster
//! (zig-zag) over a rectangle of a face, the robot tasks of the paper's Figure 4.

use super::{Circle, NozzleFrame, NozzlePath, Waypoint};
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

/// A static nozzle at `position` spraying along `axis`, circling in the plane perpendicular to
/// the axis with `radius` (m) at `frequency` (Hz), its aperture rolled by `roll` (rad).
pub fn circling(position: DVec3, axis: DVec3, radius: f64, frequency: f64, roll: f64) -> NozzlePath {
    let frame = NozzleFrame::new(position, axis, 0.0);
    let circle = Circle { radius, frequency, start: 0.0, first: frame.width_axis, second: frame.height_axis };
    NozzlePath::fixed(position, axis, roll).with_circle(circle)
}

/// A raster over `face` (see [`raster_waypoints`]) with its circle, if any, superposed; the
/// aperture rolled by `roll` (rad).
pub fn raster(face: &Face, r: &RasterPlan, roll: f64) -> NozzlePath {
    let (along, across) = raster_axes(face, r.passes);
    let path = NozzlePath::through(raster_waypoints(face, r), roll);
    if r.circle_radius > 0.0 && r.circle_frequency > 0.0 {
        let circle = Circle {
            radius: r.circle_radius,
            frequency: r.circle_frequency,
            start: r.start_time,
            first: along,
            second: across,
        };
        path.with_circle(circle)
    } else {
        path
    }
}

/// The pass direction and the step-over direction of a raster over `face`.
fn raster_axes(face: &Face, passes: PassDirection) -> (DVec3, DVec3) {
    match passes {
        PassDirection::Horizontal => (face.right, face.up),
        PassDirection::Vertical => (face.up, face.right),
    }
}

/// The corners of a raster over `face` without its circle: passes from the bottom (horizontal)
/// or the left (vertical), alternating direction, the nozzle at the standoff along the face's
/// normal, spraying against it at the travel speed; each waypoint's spray flag holds for the leg
/// that starts there.
pub fn raster_waypoints(face: &Face, r: &RasterPlan) -> Vec<Waypoint> {
    let [w, h] = r.size;
    let centre = face.center + face.right * r.offset[0] + face.up * r.offset[1] + face.normal * r.standoff;
    // `along`: the pass direction; `across`: the step-over direction.
    let (along, across) = raster_axes(face, r.passes);
    let (length, span) = match r.passes {
        PassDirection::Horizontal => (w, h),
        PassDirection::Vertical => (h, w),
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
    let mut out: Vec<Waypoint> = corners
        .iter()
        .zip(&times)
        .map(|(&(position, spray), &time)| Waypoint { time, position, axis, spray })
        .collect();
    // The path ends, spraying no more, at the last corner.
    if let Some(last) = out.last_mut() {
        last.spray = false;
    }
    out
}
