//! The nozzle's spraying poses, sampled: the stretches of the path over which it sprays, each
//! seen from its middle with bounds on how far the pose strays from there over the stretch.

use glam::DVec3;
use spraysim_engine::emission::NozzlePath;

/// Even samples of the run's time span, besides the waypoints' own times.
const TIME_SAMPLES: usize = 64;
/// Up to this many waypoints, each is a sample time of its own; beyond, the even samples
/// stand alone and each stretch's bounds take in the waypoints within it.
const MAX_WAYPOINT_SAMPLES: usize = 256;

/// A stretch of the path over which the nozzle sprays (for at least part of it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stretch {
    /// Start and end of the stretch, s.
    pub times: [f64; 2],
    /// The nozzle's position in the middle of the stretch, m.
    pub position: DVec3,
    /// The unit spray axis in the middle of the stretch.
    pub axis: DVec3,
    /// How far the nozzle strays from `position` over the stretch, m (a superposed circle
    /// included).
    pub spread: f64,
    /// How far the axis turns from `axis` over the stretch, rad.
    pub turn: f64,
    /// The nozzle's speed at the stretch's ends and middle, the largest, m/s.
    pub speed: f64,
}

/// The stretches of `path` over which the nozzle sprays within `[0, duration]` (s), in time
/// order.
pub(crate) fn spraying_stretches(path: &NozzlePath, duration: f64) -> Vec<Stretch> {
    let waypoints = path.waypoints();
    let mut times: Vec<f64> = (0..=TIME_SAMPLES).map(|k| duration * k as f64 / TIME_SAMPLES as f64).collect();
    if waypoints.len() <= MAX_WAYPOINT_SAMPLES {
        times.extend(waypoints.iter().map(|w| w.time).filter(|&t| t > 0.0 && t < duration));
    }
    times.sort_by(f64::total_cmp);
    times.dedup();
    let circle = path.circle().map_or(0.0, |c| 2.0 * c.radius);
    let mut stretches = Vec::new();
    for pair in times.windows(2) {
        let [t0, t1] = [pair[0], pair[1]];
        let middle = 0.5 * (t0 + t1);
        let (frame, sprays_in_middle) = path.at(middle);
        // The waypoints strictly inside the stretch: the corners of its piecewise path.
        let inside = &waypoints
            [waypoints.partition_point(|w| w.time <= t0)..waypoints.partition_point(|w| w.time < t1)];
        if !sprays_in_middle && !inside.iter().any(|w| w.spray) && !path.at(t0).1 {
            continue;
        }
        let corners = [path.at(t0).0, path.at(t1).0];
        let positions = corners.iter().map(|f| f.position).chain(inside.iter().map(|w| w.position));
        let axes = corners.iter().map(|f| f.axis).chain(inside.iter().map(|w| w.axis));
        let spread = positions.map(|p| p.distance(frame.position)).fold(0.0, f64::max) + circle;
        let turn = axes.map(|a| a.angle_between(frame.axis)).fold(0.0, f64::max);
        let speed = [t0, middle, t1].map(|t| path.velocity(t).length()).into_iter().fold(0.0, f64::max);
        stretches.push(Stretch {
            times: [t0, t1],
            position: frame.position,
            axis: frame.axis,
            spread,
            turn,
            speed,
        });
    }
    stretches
}

/// Time the nozzle of `path` sprays within `[0, duration]`, s: the legs that spray (from a
/// waypoint with `spray = true` to the next), and after the last waypoint if it sprays.
pub(crate) fn spraying_time(path: &NozzlePath, duration: f64) -> f64 {
    let w = path.waypoints();
    (0..w.len())
        .filter(|&i| w[i].spray)
        .map(|i| {
            let end = w.get(i + 1).map_or(duration, |next| next.time.min(duration));
            (end - w[i].time.max(0.0)).max(0.0)
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use spraysim_engine::emission::Waypoint;

    fn waypoint(time: f64, x: f64, spray: bool) -> Waypoint {
        Waypoint { time, position: DVec3::new(x, 0.0, 0.0), axis: DVec3::X, spray }
    }

    #[test]
    fn spraying_time_counts_only_the_legs_that_spray() {
        let path = NozzlePath::through(
            vec![waypoint(0.0, 0.0, true), waypoint(1.0, 1.0, false), waypoint(3.0, 2.0, true)],
            0.0,
        );
        // 0–1 s sprays, 1–3 s does not, 3–4 s sprays again.
        assert!((spraying_time(&path, 4.0) - 2.0).abs() < 1e-12);
        assert!((spraying_time(&path, 2.0) - 1.0).abs() < 1e-12);
        assert_eq!(spraying_time(&NozzlePath::fixed(DVec3::ZERO, DVec3::X, 0.0), 2.5), 2.5);
    }

    #[test]
    fn stretches_skip_the_legs_that_do_not_spray_and_bound_the_motion() {
        let path = NozzlePath::through(
            vec![waypoint(0.0, 0.0, true), waypoint(1.0, 1.0, false), waypoint(2.0, 2.0, false)],
            0.0,
        );
        let stretches = spraying_stretches(&path, 2.0);
        assert!(!stretches.is_empty());
        assert!(stretches.iter().all(|s| s.times[0] < 1.0), "{stretches:?}");
        for s in &stretches {
            let half = 0.5 * (s.times[1] - s.times[0]);
            assert!((s.spread - half).abs() < 1e-9, "moving at 1 m/s: {s:?}");
        }
    }
}
