//! 3D exports of deposits read back by small independent readers (written here from the
//! formats' specifications, not with the writers' code): their thickness is the `.npy` map's.

use spraysim::Scenario;
use std::path::Path;

/// Little-endian f32 `.npy` (version 1): shape and values.
fn read_npy_f32(path: &Path) -> (Vec<usize>, Vec<f32>) {
    let b = std::fs::read(path).expect("npy");
    assert_eq!(&b[..6], b"\x93NUMPY");
    let len = u16::from_le_bytes([b[8], b[9]]) as usize;
    let header = std::str::from_utf8(&b[10..10 + len]).expect("ascii header");
    assert!(header.contains("'<f4'") && header.contains("'fortran_order': False"), "{header}");
    let shape: Vec<usize> = header
        .split("'shape': (")
        .nth(1)
        .and_then(|r| r.split(')').next())
        .expect("shape")
        .split(',')
        .filter_map(|x| x.trim().parse().ok())
        .collect();
    let data = b[10 + len..].chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    (shape, data)
}

/// The end of the header line by line: returns the header's lines and the offset of the body.
fn header_lines(b: &[u8], last: &str) -> (Vec<String>, usize) {
    let mut lines = Vec::new();
    let mut at = 0;
    loop {
        let end = at + b[at..].iter().position(|&c| c == b'\n').expect("line");
        let line = String::from_utf8_lossy(&b[at..end]).into_owned();
        at = end + 1;
        let done = line.starts_with(last);
        lines.push(line);
        if done {
            return (lines, at);
        }
    }
}

struct Ply {
    vertices: usize,
    face_thickness: Vec<f32>,
    vertex_thickness: Vec<f32>,
}

/// A binary little-endian PLY with the vertex layout x y z nx ny nz thickness (f32) and red green
/// blue (u8), and faces `list uchar uint` then thickness (f32) and hits (u32).
fn read_ply(path: &Path) -> Ply {
    let b = std::fs::read(path).expect("ply");
    let (lines, mut at) = header_lines(&b, "end_header");
    assert!(lines.iter().any(|l| l == "format binary_little_endian 1.0"));
    let count = |what: &str| -> usize {
        lines
            .iter()
            .find_map(|l| l.strip_prefix(&format!("element {what} ")))
            .and_then(|n| n.parse().ok())
            .expect("count")
    };
    let (nv, nf) = (count("vertex"), count("face"));
    let f32_at = |b: &[u8], i: usize| f32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    let mut vertex_thickness = Vec::new();
    for _ in 0..nv {
        vertex_thickness.push(f32_at(&b, at + 24));
        at += 7 * 4 + 3;
    }
    let mut face_thickness = Vec::new();
    for _ in 0..nf {
        assert_eq!(b[at], 3, "triangles");
        face_thickness.push(f32_at(&b, at + 13));
        at += 1 + 12 + 4 + 4;
    }
    assert_eq!(at, b.len(), "nothing after the faces");
    Ply { vertices: nv, face_thickness, vertex_thickness }
}

/// The `thickness` cell data of a legacy binary VTK polydata (big-endian floats).
fn read_vtk_cell_thickness(path: &Path) -> Vec<f32> {
    let b = std::fs::read(path).expect("vtk");
    let text_until = |from: usize, key: &[u8]| {
        from + b[from..].windows(key.len()).position(|w| w == key).expect("section")
    };
    let cells = text_until(0, b"CELL_DATA ");
    let line_end = |i: usize| i + b[i..].iter().position(|&c| c == b'\n').expect("line");
    let n: usize =
        std::str::from_utf8(&b[cells + 10..line_end(cells)]).expect("ascii").trim().parse().expect("count");
    let scalars = text_until(cells, b"SCALARS thickness float 1\nLOOKUP_TABLE default\n");
    let start = line_end(line_end(scalars) + 1) + 1;
    b[start..start + 4 * n].chunks_exact(4).map(|c| f32::from_be_bytes([c[0], c[1], c[2], c[3]])).collect()
}

