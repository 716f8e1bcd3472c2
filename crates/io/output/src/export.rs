//! 3D files of a deposit: PLY, glTF 2.0 binary (`.glb`) and legacy VTK polydata, from a
//! deposit surface's triangle mesh (the layer's top, each vertex raised by its thickness), and
//! a PLY point cloud of the particles in flight.
//!
//! Every format carries the thickness per vertex (the area-weighted mean of the cells around
//! it) and per triangle (its cell's, or its block's mean when a grid is averaged down), in
//! metres; colours follow the heatmaps' scale from 0 to the thickest cell.

use crate::heatmap::color;
use glam::DVec3;
use gltf_json as gj;
use spraysim_engine::deposit::{DepositSurface, Layout, SurfaceMesh};
use spraysim_engine::world::Target;
use spraysim_scenario::Colormap;

/// A target's deposit as a mesh with everything the formats write.
pub struct Deposit {
    /// The mesh, raised by the layer.
    pub mesh: SurfaceMesh,
    /// Per triangle: the thickness of its cell (or block), m.
    pub face_thickness: Vec<f64>,
    /// Per triangle: impacts on its cell (or block, summed).
    pub face_hits: Vec<u32>,
    /// Per triangle: depth eroded (coating and substrate), m, with an erosion model.
    pub face_erosion: Option<Vec<f64>>,
    /// Per vertex: colour on the heatmaps' scale.
    pub colors: Vec<[u8; 3]>,
}

impl Deposit {
    /// The deposit of `t`, a grid averaged down to at most about `max_cells` cells.
    pub fn of(t: &Target, max_cells: usize, map: Colormap) -> Deposit {
        let s = &t.surface;
        let mesh = s.mesh(true, max_cells);
        let layout = s.layout();
        let block = |cell: u32| block_cells(&layout, &mesh, cell);
        let (thickness, areas) = (s.thickness(), |c: u32| s.cell_area(c));
        let mean = |cells: &[u32], values: &dyn Fn(u32) -> f64| match cells {
            [one] => values(*one),
            _ => {
                let (sum, area) =
                    cells.iter().fold((0.0, 0.0), |(v, a), &c| (v + values(c) * areas(c), a + areas(c)));
                if area > 0.0 { sum / area } else { 0.0 }
            }
        };
        let blocks: Vec<Vec<u32>> = mesh.cell.iter().map(|&c| block(c)).collect();
        let face_thickness = blocks.iter().map(|b| mean(b, &|c| thickness[c as usize])).collect();
        let face_hits = blocks.iter().map(|b| b.iter().map(|&c| s.hits()[c as usize]).sum()).collect();
        let face_erosion =
            t.erosion.as_ref().map(|e| blocks.iter().map(|b| mean(b, &|c| e.eroded(c as usize))).collect());
        let top = thickness.iter().copied().fold(0.0, f64::max);
        let colors =
            mesh.thickness.iter().map(|&v| color(map, if top > 0.0 { v / top } else { 0.0 }).0).collect();
        Deposit { mesh, face_thickness, face_hits, face_erosion, colors }
    }
}

/// The cells a mesh triangle standing for `cell` covers: its block of `k × k` cells on a grid
/// averaged down by `k`, or the cell alone.
fn block_cells(layout: &Layout, mesh: &SurfaceMesh, cell: u32) -> Vec<u32> {
    match *layout {
        Layout::Grid { rows, cols, .. } if mesh.block > 1 => {
            let k = mesh.block;
            let (r0, c0) = (cell as usize / cols, cell as usize % cols);
            (r0..(r0 + k).min(rows))
                .flat_map(|r| (c0..(c0 + k).min(cols)).map(move |c| (r * cols + c) as u32))
                .collect()
        }
        _ => vec![cell],
    }
}

fn f32s(v: DVec3) -> [f32; 3] {
    v.to_array().map(|x| x as f32)
}

/// Binary little-endian PLY: vertices with position (m), normal, thickness (m) and colour;
/// faces with their thickness (m) and impacts.
pub fn ply(d: &Deposit, name: &str) -> Vec<u8> {
    let m = &d.mesh;
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment spraysim deposit of {name}; lengths in m\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         property float nx\nproperty float ny\nproperty float nz\nproperty float thickness\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\n\
         element face {}\nproperty list uchar uint vertex_indices\nproperty float thickness\n\
         property uint hits\nend_header\n",
        m.positions.len(),
        m.triangles.len()
    )
    .into_bytes();
    for (i, p) in m.positions.iter().enumerate() {
        for x in f32s(*p).into_iter().chain(f32s(m.normals[i])).chain([m.thickness[i] as f32]) {
            out.extend(x.to_le_bytes());
        }
        out.extend(d.colors[i]);
    }
    for (k, t) in m.triangles.iter().enumerate() {
        out.push(3);
        t.iter().for_each(|i| out.extend(i.to_le_bytes()));
        out.extend((d.face_thickness[k] as f32).to_le_bytes());
        out.extend(d.face_hits[k].to_le_bytes());
    }
    out
}

