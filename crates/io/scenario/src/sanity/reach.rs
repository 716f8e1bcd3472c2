//! `no_target_reachable`: no particle can reach any substrate target.
//!
//! The rule: along the nozzle's path, sampled in stretches (every waypoint, and at least 64
//! even steps over the run), the emitter's cone — its axis and half-angle (for a fan, the
//! wider half-angle) — is cast at a box that holds each substrate target (each target when none
//! is a substrate). The check is conservative, so that it never warns of a scenario in which
//! some particle can land: the cone is widened by how far the axis turns over the stretch and
//! by the angle the nozzle's own velocity can add (with `nozzle.add_velocity`); the box is
//! grown by how far the nozzle moves over the stretch, by the aperture's radius and by the
//! fall under gravity, ½·g·t², over the longest time a particle at the slowest emission speed
//! takes to cover the distance to the box's farthest corner (slowed by drag, at most the
//! process's `max_lifetime`). Obstacles are ignored: they can only stop particles.

use super::poses::Stretch;
use super::{Warning, WarningCode, nozzle_key};
use crate::build::emitter;
use crate::params::v3;
use crate::scenario::Scenario;
use glam::DVec3;
use spraysim_engine::emission::{self, Emitter};
use spraysim_engine::world::Role;

/// Largest exponent of drag's slowing taken into the flight time (beyond, `max_lifetime`
/// bounds it anyway).
const MAX_DRAG_EXPONENT: f64 = 50.0;

/// The warning when no spraying stretch's cone meets any substrate target's box.
pub(super) fn check(sc: &Scenario, stretches: &[Stretch]) -> Option<Warning> {
    if stretches.is_empty() || sc.targets().is_empty() {
        return None;
    }
    let e = emitter(sc.emitter(), sc.process().flow_rate);
    let substrates = sc.targets().iter().any(|t| t.role == Role::Substrate);
    let aimed: Vec<_> = sc.targets().iter().filter(|t| !substrates || t.role == Role::Substrate).collect();
    let reach = Reach::of(sc, &e);
    let reachable =
        stretches.iter().any(|s| aimed.iter().any(|t| reach.meets(s, &t.shape.as_dyn().enclosing_box())));
    if reachable {
        return None;
    }
    let names: Vec<String> = aimed.iter().map(|t| format!("`{}`", t.name)).collect();
    let which = if substrates { "substrate target" } else { "target" };
    Some(Warning {
        code: WarningCode::NoTargetReachable,
        message: format!(
            "no particle can reach any {which} ({}): the spray cone ({:.1}° half-angle) points away from \
             them along the whole path; aim the nozzle at them",
            names.join(", "),
            e.cone_half_angle.to_degrees()
        ),
        key: nozzle_key(sc, "axis"),
    })
}

/// What widens the cone and grows the boxes, whatever the stretch.
struct Reach {
    /// Half-angle of the cone, rad.
    half_angle: f64,
    /// Radius of the aperture around the nozzle's point, m.
    aperture: f64,
    /// Slowest emission speed, m/s.
    slowest: f64,
    /// Fastest emission speed, m/s.
    fastest: f64,
    /// Drag coefficient k, 1/m (dv/dt = −k |v| v).
    drag: f64,
    /// Longest a particle flies, s.
    lifetime: f64,
    /// |g|, m/s².
    gravity: f64,
    /// Whether the nozzle's velocity adds to the particles'.
    adds_velocity: bool,
}

impl Reach {
    fn of(sc: &Scenario, e: &Emitter) -> Reach {
        let aperture = match e.aperture {
            emission::Aperture::Point => 0.0,
            emission::Aperture::Circle { r } => r,
            emission::Aperture::Rectangle { hw, hh } => hw.hypot(hh),
            emission::Aperture::Annulus { r_out, .. } => r_out,
        };
        let half_angle = match e.direction {
            // A fan's directions fill a rectangle in the tangents of its two angles: its corner
            // rays lie farthest from the axis.
            emission::Direction::Fan { wide, narrow } => {
                (0.5 * wide).tan().hypot((0.5 * narrow).tan()).atan()
            }
            _ => e.cone_half_angle,
        };
        Reach {
            half_angle,
            aperture,
            slowest: e.speed[0].max(1e-9),
            fastest: e.speed[1],
            drag: sc.process().drag.max(0.0),
            lifetime: sc.process().max_lifetime,
            gravity: v3(sc.simulation().gravity).length(),
            adds_velocity: sc.nozzle().add_velocity,
        }
    }

    /// The longest a particle takes to fly `distance` (m), s: at the slowest speed, slowed by
    /// drag (s(t) = ln(1 + k v t) / k), at most the lifetime.
    fn flight_time(&self, distance: f64) -> f64 {
        let (k, v) = (self.drag, self.slowest);
        let t = if k * distance < 1e-9 {
            distance / v
        } else {
            (k * distance).min(MAX_DRAG_EXPONENT).exp_m1() / (k * v)
        };
        t.min(self.lifetime)
    }

