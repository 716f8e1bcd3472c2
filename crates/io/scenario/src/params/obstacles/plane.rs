//! `shape = "plane"`: an infinite plane (a floor or a wall reaching beyond the scene).

use super::ObstacleGeometry;
use crate::params::v3;
use crate::reader::{Read, Section};
use serde::Serialize;
use spraysim_engine::collision::{Plane, Shape};
use std::path::Path;

/// An infinite plane, two-sided.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlaneObstacle {
    /// A point on the plane, m.
    pub center: [f64; 3],
    /// Its normal, any length.
    pub normal: [f64; 3],
}

impl ObstacleGeometry for PlaneObstacle {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        Ok(PlaneObstacle { center: s.point("center", None)?, normal: s.direction("normal", None)? })
    }

    fn shapes(&self) -> Vec<Shape> {
        vec![Shape::Plane(Plane { point: v3(self.center), normal: v3(self.normal).normalize() })]
    }
}
