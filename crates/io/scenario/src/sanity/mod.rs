//! Sanity checks: the ordinary mistakes that make a run go through without error and come out
//! meaningless (a nozzle aimed away from every target, a tool path in millimetres, a duration
//! too short for the particles to land, maps too sparse to read), each a [`Warning`] that names
//! the key to change.
//!
//! [`before_run`] judges a scenario from its parameters alone, cheaply enough to run before
//! every run (it samples the nozzle's path and never builds the deposit grids);
//! [`after_run`] adds what only the run's metrics show. One check per file:
//!
//! - [`reach`]: no particle can reach any substrate target (`no_target_reachable`);
//! - [`path_bounds`]: the path leaves the domain (`path_outside_domain`), or runs more than
//!   100 m from every target (`path_far_from_targets`);
//! - [`sampling`]: fewer than about 10 particles per cell, or per splat, over the area the
//!   spray covers (`sparse_sampling`);
//! - [`outcome`]: most particles still in flight at the end (`still_in_flight`), the nozzle
//!   mostly off the targets (`off_target`) or outside the process's window
//!   (`standoff_outside_window`, `angle_outside_window`, `travel_speed_outside_window`).

mod cone;
pub mod outcome;
pub mod path_bounds;
mod poses;
pub mod reach;
pub mod sampling;

pub use cone::{EnclosingBox, cone_meets_box};

use crate::build::nozzle_path;
use crate::params::NozzleMotion;
use crate::scenario::Scenario;
use serde::Serialize;
use spraysim_engine::Metrics;

/// What a warning is about: a stable name for scripts (`metrics.json`'s `warnings[].code`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WarningCode {
    /// No particle can reach any substrate target: the cone points away from them all.
    NoTargetReachable,
    /// The nozzle's path, or a waypoint of it, lies outside the domain box.
    PathOutsideDomain,
    /// The nozzle's path runs more than [`path_bounds::FAR`] from every target.
    PathFarFromTargets,
    /// Fewer than [`sampling::MIN_PER_CELL`] particles per cell (or splat) are expected.
    SparseSampling,
    /// Most particles are still in flight at the end of the run.
    StillInFlight,
    /// The spray axis misses every substrate most of the spraying time.
    OffTarget,
    /// The standoff is outside `process.window.standoff` most of the spraying time.
    StandoffOutsideWindow,
    /// The spray angle is beyond `process.window.max_angle` most of the spraying time.
    AngleOutsideWindow,
    /// The travel speed is outside `process.window.speed` most of the spraying time.
    TravelSpeedOutsideWindow,
}

impl WarningCode {
    /// The code as `metrics.json` writes it: `no_target_reachable`.
    pub fn as_str(self) -> &'static str {
        match self {
            WarningCode::NoTargetReachable => "no_target_reachable",
            WarningCode::PathOutsideDomain => "path_outside_domain",
            WarningCode::PathFarFromTargets => "path_far_from_targets",
            WarningCode::SparseSampling => "sparse_sampling",
            WarningCode::StillInFlight => "still_in_flight",
            WarningCode::OffTarget => "off_target",
            WarningCode::StandoffOutsideWindow => "standoff_outside_window",
            WarningCode::AngleOutsideWindow => "angle_outside_window",
            WarningCode::TravelSpeedOutsideWindow => "travel_speed_outside_window",
        }
    }
}

impl std::fmt::Display for WarningCode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A run that goes through but whose result is probably not what was meant, with the key that
/// fixes it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Warning {
    /// What it is about.
    pub code: WarningCode,
    /// What is wrong and what to do, one or two sentences.
    pub message: String,
    /// The dotted scenario key to change (`nozzle.axis`, `target[0].splat_radius`).
    pub key: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} [{}; change `{}`]", self.message, self.code, self.key)
    }
}

/// The warnings about `sc` that its parameters show, before it runs.
pub fn before_run(sc: &Scenario) -> Vec<Warning> {
    let path = nozzle_path(sc);
    let stretches = poses::spraying_stretches(&path, sc.simulation().duration);
    let mut warnings = Vec::new();
    warnings.extend(path_bounds::check(sc, &path));
    warnings.extend(reach::check(sc, &stretches));
    warnings.extend(sampling::check(sc, &stretches));
    warnings
}

/// Every warning about a run of `sc` whose metrics are `m`: [`before_run`]'s and those the
/// outcome shows.
pub fn after_run(sc: &Scenario, m: &Metrics) -> Vec<Warning> {
    let mut warnings = before_run(sc);
    let reachable = !warnings.iter().any(|w| w.code == WarningCode::NoTargetReachable);
    warnings.extend(outcome::check(sc, m, reachable));
    warnings
}

/// Particles the nozzle of `sc` emits over the run: only while it sprays (a waypoint with
/// `spray = false` emits nothing until the next).
pub fn sprayed_particles(sc: &Scenario) -> f64 {
    let path = nozzle_path(sc);
    sc.emitter().spawn_rate * poses::spraying_time(&path, sc.simulation().duration)
}

/// The key that sets what the nozzle's path does: `what` (`position`, `axis`, `speed`) of a
/// static or circling nozzle, its waypoints, or its raster.
pub(crate) fn nozzle_key(sc: &Scenario, what: &str) -> String {
    match (&sc.nozzle().motion, what) {
        (NozzleMotion::Static { .. } | NozzleMotion::Circling { .. }, "speed") => "nozzle.waypoints".into(),
        (NozzleMotion::Static { .. } | NozzleMotion::Circling { .. }, _) => format!("nozzle.{what}"),
        (NozzleMotion::Waypoints { .. }, _) => "nozzle.waypoints".into(),
        (NozzleMotion::Raster { .. }, "position") => "nozzle.raster.standoff".into(),
        (NozzleMotion::Raster { .. }, "speed") => "nozzle.raster.speed".into(),
        (NozzleMotion::Raster { .. }, _) => "nozzle.raster.target".into(),
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use crate::scenario::Scenario;

    /// The default scene with its nozzle moving square to the wall from `a` to `b` (m) over
    /// the run's 2 s, spraying, in the given domain box `(min, max)` (m) if any.
    pub(crate) fn through(a: [f64; 3], b: [f64; 3], domain: Option<([f64; 3], [f64; 3])>) -> Scenario {
        let waypoints = format!(
            "[[nozzle.waypoints]]\ntime = 0.0\nposition = {a:?}\naxis = [1.0, 0.0, 0.0]\n\
             [[nozzle.waypoints]]\ntime = 2.0\nposition = {b:?}\naxis = [1.0, 0.0, 0.0]\n"
        );
        let text = crate::DEFAULT_SCENE
            .replace("position = [-1.0, 0.0, 1.0]   # m: 1 m in front of the wall's centre\n", "")
            .replace("axis = [1.0, 0.0, 0.0]        # spraying square onto the wall\n", "");
        let domain =
            domain.map_or(String::new(), |(lo, hi)| format!("[domain]\nmin = {lo:?}\nmax = {hi:?}\n"));
        Scenario::from_toml(&format!("{text}\n{waypoints}{domain}"), "test").expect("valid scenario")
    }
}
