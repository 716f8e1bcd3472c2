//! Triangle meshes from STL (binary or ASCII) and Wavefront OBJ files.

use crate::input::{InputKind, read_input};
use crate::reader::{MAX_COORD, Num};
use glam::{DMat3, DVec3};
use spraysim_engine::collision::Triangle;
use std::path::Path;

/// Why a mesh could not be read.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {message}")]
pub struct MeshError {
    /// Path of the mesh file, as the scenario gives it.
    pub path: String,
    /// What is wrong.
    pub message: String,
}

/// Most triangles a mesh may have.
pub const MAX_TRIANGLES: usize = 10_000_000;

/// Reads the triangles of an `.stl` or `.obj` file, each corner `c` mapped to
/// `R · (c · scale) + translate` (m), `R` the rotation by `rotate` (degrees about x, then y,
/// then z). Degenerate triangles are dropped. The file must be a regular file of at most
/// [`InputKind::Mesh`]'s cap (see [`read_input`]); an OBJ file's materials (`mtllib`) are not
/// read, so no other file is opened.
pub fn load(
    path: &Path,
    scale: f64,
    rotate: [f64; 3],
    translate: [f64; 3],
) -> Result<Vec<Triangle>, MeshError> {
    let err = |message: String| MeshError { path: path.display().to_string(), message };
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("stl" | "obj")) {
        return Err(err("unknown mesh format: use .stl or .obj".into()));
    }
    let bytes = read_input(path, InputKind::Mesh).map_err(|e| err(e.problem.to_string()))?;
    let corners: Vec<[DVec3; 3]> = match ext.as_deref() {
        Some("stl") => {
            check_stl_size(&bytes).map_err(err)?;
            let mesh = stl_io::read_stl(&mut std::io::Cursor::new(&bytes))
                .map_err(|e| err(format!("not a valid STL file: {e}")))?;
            let v =
                |i: usize| mesh.vertices.get(i).map(|p| DVec3::new(p[0].into(), p[1].into(), p[2].into()));
            mesh.faces
                .iter()
                .map(|f| Some([v(f.vertices[0])?, v(f.vertices[1])?, v(f.vertices[2])?]))
                .collect::<Option<_>>()
                .ok_or_else(|| err("a face refers to a missing vertex".into()))?
        }
        Some("obj") => {
            let options = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
            // Materials are not used: refusing each `mtllib` keeps tobj from opening other files.
            let no_materials = |_: &Path| Err(tobj::LoadError::OpenFileFailed);
            let (models, _) = tobj::load_obj_buf(&mut bytes.as_slice(), &options, no_materials)
                .map_err(|e| err(format!("not a valid OBJ file: {e}")))?;
            let mut out = Vec::new();
            for m in models {
                let p = &m.mesh.positions;
                let v = |i: u32| {
                    let i = i as usize * 3;
                    p.get(i..i + 3).map(|c| DVec3::new(c[0].into(), c[1].into(), c[2].into()))
                };
                for tri in m.mesh.indices.chunks_exact(3) {
                    let t = [v(tri[0]), v(tri[1]), v(tri[2])];
                    let [Some(a), Some(b), Some(c)] = t else {
                        return Err(err("a face refers to a missing vertex".into()));
                    };
                    out.push([a, b, c]);
                }
            }
            out
        }
        _ => return Err(err("unknown mesh format: use .stl or .obj".into())),
    };
    drop(bytes);
    if corners.len() > MAX_TRIANGLES {
        return Err(err(format!("has {} triangles, more than {MAX_TRIANGLES}", corners.len())));
    }
    let offset = DVec3::from_array(translate);
    let [rx, ry, rz] = rotate.map(f64::to_radians);
    let rotation = (rotate != [0.0; 3])
        .then(|| DMat3::from_rotation_z(rz) * DMat3::from_rotation_y(ry) * DMat3::from_rotation_x(rx));
    let place = |p: DVec3| match rotation {
        Some(r) => r * (p * scale) + offset,
        None => p * scale + offset,
    };
    let mut triangles = Vec::with_capacity(corners.len());
    for (i, [a, b, c]) in corners.into_iter().enumerate() {
        let placed = [place(a), place(b), place(c)];
        // Every coordinate a scenario gives is bounded; a mesh's, once placed, is too.
        if let Some(p) = placed.iter().find(|p| !(p.is_finite() && p.abs().max_element() <= MAX_COORD)) {
            return Err(err(format!(
                "triangle {} has a corner at [{}, {}, {}] m once scaled, rotated and translated: every coordinate must lie within ±{} m",
                i + 1,
                Num(p.x),
                Num(p.y),
                Num(p.z),
                Num(MAX_COORD)
            )));
        }
        triangles.extend(Triangle::new(placed[0], placed[1], placed[2]));
    }
    if triangles.is_empty() {
        return Err(err("holds no triangles".into()));
    }
    Ok(triangles)
}

/// Refuses a binary STL whose facet count disagrees with its length: 84 bytes of header and
/// count, then 50 bytes a facet. A file that starts with `solid` and does not fit the count is
/// read as ASCII.
fn check_stl_size(bytes: &[u8]) -> Result<(), String> {
    let Some(count) = bytes.get(80..84) else {
        return if bytes.trim_ascii_start().starts_with(b"solid") {
            Ok(())
        } else {
            Err(format!("not a valid STL file: {} bytes, shorter than a binary STL's header", bytes.len()))
        };
    };
    let facets = u64::from(u32::from_le_bytes([count[0], count[1], count[2], count[3]]));
    let expected = 84 + 50 * facets;
    if bytes.len() as u64 == expected || bytes.trim_ascii_start().starts_with(b"solid") {
        return Ok(());
    }
    Err(format!(
        "binary STL whose header counts {facets} facets ({expected} bytes) but the file has {} bytes",
        bytes.len()
    ))
}