    /// True if the widened cone of stretch `s` meets box `b`, grown.
    fn meets(&self, s: &Stretch, b: &super::EnclosingBox) -> bool {
        let carried_speed = if self.adds_velocity { s.speed } else { 0.0 };
        let range =
            (self.fastest + carried_speed) * self.lifetime + 0.5 * self.gravity * self.lifetime.powi(2);
        if b.distance(s.position) > range + s.spread + self.aperture {
            return false;
        }
        let distance = b.farthest(s.position) + s.spread;
        let fall = 0.5 * self.gravity * self.flight_time(distance).powi(2);
        let grown = b.grown(s.spread + self.aperture + fall);
        // Adding the nozzle's velocity turns a particle by at most asin(v_nozzle / v_particle),
        // any way at all once the nozzle is as fast.
        let carried = if self.adds_velocity {
            let ratio = s.speed / self.slowest;
            if ratio < 1.0 { ratio.asin() } else { std::f64::consts::PI }
        } else {
            0.0
        };
        super::cone_meets_box(s.position, s.axis, self.half_angle + s.turn + carried, &grown)
    }
}

/// Whether the cone from `position` along `axis` can reach the box around `target` in `sc`,
/// for a nozzle at rest: the module's rule for one pose.
pub fn reaches(sc: &Scenario, position: DVec3, axis: DVec3, target: usize) -> bool {
    let Some(t) = sc.targets().get(target) else { return false };
    let e = emitter(sc.emitter(), sc.process().flow_rate);
    let stretch = Stretch {
        times: [0.0, 0.0],
        position,
        axis: axis.normalize_or(DVec3::X),
        spread: 0.0,
        turn: 0.0,
        speed: 0.0,
    };
    Reach::of(sc, &e).meets(&stretch, &t.shape.as_dyn().enclosing_box())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_with(overrides: &[(&str, &str)]) -> Scenario {
        let mut sc = Scenario::default_scene();
        for (k, v) in overrides {
            sc = sc.with_assignment(&format!("{k}={v}")).expect("valid override");
        }
        sc
    }

    fn warning(sc: &Scenario) -> Option<Warning> {
        let path = crate::build::nozzle_path(sc);
        check(sc, &super::super::poses::spraying_stretches(&path, sc.simulation().duration))
    }

    #[test]
    fn the_default_scene_reaches_its_wall() {
        assert_eq!(warning(&Scenario::default_scene()), None);
    }

    #[test]
    fn a_nozzle_aimed_away_from_the_wall_is_warned_of_naming_the_axis() {
        let w = warning(&default_with(&[("nozzle.axis", "[-1,0,0]")])).expect("warned");
        assert_eq!(w.code, WarningCode::NoTargetReachable);
        assert_eq!(w.key, "nozzle.axis");
        assert!(w.message.contains("`wall`"), "{}", w.message);
    }

    #[test]
    fn a_nozzle_aimed_just_past_the_edge_still_reaches_it_through_its_cone() {
        // Aimed 1.1 m to the side from 1 m: the axis misses the 2 m wall, the 9° cone does not.
        assert_eq!(warning(&default_with(&[("nozzle.axis", "[1,1.1,0]")])), None);
        // Aimed parallel to the wall, the cone misses it by far.
        assert!(warning(&default_with(&[("nozzle.axis", "[0,1,0]")])).is_some());
    }

    #[test]
    fn a_target_beyond_the_particles_flight_is_out_of_reach() {
        // Aimed at the wall from 1 km (a path in millimetres): the cone meets it, no particle
        // lives long enough to get there.
        let sc = Scenario::default_scene();
        let far = DVec3::new(-1000.0, 0.0, 1.0);
        assert!(!reaches(&sc, far, DVec3::X, 0));
        let long_lived = sc.with("process.max_lifetime", 100.0).expect("valid");
        assert!(reaches(&long_lived, far, DVec3::X, 0));
    }

    #[test]
    fn gravity_grows_the_reach_towards_a_target_below() {
        // Level over the wall's top edge, 0.3 m above it: the cone alone passes over the wall; a
        // strong enough pull brings the spray down onto it.
        let (position, axis) = (DVec3::new(-0.5, 0.0, 2.3), DVec3::X);
        let sc = default_with(&[("simulation.gravity", "[0,0,0]")]);
        assert!(!reaches(&sc, position, axis, 0));
        let heavy = default_with(&[("simulation.gravity", "[0,0,-100]")]);
        assert!(reaches(&heavy, position, axis, 0));
    }
}
