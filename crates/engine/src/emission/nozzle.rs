//! The nozzle's pose over time: static, or interpolated between time-stamped waypoints. A
//! [`NozzlePath`] is a plain value: the caller may replace a running simulation's path between
//! steps (closed-loop control, learning).

use crate::checkpoint::{Dec, Enc, StateError};
use glam::DVec3;

/// A nozzle pose: where particles start and the frame their directions are sampled in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NozzleFrame {
    /// Nozzle position, m.
    pub position: DVec3,
    /// Unit spray axis.
    pub axis: DVec3,
    /// Unit axis across the aperture's width (fan nozzles spread along it).
    pub width_axis: DVec3,
    /// Unit axis across the aperture's height: `axis × width_axis`.
    pub height_axis: DVec3,
}

impl NozzleFrame {
    /// Frame for a spray `axis`, rolled by `roll` (rad) about it. At zero roll the width axis is
    /// horizontal (`axis × z`), or +x when spraying straight up or down.
    pub fn new(position: DVec3, axis: DVec3, roll: f64) -> Self {
        let axis = axis.normalize();
        let horizontal = axis.cross(DVec3::Z);
        let w0 = if horizontal.length_squared() > 1e-12 { horizontal.normalize() } else { DVec3::X };
        let h0 = axis.cross(w0);
        let (s, c) = roll.sin_cos();
        let width_axis = w0 * c + h0 * s;
        NozzleFrame { position, axis, width_axis, height_axis: axis.cross(width_axis) }
    }
}

/// One time-stamped pose of a nozzle path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waypoint {
    /// Time, s.
    pub time: f64,
    /// Position, m.
    pub position: DVec3,
    /// Unit spray axis.
    pub axis: DVec3,
    /// Whether the nozzle sprays from this waypoint until the next.
    pub spray: bool,
}

/// A circular motion superposed on a path: the nozzleman's circles, or a robot's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Circle {
    /// Radius, m.
    pub radius: f64,
    /// Revolutions per second, Hz.
    pub frequency: f64,
    /// Time at which the offset is `radius · first`, s.
    pub start: f64,
    /// Unit direction of the offset at `start`.
    pub first: DVec3,
    /// Unit direction of the offset a quarter turn later.
    pub second: DVec3,
    /// The spray axis the circle's plane was given for (perpendicular to it): as the axis turns
    /// along the path, the plane turns with it, by the shortest rotation from this axis.
    pub axis: DVec3,
}

impl Circle {
    /// Offset from the path at time `t` (s), m.
    #[inline]
    pub fn offset(&self, t: f64) -> DVec3 {
        let phase = std::f64::consts::TAU * self.frequency * (t - self.start);
        (self.first * phase.cos() + self.second * phase.sin()) * self.radius
    }

    /// Velocity of the offset at time `t` (s), m/s.
    #[inline]
    pub fn velocity(&self, t: f64) -> DVec3 {
        let w = std::f64::consts::TAU * self.frequency;
        let phase = w * (t - self.start);
        (self.second * phase.cos() - self.first * phase.sin()) * (self.radius * w)
    }
}

/// The nozzle's motion: waypoints, an optional circle superposed on them, and the roll of the
/// aperture about the spray axis.
#[derive(Clone, Debug, PartialEq)]
pub struct NozzlePath {
    waypoints: Vec<Waypoint>,
    roll: f64,
    circle: Option<Circle>,
}

impl NozzlePath {
    /// A nozzle that stays put and sprays throughout.
    pub fn fixed(position: DVec3, axis: DVec3, roll: f64) -> Self {
        // The waypoint list is never empty: `at` relies on it.
        NozzlePath {
            waypoints: vec![Waypoint { time: 0.0, position, axis: axis.normalize(), spray: true }],
            roll,
            circle: None,
        }
    }

