//! `[[target]]`: the surfaces that record deposition, tagged by `shape`.
//!
//! Each shape is a file here declaring its keys (units and defaults in its reader), how it is
//! written back (its `Serialize`), the engine's deposit surface it builds and what a scenario
//! derives from it; the list in [`TargetShape`] names each once. A new shape is its file, its
//! `mod` line and its line in that list (and, for a new kind of deposit, a surface in the
//! engine's `deposit`).

mod cylinder;
mod mesh;
mod rectangle;
mod splat;

pub use cylinder::{CylinderTarget, ShellSide};
pub use mesh::{MeshSide, MeshTarget, mean_plane};
pub use rectangle::{OpeningParams, RectangleTarget, opening};
pub(crate) use splat::smallest_radius;
pub use splat::{MAX_SPLAT_CELLS, PARTICLES_PER_SPLAT, SplatRadius};

use super::process::ImpactParams;
use super::registry::kinds;
use super::surface::{impact_override, name};
use crate::budget::{PER_CELL, Storage};
use crate::reader::{Check, Choice, Read, Section, bad, choices};
use crate::sanity::EnclosingBox;
use crate::scenario::Scenario;
use glam::DVec3;
use serde::Serialize;
use spraysim_engine::collision::Face;
use spraysim_engine::deposit::{ShellChart, Surface};
use spraysim_engine::world::Role;
use std::path::Path;

choices!(Role { "substrate" => Role::Substrate, "collector" => Role::Collector });

/// What each target shape declares besides its keys: the engine's deposit surface it builds,
/// and what a scenario derives from it.
pub(crate) trait TargetGeometry {
    /// Reads the shape's keys from `s`; a file it names is read relative to `base`.
    fn read(s: &Section<'_>, base: &Path) -> Read<Self>
    where
        Self: Sized;

    /// `[width, height]` of the target's unrolled surface, m.
    fn size(&self) -> [f64; 2];

    /// The engine's deposit surface.
    fn surface(&self) -> Surface;

    /// The surface a raster over the target covers (`None` for a shape that has none).
    fn raster_chart(&self) -> Option<RasterChart>;

    /// Points, m, and how far around each of them the target reaches, m: the default domain
    /// holds them all.
    fn reach(&self) -> (Vec<[f64; 3]>, f64);

    /// Cells of its deposit: a heightfield's cells, a mesh's triangles.
    fn cells(&self) -> u64;

    /// An oriented box that holds the whole target, m: what the sanity checks aim the spray
    /// cone at.
    fn enclosing_box(&self) -> EnclosingBox;

    /// Area of the surface, m².
    fn area(&self) -> f64 {
        let [width, height] = self.size();
        width * height
    }

    /// Radius over which each particle's deposit spreads, m (0: the cell it lands in only).
    fn splat_radius(&self) -> f64 {
        0.0
    }

    /// The memory its deposit takes in a run, for the budget.
    fn storage(&self) -> Storage;

    /// True if the target holds its edges and is steeper than 45° under `gravity` (a unit
    /// vector, or zero), so that what slumps down it piles up at its foot without limit.
    fn piles_at_held_foot(&self, gravity: DVec3) -> bool {
        let _ = gravity;
        false
    }

    /// What the target named `name` does in `sc` that a user may not intend, one sentence each.
    fn warnings(&self, name: &str, sc: &Scenario) -> Vec<String> {
        let _ = (name, sc);
        Vec::new()
    }
}

kinds! {
    /// The geometry of a target.
    pub enum TargetShape, tagged "shape", kinds TargetKind, read with &Path, as dyn TargetGeometry {
        /// A rectangle with a regular heightfield, optionally with openings.
        "rectangle" => Rectangle(RectangleTarget),
        /// A cylindrical shell with a heightfield on its unrolled surface: a tunnel lining, a
        /// shaft, a pipe, a tank.
        "cylinder" => Cylinder(CylinderTarget),
        /// A triangle mesh from a file, with a thickness per triangle.
        "mesh" => Mesh(MeshTarget),
    }
}

/// The surface a raster over a target covers: a face (a rectangle, or the plane a mesh mostly
/// faces), or a shell's unrolled chart.
pub(crate) enum RasterChart {
    /// A flat face.
    Face(Face),
    /// A cylindrical shell, unrolled.
    Shell(ShellChart),
}

/// One `[[target]]`: a surface that records deposition.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TargetParams {
    /// Name, used for output files (letters, digits, `-` and `_`).
    pub name: String,
    /// `"substrate"` or `"collector"`.
    pub role: Role,
    /// Geometry and deposit grid: `shape` and its keys.
    #[serde(flatten)]
    pub shape: TargetShape,
    /// Thickness of a coating on the surface at the start, which erosion removes, m.
    pub coating: f64,
    /// The specified thickness band `[min, max]`, m: the metrics report the share of the area
    /// within it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<[f64; 2]>,
    /// Cells closer than this to the surface's edges or openings are left out of the thickness
    /// statistics, m.
    pub margin: f64,
    /// Impact parameters of this target, where they differ from the process's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub impact: Option<ImpactParams>,
}

