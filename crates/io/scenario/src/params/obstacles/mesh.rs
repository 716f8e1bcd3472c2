//! `shape = "mesh"`: a triangle mesh from an STL or OBJ file (formwork, a machine part).

use super::ObstacleGeometry;
use crate::budget::{PER_TRIANGLE, Storage};
use crate::params::mesh::{MeshParams, read_mesh};
use crate::reader::{Read, Section};
use spraysim_engine::collision::{Aabb, Primitive, Shape};
use std::path::Path;

impl ObstacleGeometry for MeshParams {
    fn read(s: &Section<'_>, base: &Path) -> Read<Self> {
        read_mesh(s, base)
    }

    fn shapes(&self) -> Vec<Shape> {
        self.triangles.iter().map(|&t| Shape::Triangle(t)).collect()
    }

    /// The triangles' boxes, without building their shapes (a mesh may have millions).
    fn bounds(&self) -> Option<Aabb> {
        self.triangles.iter().filter_map(Primitive::aabb).reduce(Aabb::union)
    }

    fn storage(&self) -> Option<Storage> {
        let n = self.triangles.len() as f64;
        Some(Storage { key: "file", what: format!("{n} triangles"), bytes: n * PER_TRIANGLE })
    }
}
