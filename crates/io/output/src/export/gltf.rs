//! glTF 2.0 binary (`.glb`): a deposit's mesh with vertex colours and thickness.

use super::{Deposit, f32s};
use glam::DVec3;
use gltf_json as gj;

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