    /// A path through waypoints sorted by strictly increasing time (at least one), with the
    /// aperture rolled by `roll` (rad) about the axis.
    pub fn through(waypoints: Vec<Waypoint>, roll: f64) -> Self {
        let waypoints = waypoints.into_iter().map(|w| Waypoint { axis: w.axis.normalize(), ..w }).collect();
        NozzlePath { waypoints, roll, circle: None }
    }

    /// Checks what stepping relies on: at least one waypoint, finite times in strictly
    /// increasing order, finite positions within `max_coord` (m) of the origin on every axis,
    /// finite non-zero axes, a finite roll and a finite circle of non-negative radius. The
    /// error names the waypoint (0-based) and what is wrong.
    pub fn check(&self, max_coord: f64) -> Result<(), String> {
        if self.waypoints.is_empty() {
            return Err("has no waypoint".into());
        }
        let mut previous = None;
        for (k, w) in self.waypoints.iter().enumerate() {
            if !w.time.is_finite() || previous.is_some_and(|t| w.time <= t) {
                return Err(format!(
                    "waypoint {k}: its time {} s must be finite and after the previous waypoint's",
                    w.time
                ));
            }
            previous = Some(w.time);
            if !(w.position.is_finite() && w.position.abs().max_element() <= max_coord) {
                return Err(format!(
                    "waypoint {k}: its position {} m must be finite and within ±{max_coord} m",
                    w.position
                ));
            }
            if !(w.axis.is_finite() && (w.axis.length() - 1.0).abs() < 1e-6) {
                return Err(format!(
                    "waypoint {k}: its axis {} must be a finite, non-zero direction",
                    w.axis
                ));
            }
        }
        if !self.roll.is_finite() {
            return Err(format!("its roll {} rad must be finite", self.roll));
        }
        if let Some(c) = &self.circle {
            let vectors = [c.first, c.second, c.axis].iter().all(|v| v.is_finite());
            if !(vectors
                && c.radius.is_finite()
                && c.radius >= 0.0
                && c.frequency.is_finite()
                && c.start.is_finite())
            {
                return Err("its circle must have a finite, non-negative radius and finite terms".into());
            }
        }
        Ok(())
    }

    /// This path with `circle` superposed on its positions.
    pub fn with_circle(self, circle: Circle) -> Self {
        NozzlePath { circle: Some(circle), ..self }
    }

    /// Writes the path, for a checkpoint (a run may have replaced it).
    pub(crate) fn save_state(&self, e: &mut Enc) {
        e.list(&self.waypoints, |e, w| {
            e.f64(w.time);
            e.vec3(w.position);
            e.vec3(w.axis);
            e.bool(w.spray);
        });
        e.f64(self.roll);
        e.bool(self.circle.is_some());
        if let Some(c) = &self.circle {
            e.f64(c.radius);
            e.f64(c.frequency);
            e.f64(c.start);
            e.vec3(c.first);
            e.vec3(c.second);
            e.vec3(c.axis);
        }
    }

    /// Reads what [`NozzlePath::save_state`] wrote.
    pub(crate) fn load_state(d: &mut Dec<'_>) -> Result<NozzlePath, StateError> {
        let waypoints = d.list(57, |d| {
            Ok(Waypoint { time: d.f64()?, position: d.vec3()?, axis: d.vec3()?, spray: d.bool()? })
        })?;
        let roll = d.f64()?;
        let circle = if d.bool()? {
            Some(Circle {
                radius: d.f64()?,
                frequency: d.f64()?,
                start: d.f64()?,
                first: d.vec3()?,
                second: d.vec3()?,
                axis: d.vec3()?,
            })
        } else {
            None
        };
        Ok(NozzlePath { waypoints, roll, circle })
    }

    /// The superposed circle, if any.
    pub fn circle(&self) -> Option<&Circle> {
        self.circle.as_ref()
    }

