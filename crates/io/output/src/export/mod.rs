//! 3D files of a deposit: PLY ([`ply`]), glTF 2.0 binary (`.glb`, [`glb`]) and legacy VTK
//! polydata ([`vtk`]), from a deposit surface's triangle mesh (the layer's top, each vertex
//! raised by its thickness), and a PLY point cloud of the particles in flight
//! ([`ply_points`]).
//!
//! Every format carries the thickness per vertex (the area-weighted mean of the cells around
//! it) and per triangle (its cell's, or its block's mean when a grid is averaged down), in
//! metres; colours follow the heatmaps' scale from 0 to the thickest cell. This module builds
//! that shared geometry ([`Deposit`]); each format's file writes it.

mod gltf;
mod ply;
mod vtk;

pub use gltf::glb;
pub use ply::{ply, ply_points};
pub use vtk::vtk;

use crate::heatmap::color;
use glam::DVec3;
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

/// `v` in single precision, as every format stores coordinates.
fn f32s(v: DVec3) -> [f32; 3] {
    v.to_array().map(|x| x as f32)
}
