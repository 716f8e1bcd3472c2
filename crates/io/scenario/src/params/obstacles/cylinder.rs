//! `shape = "cylinder"`: a solid bar with flat ends (rebar, a pipe, a column).

use super::ObstacleGeometry;
use crate::params::v3;
use crate::reader::{Check, Read, Section, bad};
use serde::Serialize;
use spraysim_engine::collision::{Cylinder, Shape};
use std::path::Path;

/// A solid cylinder with flat caps.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CylinderObstacle {
    /// Centre of the first cap, m.
    pub start: [f64; 3],
    /// Centre of the second cap, m.
    pub end: [f64; 3],
    /// Radius, m.
    pub radius: f64,
}

impl ObstacleGeometry for CylinderObstacle {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        let (start, end) = (s.point("start", None)?, s.point("end", None)?);
        if v3(start).distance(v3(end)) < 1e-9 {
            return bad(&s.key("end"), "must differ from start");
        }
        Ok(CylinderObstacle { start, end, radius: s.number("radius", None, Check::Positive(1e3), "m")? })
    }

    fn shapes(&self) -> Vec<Shape> {
        vec![Shape::Cylinder(Cylinder { a: v3(self.start), b: v3(self.end), radius: self.radius })]
    }
}
