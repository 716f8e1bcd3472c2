//! Legacy VTK: a deposit's mesh as binary polydata.

use super::{Deposit, f32s};

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
