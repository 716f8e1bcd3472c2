//! `shape = "disk"`: a flat disk (a round plate, a manhole cover).

use super::ObstacleGeometry;
use crate::params::v3;
use crate::reader::{Check, Read, Section};
use serde::Serialize;
use spraysim_engine::collision::{Disk, Shape};
use std::path::Path;

/// A flat disk, two-sided.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DiskObstacle {
    /// Centre, m.
    pub center: [f64; 3],
    /// Normal, any length.
    pub normal: [f64; 3],
    /// Radius, m.
    pub radius: f64,
}

impl ObstacleGeometry for DiskObstacle {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        Ok(DiskObstacle {
            center: s.point("center", None)?,
            normal: s.direction("normal", None)?,
            radius: s.number("radius", None, Check::Positive(1e3), "m")?,
        })
    }

    fn shapes(&self) -> Vec<Shape> {
        let (center, normal) = (v3(self.center), v3(self.normal).normalize());
        vec![Shape::Disk(Disk { center, normal, radius: self.radius })]
    }
}