/// The `_THICKNESS` attribute of the first primitive of a binary glTF.
fn read_glb_thickness(path: &Path) -> Vec<f32> {
    let b = std::fs::read(path).expect("glb");
    let u32_at = |i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]) as usize;
    assert_eq!(&b[..4], b"glTF");
    assert_eq!(u32_at(8), b.len(), "the header's length is the file's");
    let json_len = u32_at(12);
    assert_eq!(&b[16..20], b"JSON");
    let json: serde_json::Value = serde_json::from_slice(&b[20..20 + json_len]).expect("json");
    let bin_at = 20 + json_len;
    assert_eq!(&b[bin_at + 4..bin_at + 8], b"BIN\0");
    let bin = &b[bin_at + 8..bin_at + 8 + u32_at(bin_at)];
    let accessor =
        json["meshes"][0]["primitives"][0]["attributes"]["_THICKNESS"].as_u64().expect("attribute") as usize;
    let acc = &json["accessors"][accessor];
    assert_eq!(acc["componentType"], 5126, "float");
    let view = &json["bufferViews"][acc["bufferView"].as_u64().expect("view") as usize];
    let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
    let count = acc["count"].as_u64().expect("count") as usize;
    bin[offset..offset + 4 * count]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

#[test]
fn exported_meshes_carry_the_thickness_of_the_maps() {
    let text = r#"
        [simulation]
        duration = 0.3
        [process]
        preset = "painting"
        [nozzle]
        position = [0.0, 0.0, 0.3]
        axis = [0.0, 0.0, -1.0]
        [[target]]
        name = "panel"
        center = [0.0, 0.0, 0.0]
        normal = [0.0, 0.0, 1.0]
        up = [0.0, 1.0, 0.0]
        size = [0.8, 0.6]
        resolution = [40, 30]
        [output]
        export = ["ply", "glb", "vtk"]
        "#;
    let sc = Scenario::from_toml(text, "export").unwrap_or_else(|e| panic!("{e}"));
    let mut sim = sc.build().expect("valid");
    sim.run(|_| {});
    let tmp = tempfile::tempdir().expect("tempdir");
    spraysim::output::write_outputs(&sim, &sc, tmp.path()).expect("written");
    let (shape, map) = read_npy_f32(&tmp.path().join("panel_thickness.npy"));
    assert_eq!(shape, [30, 40]);
    assert!(map.iter().any(|&t| t > 0.0));
    // Two triangles a cell, row-major from the bottom row: each carries its cell's thickness.
    let ply = read_ply(&tmp.path().join("panel.ply"));
    assert_eq!((ply.vertices, ply.face_thickness.len()), (41 * 31, 2 * 1200));
    let vtk = read_vtk_cell_thickness(&tmp.path().join("panel.vtk"));
    for (k, &t) in map.iter().enumerate() {
        assert_eq!(ply.face_thickness[2 * k], t, "PLY face of cell {k}");
        assert_eq!(ply.face_thickness[2 * k + 1], t, "PLY face of cell {k}");
        assert_eq!(vtk[2 * k], t, "VTK cell data of cell {k}");
    }
    // Vertices carry the mean of the cells around them, in PLY and glTF alike.
    let glb = read_glb_thickness(&tmp.path().join("panel.glb"));
    assert_eq!(glb.len(), 41 * 31);
    for vr in 0..=30usize {
        for vc in 0..=40usize {
            let around: Vec<f64> = [
                (vr.wrapping_sub(1), vc.wrapping_sub(1)),
                (vr.wrapping_sub(1), vc),
                (vr, vc.wrapping_sub(1)),
                (vr, vc),
            ]
            .iter()
            .filter(|&&(r, c)| r < 30 && c < 40)
            .map(|&(r, c)| f64::from(map[r * 40 + c]))
            .collect();
            let mean = around.iter().sum::<f64>() / around.len() as f64;
            let v = vr * 41 + vc;
            for (format, got) in [("glb", glb[v]), ("ply", ply.vertex_thickness[v])] {
                assert!(
                    (f64::from(got) - mean).abs() <= 1e-6 * mean.max(1e-9),
                    "{format} vertex {v}: {got} vs {mean}"
                );
            }
        }
    }
}
