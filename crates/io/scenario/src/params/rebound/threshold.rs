//! `rebound_model = "threshold"`, known to the tests only: every impact steeper than
//! `critical_angle` rebounds, every other sticks, by an engine law defined here. It shows that
//! a new rebound law is one file and its line in the list of [`super::ReboundParams`]: with
//! nothing else changed, a scenario reads it in `[process.impact]` and in a surface's `impact`
//! table (over the process's values), writes it back and runs it.

use super::ReboundModel;
use crate::reader::{Check, Read, Section};
use crate::scenario::Scenario;
use crate::scenes::wall;
use serde::Serialize;
use spraysim_engine::process::{ImpactSite, ReboundLaw};
use std::sync::Arc;

/// The keys of the threshold law.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ThresholdLaw {
    /// Impacts farther than this from the normal rebound, degrees.
    pub critical_angle: f64,
}

impl ReboundModel for ThresholdLaw {
    /// 45°.
    fn defaults() -> Self {
        ThresholdLaw { critical_angle: 45.0 }
    }

    fn read_over(s: &Section<'_>, d: &Self) -> Read<Self> {
        let critical_angle =
            s.number("critical_angle", Some(d.critical_angle), Check::Within(-1.0, 90.0), "degrees")?;
        Ok(ThresholdLaw { critical_angle })
    }

    fn law(&self) -> Arc<dyn ReboundLaw> {
        Arc::new(Threshold { critical: self.critical_angle.to_radians() })
    }
}

/// The engine's side of the law: a law the engine does not know.
#[derive(Debug)]
struct Threshold {
    /// Impacts farther than this from the normal rebound, rad.
    critical: f64,
}

impl ReboundLaw for Threshold {
    fn probability(&self, impact: &ImpactSite) -> f64 {
        if impact.theta > self.critical { 1.0 } else { 0.0 }
    }
}

/// Painting sprayed square onto a wall, with `impact` as the process's impact table and a
/// wall whose own impact table changes the threshold law's angle to 80°.
fn scene(impact: &str) -> String {
    format!(
        r#"
[simulation]
duration = 0.1
[process]
preset = "painting"
[process.impact]
alpha = 1.0
restitution = 0.3
{impact}
[emitter]
spawn_rate = 2000.0
[nozzle]
position = [-0.3, 0.0, 1.0]
axis = [1.0, 0.0, 0.0]
{wall}"#,
        wall = wall().resolution(32, 32).with("[target.impact]\ncritical_angle = 80.0"),
    )
}

#[test]
fn a_rebound_law_declared_in_one_file_and_one_line_works_end_to_end() {
    let sc = Scenario::from_toml(&scene("rebound_model = \"threshold\"\ncritical_angle = -1.0"), "law.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    let resolved = sc.to_toml();
    assert!(resolved.contains("rebound_model = \"threshold\"\ncritical_angle = -1.0\n"), "{resolved}");
    assert_eq!(Scenario::from_toml(&resolved, "resolved.toml").unwrap_or_else(|e| panic!("{e}")), sc);
    // The wall's own table takes the process's law and changes its key: nothing is steeper than
    // 80° there, so everything sticks.
    let mut sim = sc.build().unwrap_or_else(|e| panic!("{e}"));
    sim.run(|_| {});
    assert_eq!(sim.metrics().rebound_ratio, Some(0.0));
    // Without the override, the process's law (-1°: every impact is steeper) bounces all.
    let sc = sc.with("target[0].impact", crate::Value::Toml("{}".into())).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().unwrap_or_else(|e| panic!("{e}"));
    sim.run(|_| {});
    assert_eq!(sim.metrics().rebound_ratio, Some(1.0));
    // Its defaults, and its keys refused under another law.
    let sc = Scenario::from_toml(&scene("rebound_model = \"threshold\""), "law.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(sc.to_toml().contains("critical_angle = 45.0"));
    let err = Scenario::from_toml(&scene("rebound_model = \"never\""), "law.toml")
        .expect_err("a key of another law");
    assert!(
        err.to_string().contains(
            "`target[0].impact.critical_angle` is not a key of an impact table with rebound_model = \"never\""
        ),
        "{err}"
    );
}
