//! `shape = "face"`: a rectangle (a panel, formwork).

use super::ObstacleGeometry;
use crate::params::v3;
use crate::reader::{Check, Read, Section, not_parallel};
use serde::Serialize;
use spraysim_engine::collision::{Face, Shape};
use std::path::Path;

/// A rectangle, two-sided.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FaceObstacle {
    /// Centre, m.
    pub center: [f64; 3],
    /// Normal, any length.
    pub normal: [f64; 3],
    /// A direction in the face, along its height (made perpendicular to `normal`).
    pub up: [f64; 3],
    /// `[width, height]`, m; width along `up × normal`, height along `up`.
    pub size: [f64; 2],
}

impl ObstacleGeometry for FaceObstacle {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        let (center, normal, up) =
            (s.point("center", None)?, s.direction("normal", None)?, s.direction("up", None)?);
        not_parallel(&s.key("up"), up, normal, "normal")?;
        Ok(FaceObstacle { center, normal, up, size: s.numbers("size", None, Check::Positive(1e4), "m")? })
    }

    fn shapes(&self) -> Vec<Shape> {
        vec![Shape::Face(Face::new(v3(self.center), v3(self.normal).normalize(), v3(self.up), self.size))]
    }
}
