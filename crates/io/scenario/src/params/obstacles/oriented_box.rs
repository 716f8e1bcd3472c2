//! `shape = "box"`: a solid box on axes of its own (a beam, a block-out).

use super::ObstacleGeometry;
use crate::params::v3;
use crate::reader::{Check, Read, Section, not_parallel};
use glam::DVec3;
use serde::Serialize;
use spraysim_engine::collision::{OrientedBox, Shape};
use std::path::Path;

/// A solid box on axes of its own.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BoxObstacle {
    /// Centre, m.
    pub center: [f64; 3],
    /// Full size along the box's own x, y and z axes, m.
    pub size: [f64; 3],
    /// Direction of the box's x axis, any length.
    pub x_axis: [f64; 3],
    /// Direction of its y axis (made perpendicular to `x_axis`); z completes a right-handed set.
    pub y_axis: [f64; 3],
}

impl ObstacleGeometry for BoxObstacle {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        let center = s.point("center", None)?;
        let size = s.numbers("size", None, Check::Positive(1e4), "m")?;
        let x_axis = s.direction("x_axis", Some([1.0, 0.0, 0.0]))?;
        let y_axis = s.direction("y_axis", Some([0.0, 1.0, 0.0]))?;
        not_parallel(&s.key("y_axis"), y_axis, x_axis, "x_axis")?;
        Ok(BoxObstacle { center, size, x_axis, y_axis })
    }

    fn shapes(&self) -> Vec<Shape> {
        let x = v3(self.x_axis).normalize();
        let y = v3(self.y_axis);
        let y = (y - x * y.dot(x)).normalize();
        vec![Shape::Box(OrientedBox {
            center: v3(self.center),
            axes: [x, y, x.cross(y)],
            half_extents: DVec3::from_array(self.size) / 2.0,
        })]
    }
}