    /// Pose at time `t` (s) and whether the nozzle sprays then. Position is interpolated
    /// linearly (plus the circle, if any), the axis spherically; before the first waypoint the
    /// nozzle holds that pose without spraying, after the last it holds the last pose and its
    /// spray state.
    pub fn at(&self, t: f64) -> (NozzleFrame, bool) {
        let w = &self.waypoints;
        if w.is_empty() {
            return (NozzleFrame::new(DVec3::ZERO, DVec3::X, self.roll), false);
        }
        let i = w.partition_point(|p| p.time <= t);
        let (pos, axis, spray) = if i == 0 {
            // Before the path starts, the nozzle waits at its first pose without spraying.
            (w[0].position, w[0].axis, false)
        } else if i == w.len() {
            let last = w[w.len() - 1];
            (last.position, last.axis, last.spray)
        } else {
            let (a, b) = (w[i - 1], w[i]);
            let f = (t - a.time) / (b.time - a.time);
            (a.position.lerp(b.position, f), slerp(a.axis, b.axis, f), a.spray)
        };
        let pos = pos + self.circle.map_or(DVec3::ZERO, |c| turn(c.axis, axis) * c.offset(t));
        (NozzleFrame::new(pos, axis, self.roll), spray)
    }

    /// Whether the nozzle sprays at time `t` (s), a waypoint up to `slack` (s) after `t` taken
    /// as reached: as [`NozzlePath::at`] says, but for a time that stands for an instant that a
    /// waypoint's time may give rounded the other way (see [`NozzlePath::step_slack`]).
    pub fn sprays(&self, t: f64, slack: f64) -> bool {
        let i = self.waypoints.partition_point(|p| p.time <= t + slack);
        i > 0 && self.waypoints[i - 1].spray
    }

    /// How far (s) a waypoint may lie after the time `t` = step × `dt` of a step (s) and still
    /// count as reached at that step: a millionth of the step, or a millionth of a millionth of
    /// `t` where that is more. The two are one instant computed two ways (a waypoint at 0.95 s,
    /// step 950 of 1 ms at 0.9500000000000001 s, or the other way round), and which rounds lower
    /// must not decide whether a spraying step is counted; no real path turns its spray on or
    /// off that close after a step.
    pub fn step_slack(t: f64, dt: f64) -> f64 {
        (dt * 1e-6).max(t.abs() * 1e-12)
    }

    /// The nozzle's velocity at time `t` (s), m/s: the travel along the path plus the circle
    /// (in its plane at `t`; the plane's own turning is left out, as slow beside the circle).
    pub fn velocity(&self, t: f64) -> DVec3 {
        let circle = self.circle.map_or(DVec3::ZERO, |c| turn(c.axis, self.at(t).0.axis) * c.velocity(t));
        self.travel_velocity(t) + circle
    }

    /// The velocity of travel along the path at time `t` (s), m/s, without the circle:
    /// constant along each leg between waypoints, zero before the first and after the last.
    pub fn travel_velocity(&self, t: f64) -> DVec3 {
        let w = &self.waypoints;
        let i = w.partition_point(|p| p.time <= t);
        if i == 0 || i == w.len() {
            return DVec3::ZERO;
        }
        (w[i].position - w[i - 1].position) / (w[i].time - w[i - 1].time)
    }

    /// The waypoints, by increasing time.
    pub fn waypoints(&self) -> &[Waypoint] {
        &self.waypoints
    }

    /// Roll of the aperture about the spray axis, rad.
    pub fn roll(&self) -> f64 {
        self.roll
    }

    /// Time of the last waypoint at which the nozzle starts spraying or goes on spraying
    /// after, s: when spraying ends (infinite when the last waypoint sprays).
    pub fn spray_end(&self) -> f64 {
        match self.waypoints.last() {
            Some(last) if last.spray => f64::INFINITY,
            Some(last) => last.time,
            None => 0.0,
        }
    }
}

/// The shortest rotation taking unit `from` to unit `to` (the identity, exactly, when they
/// are equal).
#[inline]
fn turn(from: DVec3, to: DVec3) -> glam::DQuat {
    if from == to { glam::DQuat::IDENTITY } else { glam::DQuat::from_rotation_arc(from, to) }
}

