//! `shape = "ledge"`, known to the tests only: a thin square plate level at its centre, built
//! into the engine as a [`Shape::Custom`] of a primitive defined here. It shows that a new
//! obstacle shape is one file and its line in the list of [`super::ObstacleShape`]: with
//! nothing else changed, a scenario reads it (naming it in errors), writes it back, bounds the
//! default domain by its box, builds it and stops particles on it.

use super::ObstacleGeometry;
use crate::params::v3;
use crate::reader::{Check, Read, Section};
use crate::scenario::Scenario;
use crate::scenes::floor;
use glam::DVec3;
use serde::Serialize;
use spraysim_engine::collision::{Aabb, Flight, Hit, Primitive, Shape, roots};
use std::path::Path;
use std::sync::Arc;

/// A horizontal square plate, two-sided.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LedgeObstacle {
    /// Centre, m.
    pub center: [f64; 3],
    /// Half the side of the square, m.
    pub half_side: f64,
}

impl ObstacleGeometry for LedgeObstacle {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        Ok(LedgeObstacle {
            center: s.point("center", None)?,
            half_side: s.number("half_side", None, Check::Positive(1e3), "m")?,
        })
    }

    fn shapes(&self) -> Vec<Shape> {
        vec![Shape::Custom(Arc::new(Ledge { center: v3(self.center), half: self.half_side }))]
    }
}

/// The engine's side of the ledge: a shape the engine does not know.
#[derive(Debug)]
struct Ledge {
    /// Centre, m.
    center: DVec3,
    /// Half the side, m.
    half: f64,
}

impl Ledge {
    /// The hit at `p` (m) after the fraction `t` of a path, if `p` is on the plate.
    fn at(&self, p: DVec3, t: f64, from_above: bool) -> Option<Hit> {
        let on = (p.x - self.center.x).abs() <= self.half && (p.y - self.center.y).abs() <= self.half;
        on.then_some(Hit { t, point: p, normal: if from_above { DVec3::Z } else { DVec3::NEG_Z } })
    }
}

impl Primitive for Ledge {
    fn intersect(&self, p0: DVec3, p1: DVec3) -> Option<Hit> {
        let (d0, d1) = (p0.z - self.center.z, p1.z - self.center.z);
        if d0 == 0.0 || (d0 > 0.0) == (d1 > 0.0) && d1 != 0.0 {
            return None;
        }
        let t = d0 / (d0 - d1);
        self.at(p0.lerp(p1, t), t, d0 > 0.0)
    }

    fn intersect_arc(&self, arc: &Flight) -> Option<Hit> {
        // z(τ) = z₀ + v τ + ½ g τ² = the plate's height: the first root in (0, T].
        let (a, b, c) = (0.5 * arc.g.z, arc.v0.z, arc.x0.z - self.center.z);
        let tau = roots(&[c, b, a], 0.0, arc.duration).iter().copied().find(|&tau| tau > 0.0)?;
        self.at(arc.at(tau), tau / arc.duration, c > 0.0)
    }

    fn aabb(&self) -> Option<Aabb> {
        let h = DVec3::new(self.half, self.half, 0.0);
        Some(Aabb { min: self.center - h, max: self.center + h })
    }
}

/// Shotcrete sprayed straight down from 1.5 m onto a 2 m × 2 m floor (a substrate), through a
/// ledge with the keys `ledge` (TOML), with no domain given.
fn scene(ledge: &str) -> String {
    format!(
        r#"
[simulation]
duration = 0.1
[emitter]
spawn_rate = 2000.0
[nozzle]
position = [0.0, 0.0, 1.5]
axis = [0.0, 0.0, -1.0]
{floor}[[obstacle]]
name = "ledge"
shape = "ledge"
{ledge}
"#,
        floor = floor().substrate().at([0.0, 0.0, 0.0]).size(2.0, 2.0).resolution(32, 32),
    )
}

#[test]
fn an_obstacle_shape_declared_in_one_file_and_one_line_works_end_to_end() {
    let sc = Scenario::from_toml(&scene("center = [0.0, 0.0, 0.75]\nhalf_side = 0.1"), "ledge.toml")
        .unwrap_or_else(|e| panic!("{e}"));
    // Written back with its word and keys, and read back the same.
    let resolved = sc.to_toml();
    assert!(
        resolved.contains("shape = \"ledge\"\ncenter = [0.0, 0.0, 0.75]\nhalf_side = 0.1\n"),
        "{resolved}"
    );
    assert_eq!(Scenario::from_toml(&resolved, "resolved.toml").unwrap_or_else(|e| panic!("{e}")), sc);
    // The default domain holds its box (the engine's `aabb`), grown by 1 m.
    let d = sc.domain();
    assert!(d.min[0] <= -1.1 && d.max[0] >= 1.1 && d.min[2] <= -1.0 && d.max[2] >= 2.5, "{d:?}");
    // It builds into the engine's shape and stops particles.
    let mut sim = sc.build().unwrap_or_else(|e| panic!("{e}"));
    sim.run(|_| {});
    let m = sim.metrics();
    assert!(m.obstacles[0].hits > 0, "nothing struck the ledge");
    assert_eq!(m.fates.total().count, m.emitted.count);
    // Errors name its keys and its kind.
    let err =
        Scenario::from_toml(&scene("center = [0.0, 0.0, 0.75]"), "ledge.toml").expect_err("no half_side");
    assert!(err.to_string().contains("`obstacle[0].half_side` is required for a ledge obstacle"), "{err}");
    let err =
        Scenario::from_toml(&scene("center = [0.0, 0.0, 0.75]\nhalf_side = 0.1\nradius = 1.0"), "ledge.toml")
            .expect_err("a key it does not have");
    assert!(err.to_string().contains("`obstacle[0].radius` is not a key of a ledge obstacle"), "{err}");
}