/// A point cloud of `points` (m) with their velocities (m/s), as binary PLY.
pub fn ply_points(points: &[(DVec3, DVec3)]) -> Vec<u8> {
    let mut out = format!(
        "ply\nformat binary_little_endian 1.0\ncomment spraysim particles in flight; m and m/s\n\
         element vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         property float vx\nproperty float vy\nproperty float vz\nend_header\n",
        points.len()
    )
    .into_bytes();
    for (p, v) in points {
        for x in f32s(*p).into_iter().chain(f32s(*v)) {
            out.extend(x.to_le_bytes());
        }
    }
    out
}

/// Legacy VTK polydata (binary, big-endian as the format wants): points, triangles, and the
/// thickness (m), impacts and erosion (m) as cell data, the thickness as point data too.
pub fn vtk(d: &Deposit, name: &str) -> Vec<u8> {
    let m = &d.mesh;
    let (np, nt) = (m.positions.len(), m.triangles.len());
    let mut out = format!("# vtk DataFile Version 3.0\nspraysim deposit of {name} (m)\nBINARY\nDATASET POLYDATA\nPOINTS {np} float\n")
        .into_bytes();
    m.positions.iter().for_each(|p| f32s(*p).iter().for_each(|x| out.extend(x.to_be_bytes())));
    out.extend(format!("\nPOLYGONS {nt} {}\n", 4 * nt).into_bytes());
    for t in &m.triangles {
        out.extend(3i32.to_be_bytes());
        t.iter().for_each(|&i| out.extend((i as i32).to_be_bytes()));
    }
    let scalars = |out: &mut Vec<u8>, label: &str, kind: &str, values: &mut dyn Iterator<Item = [u8; 4]>| {
        out.extend(format!("\nSCALARS {label} {kind} 1\nLOOKUP_TABLE default\n").into_bytes());
        values.for_each(|b| out.extend(b));
    };
    out.extend(format!("\nCELL_DATA {nt}").into_bytes());
    scalars(&mut out, "thickness", "float", &mut d.face_thickness.iter().map(|&x| (x as f32).to_be_bytes()));
    scalars(
        &mut out,
        "hits",
        "int",
        &mut d.face_hits.iter().map(|&x| (x.min(i32::MAX as u32) as i32).to_be_bytes()),
    );
    if let Some(e) = &d.face_erosion {
        scalars(&mut out, "erosion", "float", &mut e.iter().map(|&x| (x as f32).to_be_bytes()));
    }
    out.extend(format!("\nPOINT_DATA {np}").into_bytes());
    scalars(&mut out, "thickness", "float", &mut m.thickness.iter().map(|&x| (x as f32).to_be_bytes()));
    out.push(b'\n');
    out
}

/// The binary chunk of a `.glb`: positions, normals, colours (RGBA u8), thickness and indices,
/// each padded to 4 bytes, with each one's (offset, length) in it.
fn glb_buffer(d: &Deposit) -> (Vec<u8>, [(usize, usize); 5]) {
    let m = &d.mesh;
    let flat = |v: &[DVec3]| v.iter().flat_map(|p| f32s(*p)).flat_map(f32::to_le_bytes).collect::<Vec<u8>>();
    let parts: [Vec<u8>; 5] = [
        flat(&m.positions),
        flat(&m.normals),
        d.colors.iter().flat_map(|c| [c[0], c[1], c[2], 255]).collect(),
        m.thickness.iter().flat_map(|&t| (t as f32).to_le_bytes()).collect(),
        m.triangles.iter().flatten().flat_map(|i| i.to_le_bytes()).collect(),
    ];
    let mut bin = Vec::new();
    let views = parts.map(|bytes| {
        let view = (bin.len(), bytes.len());
        bin.extend(bytes);
        bin.resize(bin.len().next_multiple_of(4), 0);
        view
    });
    (bin, views)
}

