//! `shape = "sphere"`: a solid ball.

use super::ObstacleGeometry;
use crate::params::v3;
use crate::reader::{Check, Read, Section};
use serde::Serialize;
use spraysim_engine::collision::{Shape, Sphere};
use std::path::Path;

/// A solid sphere.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SphereObstacle {
    /// Centre, m.
    pub center: [f64; 3],
    /// Radius, m.
    pub radius: f64,
}

impl ObstacleGeometry for SphereObstacle {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        Ok(SphereObstacle {
            center: s.point("center", None)?,
            radius: s.number("radius", None, Check::Positive(1e3), "m")?,
        })
    }

    fn shapes(&self) -> Vec<Shape> {
        vec![Shape::Sphere(Sphere { center: v3(self.center), radius: self.radius })]
    }
}
