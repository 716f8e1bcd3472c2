//! Targets (faces with a heightfield) and obstacles, with what has happened on them.

use crate::collision::Face;
use crate::heightfield::HeightField;
use crate::scenario::Role;
use serde::Serialize;

/// A number of particles and the material volume they carry.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Amount {
    /// Particles.
    pub count: u64,
    /// Volume, m³.
    pub volume: f64,
}

impl Amount {
    /// Adds one particle of `volume` (m³).
    #[inline]
    pub fn add(&mut self, volume: f64) {
        self.count += 1;
        self.volume += volume;
    }
}

impl std::ops::Add for Amount {
    type Output = Amount;
    fn add(self, o: Amount) -> Amount {
        Amount { count: self.count + o.count, volume: self.volume + o.volume }
    }
}

impl std::iter::Sum for Amount {
    fn sum<I: Iterator<Item = Amount>>(iter: I) -> Amount {
        iter.fold(Amount::default(), |a, b| a + b)
    }
}

/// A target face and the layer it has received.
#[derive(Clone, Debug)]
pub struct Target {
    /// Name, as in the scenario.
    pub name: String,
    /// Substrate or collector.
    pub role: Role,
    /// Geometry.
    pub face: Face,
    /// Deposited thickness and impact counts over the face's front.
    pub field: HeightField,
    /// Impacts on either side.
    pub hits: u64,
    /// Particles stuck on the front (all in `field`).
    pub stuck: Amount,
    /// Particles stuck on the back, which has no heightfield.
    pub stuck_back: Amount,
    /// Material released by cohesive failures that landed here (front or back).
    pub received: Amount,
    /// Of that, the volume on the back, m³.
    pub received_back: f64,
    /// Material that failed and fell off: released particles and their volume.
    pub detached: Amount,
    /// Per cell: 0 sound, 1 over-loaded at the last analysis, 2 failed at some time.
    pub failure_mask: Vec<u8>,
    /// Per cell: depth eroded by impacts, m (empty when erosion is off).
    pub erosion: Vec<f64>,
    /// Per cell: coating left, m (empty when erosion is off).
    pub coating: Vec<f64>,
    /// Coating thickness at the start, m.
    pub initial_coating: f64,
}

impl Target {
    /// Per cell, 1 where a wet film risks sagging: its thickness times the sine of the face's
    /// tilt from horizontal exceeds `threshold` (m). A horizontal face never sags.
    pub fn sag_risk(&self, threshold: f64) -> Vec<u8> {
        let limit = self.sag_limit(threshold).unwrap_or(f64::INFINITY);
        self.field.thickness().iter().map(|&t| u8::from(t > limit)).collect()
    }

    /// Film thickness (m) beyond which a film sags on this face, `threshold / sin β` with β the
    /// face's tilt from horizontal; `None` when sagging is off or the face is horizontal.
    pub fn sag_limit(&self, threshold: f64) -> Option<f64> {
        let tilt_sin = (1.0 - self.face.normal.z * self.face.normal.z).max(0.0).sqrt();
        (threshold > 0.0 && tilt_sin >= 1e-9).then(|| threshold / tilt_sin)
    }
}

/// An obstacle and what has struck it.
#[derive(Clone, Debug)]
pub struct Obstacle {
    /// Name, as in the scenario.
    pub name: String,
    /// Impacts.
    pub hits: u64,
    /// Particles stuck on it.
    pub stuck: Amount,
    /// Released material that landed on it.
    pub received: Amount,
}