/// Adds to `root` an accessor of `count` elements over the bytes `(offset, length)` of buffer 0.
fn glb_accessor(
    root: &mut gj::Root,
    (offset, length): (usize, usize),
    count: usize,
    (ty, comp): (gj::accessor::Type, gj::accessor::ComponentType),
    target: gj::buffer::Target,
    bounds: Option<(DVec3, DVec3)>,
) -> gj::Index<gj::Accessor> {
    use gj::validation::{Checked::Valid, USize64};
    let view = root.push(gj::buffer::View {
        buffer: gj::Index::new(0),
        byte_length: USize64::from(length),
        byte_offset: Some(USize64::from(offset)),
        byte_stride: None,
        name: None,
        target: Some(Valid(target)),
        extensions: None,
        extras: Default::default(),
    });
    root.push(gj::Accessor {
        buffer_view: Some(view),
        byte_offset: None,
        count: USize64::from(count),
        component_type: Valid(gj::accessor::GenericComponentType(comp)),
        extensions: None,
        extras: Default::default(),
        type_: Valid(ty),
        min: bounds.map(|(l, _)| gj::Value::from(f32s(l).to_vec())),
        max: bounds.map(|(_, h)| gj::Value::from(f32s(h).to_vec())),
        name: None,
        // Colours are stored as u8 and read as 0..1.
        normalized: comp == gj::accessor::ComponentType::U8,
        sparse: None,
    })
}

/// glTF 2.0 binary: one mesh with positions (m), normals, vertex colours and the per-vertex
/// thickness as the application attribute `_THICKNESS` (m), double-sided.
pub fn glb(d: &Deposit, name: &str) -> Result<Vec<u8>, String> {
    use gj::accessor::{ComponentType as C, Type as T};
    use gj::buffer::Target::{ArrayBuffer, ElementArrayBuffer};
    use gj::validation::Checked::Valid;
    let m = &d.mesh;
    let n = m.positions.len();
    let (bin, [pos, nor, col, thk, idx]) = glb_buffer(d);
    let mut root = gj::Root::default();
    root.asset.generator = Some("spraysim".into());
    root.push(gj::Buffer {
        byte_length: gj::validation::USize64::from(bin.len()),
        name: None,
        uri: None,
        extensions: None,
        extras: Default::default(),
    });
    let bounds =
        m.positions.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), &p| (l.min(p), h.max(p)));
    let attributes = [
        (
            gj::mesh::Semantic::Positions,
            glb_accessor(&mut root, pos, n, (T::Vec3, C::F32), ArrayBuffer, Some(bounds)),
        ),
        (gj::mesh::Semantic::Normals, glb_accessor(&mut root, nor, n, (T::Vec3, C::F32), ArrayBuffer, None)),
        (gj::mesh::Semantic::Colors(0), glb_accessor(&mut root, col, n, (T::Vec4, C::U8), ArrayBuffer, None)),
        (
            gj::mesh::Semantic::Extras("THICKNESS".into()),
            glb_accessor(&mut root, thk, n, (T::Scalar, C::F32), ArrayBuffer, None),
        ),
    ]
    .into_iter()
    .map(|(s, a)| (Valid(s), a))
    .collect();
    let indices =
        glb_accessor(&mut root, idx, 3 * m.triangles.len(), (T::Scalar, C::U32), ElementArrayBuffer, None);
    let material = root.push(gj::Material {
        double_sided: true,
        name: Some(format!("{name} deposit")),
        ..Default::default()
    });
    let primitive = gj::mesh::Primitive {
        attributes,
        extensions: None,
        extras: Default::default(),
        indices: Some(indices),
        material: Some(material),
        mode: Valid(gj::mesh::Mode::Triangles),
        targets: None,
    };
    let mesh = root.push(gj::Mesh {
        extensions: None,
        extras: Default::default(),
        name: Some(name.into()),
        primitives: vec![primitive],
        weights: None,
    });
    let node = root.push(gj::Node { mesh: Some(mesh), name: Some(name.into()), ..Default::default() });
    let scene =
        root.push(gj::Scene { extensions: None, extras: Default::default(), name: None, nodes: vec![node] });
    root.scene = Some(scene);
    let mut json = root.to_vec().map_err(|e| e.to_string())?;
    json.resize(json.len().next_multiple_of(4), b' ');
    Ok(glb_container(&json, &bin))
}

/// The `.glb` container: its header, then the JSON chunk and the binary chunk, each with its
/// length and type.
fn glb_container(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend(b"glTF");
    out.extend(2u32.to_le_bytes());
    out.extend((total as u32).to_le_bytes());
    out.extend((json.len() as u32).to_le_bytes());
    out.extend(b"JSON");
    out.extend(json);
    out.extend((bin.len() as u32).to_le_bytes());
    out.extend(b"BIN\0");
    out.extend(bin);
    out
}