impl TargetParams {
    /// `[width, height]` of the target's unrolled surface, m: a rectangle's size, a shell's arc
    /// length and length, a mesh's extent on its mean plane (see [`mean_plane`]).
    pub fn size(&self) -> [f64; 2] {
        self.shape.as_dyn().size()
    }
}

impl TargetShape {
    /// The engine's deposit surface of this target.
    pub fn surface(&self) -> Surface {
        self.as_dyn().surface()
    }

    /// Cells of this target's deposit: a heightfield's cells, a mesh's triangles.
    pub fn cells(&self) -> u64 {
        self.as_dyn().cells()
    }
}

/// What a target's edges do to a slumping layer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Edges {
    /// The layer runs off over them.
    #[default]
    Free,
    /// Formwork, or a floor under a wall, holds it.
    Held,
}

choices!(Edges { "free" => Edges::Free, "held" => Edges::Held });

/// Reads a `[[target]]` (its `name` added to `seen`); a mesh is read from `base`.
pub(crate) fn read_target(
    s: &Section<'_>,
    seen: &mut Vec<String>,
    process: &ImpactParams,
    base: &Path,
) -> Read<TargetParams> {
    let name = name(s, seen)?;
    let role = s.choice("role", Some(Role::Substrate))?;
    let kind = s.choice("shape", Some(TargetKind::Rectangle))?;
    let shape = TargetShape::read(kind, s, base)?;
    let coating = s.number("coating", Some(0.0), Check::Within(0.0, 1.0), "m")?;
    let tolerance = if s.has("tolerance") {
        let band = s.numbers("tolerance", None, Check::Within(0.0, 100.0), "m")?;
        if band[0] > band[1] {
            return bad(&s.key("tolerance"), format!("must be [min, max] with min ≤ max, got {band:?}"));
        }
        Some(band)
    } else {
        None
    };
    let margin = s.number("margin", Some(0.0), Check::Within(0.0, 1e3), "m")?;
    let impact = impact_override(s, process)?;
    s.finish(&format!("a {} target", kind.name()))?;
    Ok(TargetParams { name, role, shape, coating, tolerance, margin, impact })
}

/// Heightfield cells `[cols, rows]`, whole numbers in 1–4096 (`default` when absent).
fn resolution(s: &Section<'_>, default: [f64; 2]) -> Read<[u32; 2]> {
    let [cols, rows] =
        s.numbers("resolution", Some(default), Check::Within(1.0, 4096.0), "cells per side")?;
    if cols.fract() != 0.0 || rows.fract() != 0.0 {
        return bad(&s.key("resolution"), format!("must be whole numbers of cells, got [{cols}, {rows}]"));
    }
    Ok([cols as u32, rows as u32])
}

/// The memory of a heightfield of `resolution` cells, for the budget.
fn heightfield_storage(resolution: [u32; 2]) -> Storage {
    let cells = f64::from(resolution[0]) * f64::from(resolution[1]);
    Storage { key: "resolution", what: format!("{cells} cells"), bytes: cells * PER_CELL }
}

/// The splat radius for a grid of `size` (m) and `resolution`: the file's, m, at most half the
/// smaller side and [`MAX_SPLAT_CELLS`] cells; without one, to be derived once the whole
/// scenario is read (see [`SplatRadius`]).
fn splat_radius(s: &Section<'_>, size: [f64; 2], resolution: [u32; 2]) -> Read<SplatRadius> {
    if !s.has("splat_radius") {
        return Ok(SplatRadius::to_derive());
    }
    let r = s.number("splat_radius", None, Check::Within(0.0, size[0].min(size[1]) / 2.0), "m")?;
    let cells = r / (size[0] / f64::from(resolution[0])).min(size[1] / f64::from(resolution[1]));
    if cells > MAX_SPLAT_CELLS {
        return bad(&s.key("splat_radius"), "spans more than 32 cells; lower it or the resolution");
    }
    Ok(SplatRadius::given(r))
}

impl TargetShape {
    /// The splat radius of a heightfield target (`None` for a mesh, which deposits per
    /// triangle).
    pub fn splat_radius(&self) -> Option<SplatRadius> {
        match self {
            TargetShape::Rectangle(r) => Some(r.splat_radius),
            TargetShape::Cylinder(c) => Some(c.splat_radius),
            TargetShape::Mesh(_) => None,
        }
    }

    /// The splat radius of a heightfield target, to set a derived one.
    pub(crate) fn splat_radius_mut(&mut self) -> Option<&mut SplatRadius> {
        match self {
            TargetShape::Rectangle(r) => Some(&mut r.splat_radius),
            TargetShape::Cylinder(c) => Some(&mut c.splat_radius),
            TargetShape::Mesh(_) => None,
        }
    }

    /// Heightfield cells `[cols, rows]` of a heightfield target (`None` for a mesh).
    pub fn resolution(&self) -> Option<[u32; 2]> {
        match self {
            TargetShape::Rectangle(r) => Some(r.resolution),
            TargetShape::Cylinder(c) => Some(c.resolution),
            TargetShape::Mesh(_) => None,
        }
    }
}
