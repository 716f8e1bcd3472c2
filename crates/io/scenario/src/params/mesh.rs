//! A triangle mesh read from a file and placed in the scene: the keys a mesh target and a mesh
//! obstacle share.

use crate::reader::{Check, Invalid, Read, Section};
use serde::Serialize;
use spraysim_engine::collision::Triangle;
use std::path::Path;
use std::sync::Arc;

/// A triangle mesh read from an STL or OBJ file and placed in the scene: each vertex `p` of the
/// file goes to `R · (scale · p) + translate`, with `R` the rotation by `rotate`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshParams {
    /// The file (`.stl` or `.obj`); the resolved scenario holds its absolute path.
    pub file: String,
    /// Factor from the file's units to metres (0.001 for millimetres).
    pub scale: f64,
    /// Rotation, degrees about x, then y, then z (fixed axes).
    pub rotate: [f64; 3],
    /// Translation after scaling and rotating, m.
    pub translate: [f64; 3],
    /// The placed triangles, m.
    #[serde(skip)]
    pub triangles: Arc<Vec<Triangle>>,
}

/// Reads and loads a mesh: `file` relative to `base`, `scale`, `rotate`, `translate`.
pub(crate) fn read_mesh(s: &Section<'_>, base: &Path) -> Read<MeshParams> {
    let file = s.string("file", None)?;
    let scale = s.number("scale", Some(1.0), Check::Positive(1e6), "")?;
    let rotate = s.numbers("rotate", Some([0.0; 3]), Check::Within(-360.0, 360.0), "degrees")?;
    let translate = s.point("translate", Some([0.0; 3]))?;
    let path = base.join(&file);
    let path = std::path::absolute(&path).unwrap_or(path);
    let triangles = crate::mesh::load(&path, scale, rotate, translate)
        .map_err(|e| Invalid { key: s.key("file"), message: format!("cannot be used: {e}") })?;
    Ok(MeshParams {
        file: path.display().to_string(),
        scale,
        rotate,
        translate,
        triangles: Arc::new(triangles),
    })
}
