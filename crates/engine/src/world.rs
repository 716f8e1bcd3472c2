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
    /// Particles stuck on the front (all in the deposit).
    pub stuck: Amount,
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
    /// Erosion maps, when an erosion law applies to this target.
    pub erosion: Option<ErosionMaps>,
}

/// Per-cell erosion of a target.
#[derive(Clone, Debug, PartialEq)]
pub struct ErosionMaps {
    /// Depth eroded by impacts, m.
    pub eroded: Vec<f64>,
    /// Coating left, m.
    pub coating: Vec<f64>,
    /// Coating thickness at the start, m.
    pub initial_coating: f64,
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
