//! `path_outside_domain` and `path_far_from_targets`: a nozzle path that lies where no run can
//! use it — outside the domain box (its particles are retired as soon as they are emitted), or
//! more than [`FAR`] from every target (a tool path written in millimetres, read as metres).

use super::{Warning, WarningCode, nozzle_key};
use crate::params::v3;
use crate::scenario::Scenario;
use spraysim_engine::emission::NozzlePath;

/// Farther than this from every target, a nozzle position is taken for a mistake, m.
pub const FAR: f64 = 100.0;

/// The warnings about where `path`, the nozzle path of `sc`, lies: one per kind of mistake,
/// naming the first waypoint at fault.
pub(super) fn check(sc: &Scenario, path: &NozzlePath) -> Vec<Warning> {
    let mut warnings = Vec::new();
    let waypoints = path.waypoints();
    let (min, max) = (v3(sc.domain().min), v3(sc.domain().max));
    // A superposed circle moves the nozzle off its waypoints by up to its radius.
    let circle = path.circle().map_or(0.0, |c| c.radius);
    let outside = waypoints
        .iter()
        .position(|w| (w.position - circle).cmplt(min).any() || (w.position + circle).cmpgt(max).any());
    let which = |k: usize| {
        if waypoints.len() > 1 { format!("waypoint {k} of the nozzle's path") } else { "the nozzle".into() }
    };
    if let Some(k) = outside {
        warnings.push(Warning {
            code: WarningCode::PathOutsideDomain,
            message: format!(
                "{} at {} m lies outside the domain box (domain.min {:?} m, domain.max {:?} m): what it emits \
                 there is retired at once; move the path, or widen the domain",
                which(k),
                waypoints[k].position,
                sc.domain().min,
                sc.domain().max
            ),
            key: nozzle_key(sc, "position"),
        });
    }
    let boxes: Vec<_> = sc.targets().iter().map(|t| t.shape.as_dyn().enclosing_box()).collect();
    // Without targets there is nothing to be far from.
    if boxes.is_empty() {
        return warnings;
    }
    let nearest =
        |k: usize| boxes.iter().map(|b| b.distance(waypoints[k].position)).fold(f64::INFINITY, f64::min);
    let far = (0..waypoints.len()).find(|&k| nearest(k) > FAR);
    if let Some(k) = far {
        warnings.push(Warning {
            code: WarningCode::PathFarFromTargets,
            message: format!(
                "{} at {} m is {:.0} m from the nearest target, more than {FAR} m: positions are in metres \
                 (a tool path in millimetres must be divided by 1000)",
                which(k),
                waypoints[k].position,
                nearest(k)
            ),
            key: nozzle_key(sc, "position"),
        });
    }
    warnings
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sanity::tests::through;

    fn warnings(sc: &Scenario) -> Vec<Warning> {
        check(sc, &crate::build::nozzle_path(sc))
    }

    #[test]
    fn the_default_scene_lies_within_its_domain_and_near_its_targets() {
        assert_eq!(warnings(&Scenario::default_scene()), vec![]);
        assert_eq!(warnings(&through([-1.0, -0.5, 1.0], [-1.0, 0.5, 1.0], None)), vec![]);
    }

    #[test]
    fn a_tool_path_in_millimetres_is_far_from_every_target() {
        let w = warnings(&through([-1000.0, -500.0, 1000.0], [-1000.0, 500.0, 1000.0], None));
        assert_eq!(w.len(), 1, "{w:?}");
        assert_eq!(w[0].code, WarningCode::PathFarFromTargets);
        assert_eq!(w[0].key, "nozzle.waypoints");
        assert!(
            w[0].message.contains("waypoint 0") && w[0].message.contains("millimetres"),
            "{}",
            w[0].message
        );
    }

    #[test]
    fn a_waypoint_outside_a_given_domain_is_named() {
        let domain = Some(([-2.0, -2.0, -1.0], [1.0, 2.0, 3.0]));
        let w = warnings(&through([-1.0, 0.0, 1.0], [-1.0, 2.5, 1.0], domain));
        assert_eq!(w.iter().map(|w| w.code).collect::<Vec<_>>(), vec![WarningCode::PathOutsideDomain]);
        assert!(w[0].message.contains("waypoint 1"), "{}", w[0].message);
        assert_eq!(w[0].key, "nozzle.waypoints");
    }
}
