//! What has happened on each target and obstacle: the mutable data sets the pipeline works on.

use crate::collision::SurfaceId;
use crate::deposit::{DepositSurface, Surface};
use crate::tally::Amount;

/// Role of a target.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Role {
    /// The surface being sprayed; counts towards transfer efficiency and rebound ratio.
    #[default]
    Substrate,
    /// A surface that catches what rebounds or falls (a floor).
    Collector,
}

/// A target: its deposit surface and what has happened on it.
#[derive(Clone, Debug)]
pub struct Target {
    /// Name.
    pub name: String,
    /// Substrate or collector.
    pub role: Role,
    /// Geometry and deposited layer.
    pub surface: Surface,
    /// The surface's index in the collision scene.
    pub surface_id: SurfaceId,
    /// Impacts on either side.
    pub hits: u64,
    /// Particles stuck on the front (all in the deposit), adhering or loose.
    pub stuck: Amount,
    /// Of those, the rebounds that came to rest loose instead of adhering: material on the
    /// surface but not in place in the layer.
    pub loose: Amount,
    /// Of those, the rebounds that adhered where they landed again: in the layer, but as
    /// trapped rebound (a defect on floors, ACI 506R), not as sprayed material.
    pub trapped: Amount,
    /// Particles whose first impact on a substrate was on this target's front (the material
    /// delivered to it).
    pub delivered: Amount,
    /// Particles stuck on the back, which collects no deposit.
    pub stuck_back: Amount,
    /// Material released by cohesive failures that landed here (front or back).
    pub received: Amount,
    /// Of that, the volume on the back, m³.
    pub received_back: f64,
    /// Material that failed and fell off: released particles and their volume.
    pub detached: Amount,
    /// Per cell: 0 sound, 1 over-loaded at the last analysis, 2 failed at some time.
    pub failure_mask: Vec<u8>,
    /// Whether the last analysis left cells over-loaded but holding (1 in `failure_mask`).
    pub at_risk: bool,
    /// Erosion maps, when an erosion law applies to this target.
    pub erosion: Option<ErosionMaps>,
}

/// Per-cell erosion of a target.
#[derive(Clone, Debug, PartialEq)]
pub struct ErosionMaps {
    /// Coating left, m.
    pub coating: Vec<f64>,
    /// Depth worn off the substrate under the coating, m.
    pub substrate: Vec<f64>,
    /// Coating thickness at the start, m.
    pub initial_coating: f64,
}

impl ErosionMaps {
    /// Depth removed at cell `c`, coating and substrate together, m.
    pub fn eroded(&self, c: usize) -> f64 {
        (self.initial_coating - self.coating[c]) + self.substrate[c]
    }

    /// Wears cell `c` (of `area` m²) by one impact that would remove `coat` m³ of coating or
    /// `sub` m³ of substrate: the coating first, and the substrate with the share of the impact
    /// the coating left did not absorb.
    pub fn wear(&mut self, c: usize, area: f64, coat: f64, sub: f64) {
        let (left, depth) = (self.coating[c], coat / area);
        if left >= depth {
            self.coating[c] = left - depth;
            return;
        }
        // The coating absorbs the fraction left / depth of the impact; the rest reaches steel.
        let spent = if depth > 0.0 { left / depth } else { 0.0 };
        self.coating[c] = 0.0;
        self.substrate[c] += (1.0 - spent) * sub / area;
    }
}

impl Target {
    /// Per cell, 1 where a wet film risks sagging: its thickness times the sine of the surface's
    /// tilt from horizontal exceeds `threshold` (m). A horizontal surface never sags.
    pub fn sag_risk(&self, threshold: f64) -> Vec<u8> {
        let t = self.surface.thickness();
        (0..t.len() as u32)
            .map(|c| u8::from(t[c as usize] > self.sag_limit(c, threshold).unwrap_or(f64::INFINITY)))
            .collect()
    }

    /// Film thickness (m) beyond which a film sags at `cell`, `threshold / sin β` with β the
    /// surface's tilt from horizontal there; `None` when sagging is off or the surface is
    /// horizontal.
    pub fn sag_limit(&self, cell: u32, threshold: f64) -> Option<f64> {
        let n = self.surface.normal(cell);
        let tilt_sin = (1.0 - n.z * n.z).max(0.0).sqrt();
        (threshold > 0.0 && tilt_sin >= 1e-9).then(|| threshold / tilt_sin)
    }
}

/// An obstacle and what has struck it.
#[derive(Clone, Debug, Default)]
pub struct Obstacle {
    /// Name.
    pub name: String,
    /// Impacts.
    pub hits: u64,
    /// Particles stuck on it.
    pub stuck: Amount,
    /// Released material that landed on it.
    pub received: Amount,
}