/// Spherical interpolation between unit vectors that are not opposite.
pub fn slerp(a: DVec3, b: DVec3, f: f64) -> DVec3 {
    let cos = a.dot(b).clamp(-1.0, 1.0);
    let omega = cos.acos();
    if omega < 1e-9 {
        return a.lerp(b, f).normalize();
    }
    let s = omega.sin();
    (a * ((1.0 - f) * omega).sin() / s + b * (f * omega).sin() / s).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waypoints_interpolate_position_linearly_and_axis_on_the_sphere() {
        let path = NozzlePath::through(
            vec![
                Waypoint { time: 1.0, position: DVec3::ZERO, axis: DVec3::X, spray: true },
                Waypoint {
                    time: 3.0,
                    position: DVec3::new(2.0, 0.0, 0.0),
                    axis: DVec3::Y * 5.0,
                    spray: false,
                },
            ],
            0.0,
        );
        let (f, spray) = path.at(2.0);
        assert!(spray);
        assert!(f.position.abs_diff_eq(DVec3::new(1.0, 0.0, 0.0), 1e-12));
        let diag = DVec3::new(1.0, 1.0, 0.0).normalize();
        assert!(f.axis.abs_diff_eq(diag, 1e-12), "{}", f.axis);
        let (f, _) = path.at(1.5);
        assert!((f.axis.angle_between(DVec3::X) - std::f64::consts::FRAC_PI_8).abs() < 1e-12);
        // Before its first waypoint the nozzle waits there, not yet spraying.
        let (before, spray_before) = path.at(0.0);
        assert!(before.position == DVec3::ZERO && !spray_before);
        assert!(path.at(1.0).1, "sprays from its first waypoint");
        let (after, spray_after) = path.at(10.0);
        assert!(after.axis.abs_diff_eq(DVec3::Y, 1e-12) && !spray_after);
    }

    #[test]
    fn the_frame_is_orthonormal_and_rolls() {
        let f = NozzleFrame::new(DVec3::ZERO, DVec3::new(1.0, 0.0, -1.0), 0.0);
        assert!(f.width_axis.z.abs() < 1e-12, "width axis horizontal at zero roll");
        let r = NozzleFrame::new(DVec3::ZERO, DVec3::new(1.0, 0.0, -1.0), std::f64::consts::FRAC_PI_2);
        assert!(r.width_axis.abs_diff_eq(f.height_axis, 1e-12));
        for g in [f, r, NozzleFrame::new(DVec3::ZERO, -DVec3::Z, 0.3)] {
            assert!((g.axis.dot(g.width_axis)).abs() < 1e-12 && (g.axis.dot(g.height_axis)).abs() < 1e-12);
            assert!((g.width_axis.cross(g.height_axis) - g.axis).length() < 1e-12);
        }
    }

    #[test]
    fn a_circling_nozzle_stays_on_its_circle_across_the_axis() {
        use crate::emission::circling;
        let (centre, axis) = (DVec3::new(-1.0, 0.0, 1.0), DVec3::new(1.0, 0.0, 0.0));
        let path = circling(centre, axis, 0.1, 2.0, 0.0);
        for k in 0..50 {
            let t = k as f64 * 0.013;
            let (frame, spraying) = path.at(t);
            let off = frame.position - centre;
            assert!(spraying && (off.length() - 0.1).abs() < 1e-12 && off.dot(axis).abs() < 1e-12);
            // Speed 2π r f, along the circle.
            let v = path.velocity(t);
            assert!((v.length() - std::f64::consts::TAU * 0.2).abs() < 1e-12 && v.dot(off).abs() < 1e-12);
            assert_eq!(path.travel_velocity(t), DVec3::ZERO);
        }
        assert!(
            path.at(0.5).0.position.abs_diff_eq(path.at(0.0).0.position, 1e-12),
            "one revolution in 0.5 s"
        );
    }
}
