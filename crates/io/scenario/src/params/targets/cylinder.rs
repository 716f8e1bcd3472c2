//! `shape = "cylinder"`: a cylindrical shell with a heightfield on its unrolled surface (a
//! tunnel lining, a shaft, a pipe, a tank).

use super::{Edges, RasterChart, SplatRadius, TargetGeometry, heightfield_storage, resolution, splat_radius};
use crate::budget::Storage;
use crate::params::v3;
use crate::reader::{Check, Read, Section, bad, choices, not_parallel};
use crate::sanity::EnclosingBox;
use glam::DVec3;
use serde::Serialize;
use spraysim_engine::collision::CylinderShell;
use spraysim_engine::deposit::{CylinderSurface, ShellChart, Surface};
use std::path::Path;

/// A cylindrical shell with a heightfield on its unrolled surface.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CylinderTarget {
    /// Centre of the axis segment, m.
    pub center: [f64; 3],
    /// Direction of the axis.
    pub axis: [f64; 3],
    /// Radius, m.
    pub radius: f64,
    /// Length along the axis, m.
    pub length: f64,
    /// `[start, end]` about the axis, degrees, from `reference` towards `reference × axis`.
    pub angles: [f64; 2],
    /// Direction of angle 0 (made perpendicular to the axis).
    pub reference: [f64; 3],
    /// `"inside"` (a lining) or `"outside"` (a tank) receives the spray.
    pub side: ShellSide,
    /// Heightfield cells `[around, along]`.
    pub resolution: [u32; 2],
    /// Radius over which each stuck particle's volume is spread, m (0: one cell), as the file
    /// gives it or derived from the particles expected per cell.
    pub splat_radius: SplatRadius,
    /// What the shell's edges do to a slumping layer.
    pub edges: Edges,
}

/// Which side of a cylindrical shell receives spray.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ShellSide {
    /// The inside: a tunnel lining, a shaft.
    #[default]
    Inside,
    /// The outside: a tank, a pipe.
    Outside,
}

choices!(ShellSide { "inside" => ShellSide::Inside, "outside" => ShellSide::Outside });

impl TargetGeometry for CylinderTarget {
    fn read(s: &Section<'_>, _base: &Path) -> Read<Self> {
        let center = s.point("center", None)?;
        let axis = s.direction("axis", None)?;
        let radius = s.number("radius", None, Check::Positive(1e3), "m")?;
        let length = s.number("length", None, Check::Positive(1e4), "m")?;
        let angles = s.numbers("angles", Some([0.0, 360.0]), Check::Within(-720.0, 720.0), "degrees")?;
        if angles[1] <= angles[0] || angles[1] - angles[0] > 360.0 {
            let message = format!("must be [start, end] with start < end ≤ start + 360, got {angles:?}");
            return bad(&s.key("angles"), message);
        }
        // Angle 0 horizontal across the axis by default, so that 90° is straight up.
        let a = v3(axis).normalize();
        let default =
            if a.cross(DVec3::Z).length() > 1e-6 { a.cross(DVec3::Z).normalize() } else { DVec3::X };
        let reference = s.direction("reference", Some(default.to_array()))?;
        not_parallel(&s.key("reference"), reference, axis, "axis")?;
        let side = s.choice("side", Some(ShellSide::Inside))?;
        let resolution = resolution(s, [1024.0, 512.0])?;
        let size = [radius * (angles[1] - angles[0]).to_radians(), length];
        let splat_radius = splat_radius(s, size, resolution)?;
        let edges = s.choice("edges", Some(Edges::Free))?;
        Ok(CylinderTarget {
            center,
            axis,
            radius,
            length,
            angles,
            reference,
            side,
            resolution,
            splat_radius,
            edges,
        })
    }

    /// The arc length and the length, m.
    fn size(&self) -> [f64; 2] {
        [self.radius * (self.angles[1] - self.angles[0]).to_radians(), self.length]
    }

    fn surface(&self) -> Surface {
        let [cols, rows] = self.resolution.map(|r| r as usize);
        // Reading checked the shell: its chart exists.
        let chart = self.chart().unwrap_or_else(|| unreachable!("checked when read"));
        let shell = CylinderSurface::new(chart, cols, rows, self.splat_radius.radius);
        Surface::Cylinder(shell.with_held_edges(self.edges == Edges::Held))
    }

    fn raster_chart(&self) -> Option<RasterChart> {
        self.chart().map(RasterChart::Shell)
    }

    fn reach(&self) -> (Vec<[f64; 3]>, f64) {
        (vec![self.center], self.radius.hypot(self.length / 2.0))
    }

    /// The box around the whole cylinder, whatever its angles.
    fn enclosing_box(&self) -> EnclosingBox {
        let axis = v3(self.axis).normalize();
        let (across, third) = axis.any_orthonormal_pair();
        EnclosingBox {
            center: v3(self.center),
            axes: [axis, across, third],
            half: [self.length / 2.0, self.radius, self.radius],
        }
    }

    fn splat_radius(&self) -> f64 {
        self.splat_radius.radius
    }

    fn cells(&self) -> u64 {
        u64::from(self.resolution[0]) * u64::from(self.resolution[1])
    }

    fn storage(&self) -> Storage {
        heightfield_storage(self.resolution)
    }

    /// Held at all: some of a shell always faces sideways or down.
    fn piles_at_held_foot(&self, _gravity: DVec3) -> bool {
        self.edges == Edges::Held
    }
}

impl CylinderTarget {
    /// The unrolled chart of the shell (`None` for a degenerate one, which reading refuses).
    fn chart(&self) -> Option<ShellChart> {
        let angles = self.angles.map(f64::to_radians);
        let (center, axis, reference) = (v3(self.center), v3(self.axis), v3(self.reference));
        let shell = CylinderShell::new(center, axis, reference, self.radius, self.length, angles)?;
        Some(ShellChart { shell, inside: self.side == ShellSide::Inside })
    }
}
