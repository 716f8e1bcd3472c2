//! What only the run's metrics show: most particles still in flight at its end
//! (`still_in_flight`), and a nozzle mostly off the targets (`off_target`) or outside the
//! process's working window (`standoff_outside_window`, `angle_outside_window`,
//! `travel_speed_outside_window`). Each fires when it holds for more than [`MOST`] of what it
//! counts.

use super::{Warning, WarningCode, nozzle_key};
use crate::params::NozzleMotion;
use crate::scenario::Scenario;
use spraysim_engine::Metrics;

/// The share above which a check fires: "most", 0..1.
pub const MOST: f64 = 0.5;

/// The warnings `m`, the metrics of a run of `sc`, call for; `reachable` is false when the
/// check before the run found no target in reach (the off-target share then says nothing new).
pub(super) fn check(sc: &Scenario, m: &Metrics, reachable: bool) -> Vec<Warning> {
    let mut warnings: Vec<Warning> = still_in_flight(sc, m).into_iter().collect();
    warnings.extend(window(sc, m, reachable));
    warnings
}

/// `still_in_flight`: more than [`MOST`] of the emitted particles are in flight at the end.
fn still_in_flight(sc: &Scenario, m: &Metrics) -> Option<Warning> {
    let (emitted, in_flight) = (m.emitted.count, m.fates.in_flight.count);
    (emitted > 0 && in_flight as f64 > MOST * emitted as f64).then(|| Warning {
        code: WarningCode::StillInFlight,
        message: format!(
            "{:.1} % of the emitted particles are still in flight at the end of the run: \
             simulation.duration ({} s) ends before they land; lengthen it (or check that the \
             spray reaches a target)",
            100.0 * in_flight as f64 / emitted as f64,
            sc.simulation().duration
        ),
        key: "simulation.duration".into(),
    })
}

/// `off_target` and the window's warnings: the nozzle mostly off the targets, or outside
/// `[process.window]`, over the spraying time.
fn window(sc: &Scenario, m: &Metrics, reachable: bool) -> Vec<Warning> {
    let mut warnings = Vec::new();
    let p = &m.path;
    if p.spraying_time <= 0.0 {
        return warnings;
    }
    if p.off_target_share > MOST {
        if reachable {
            warnings.push(Warning {
                code: WarningCode::OffTarget,
                message: format!(
                    "the spray axis misses every target for {:.1} % of the spraying time: aim the nozzle at them",
                    100.0 * p.off_target_share
                ),
                key: nozzle_key(sc, "axis"),
            });
        }
        // Standoff and angle are judged on the time on target only.
        return warnings;
    }
    let w = &sc.process().window;
    // The share of the spraying time on target outside the window: the engine's share counts
    // the samples off target as outside too, out of all the spraying samples (off target is at
    // most half of them here).
    let off = p.off_target_share;
    let on_target = |share: f64| ((share - off) / (1.0 - off)).clamp(0.0, 1.0);
    let mut judge = |code, share: f64, of: &str, what: String, key: String| {
        if share > MOST {
            warnings.push(Warning {
                code,
                message: format!(
                    "{what} for {:.1} % of the {of} (process.window: the preset's recommendation)",
                    100.0 * share
                ),
                key,
            });
        }
    };
    if let Some(r) = p.standoff {
        judge(
            WarningCode::StandoffOutsideWindow,
            on_target(r.outside_share),
            "spraying time on target",
            format!(
                "the standoff (mean {:.3} m) is outside process.window.standoff [{}, {}] m",
                r.mean, w.standoff[0], w.standoff[1]
            ),
            nozzle_key(sc, "position"),
        );
    }
    if let Some(r) = p.angle {
        judge(
            WarningCode::AngleOutsideWindow,
            on_target(r.outside_share),
            "spraying time on target",
            format!(
                "the spray axis (mean {:.1}° off square) is beyond process.window.max_angle {}°",
                r.mean, w.max_angle
            ),
            nozzle_key(sc, "axis"),
        );
    }
    // A static or circling nozzle does not travel: its travel speed is not judged.
    let travels = matches!(sc.nozzle().motion, NozzleMotion::Waypoints { .. } | NozzleMotion::Raster { .. });
    if let Some(r) = p.travel_speed.filter(|_| travels) {
        judge(
            WarningCode::TravelSpeedOutsideWindow,
            r.outside_share,
            "spraying time",
            format!(
                "the travel speed (mean {:.3} m/s) is outside process.window.speed [{}, {}] m/s",
                r.mean, w.speed[0], w.speed[1]
            ),
            nozzle_key(sc, "speed"),
        );
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sanity::tests::through;

    /// The metrics of a run of `sc`, with `edit` applied to them.
    fn judged(sc: &Scenario, edit: impl FnOnce(&mut Metrics)) -> Vec<WarningCode> {
        let mut sim = sc.build().expect("built");
        sim.run(|_| {});
        let mut m = sim.metrics();
        edit(&mut m);
        check(sc, &m, true).into_iter().map(|w| w.code).collect()
    }

    #[test]
    fn a_static_nozzle_square_on_at_its_standoff_is_within_its_window() {
        assert_eq!(judged(&Scenario::default_scene(), |_| {}), vec![]);
    }

    #[test]
    fn particles_mostly_in_flight_call_for_a_longer_duration() {
        let codes = judged(&Scenario::default_scene(), |m| {
            m.fates.in_flight.count = m.emitted.count * 6 / 10;
        });
        assert_eq!(codes, vec![WarningCode::StillInFlight]);
        let codes = judged(&Scenario::default_scene(), |m| {
            m.fates.in_flight.count = m.emitted.count * 4 / 10;
        });
        assert_eq!(codes, vec![]);
    }

    #[test]
    fn a_nozzle_too_far_and_too_fast_is_outside_its_window() {
        // 3 m from the wall (window 1–2 m), crossing 1.6 m in 2 s at 0.8 m/s (window ≤ 0.5 m/s).
        let sc = through([-3.0, -0.8, 1.0], [-3.0, 0.8, 1.0], None);
        let codes = judged(&sc, |_| {});
        assert_eq!(codes, vec![WarningCode::StandoffOutsideWindow, WarningCode::TravelSpeedOutsideWindow]);
    }

    #[test]
    fn a_nozzle_mostly_off_target_is_told_so_once() {
        let sc = Scenario::default_scene().with("nozzle.axis", vec![1.0, 3.0, 0.0]).expect("valid");
        assert_eq!(judged(&sc, |_| {}), vec![WarningCode::OffTarget]);
    }

    #[test]
    fn the_window_is_judged_over_the_time_on_target() {
        // Half the spraying time off target, and all the time on target too far away: the
        // engine counts both as outside the standoff window, 100 % of the spraying time.
        let sc = Scenario::default_scene();
        let codes = judged(&sc, |m| {
            m.path.off_target_share = 0.5;
            if let Some(r) = &mut m.path.standoff {
                r.outside_share = 1.0;
            }
        });
        assert_eq!(codes, vec![WarningCode::StandoffOutsideWindow]);
        // A third off target and a third of the time on target outside: under half of it.
        let codes = judged(&sc, |m| {
            m.path.off_target_share = 1.0 / 3.0;
            if let Some(r) = &mut m.path.standoff {
                r.outside_share = 1.0 / 3.0 + 2.0 / 9.0;
            }
        });
        assert_eq!(codes, vec![]);
    }
}
