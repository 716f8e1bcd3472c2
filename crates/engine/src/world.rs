//! What has happened on each target and obstacle: the mutable data sets the pipeline works on.

use crate::collision::SurfaceId;
use crate::deposit::{DepositSurface, Pending, Surface, WEAR_QUANTUM};
use crate::tally::{Quanta, Tallied};

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
    /// Name the scenario gives it (unique among targets and obstacles), for outputs.
    pub name: String,
    /// Substrate (sprayed) or collector (catches what rebounds or falls).
    pub role: Role,
    /// Geometry and deposited layer.
    pub surface: Surface,
    /// The index in the collision scene of the surface's first piece; its pieces follow in
    /// order.
    pub surface_id: SurfaceId,
    /// How many pieces the surface has in the scene.
    pub pieces: u32,
    /// What has struck it, in quanta.
    pub tally: TargetTally,
    /// Per cell: 0 sound, 1 over-loaded at the last analysis, 2 failed at some time.
    pub failure_mask: Vec<u8>,
    /// Whether the last analysis left cells over-loaded but holding (1 in `failure_mask`).
    pub at_risk: bool,
    /// Erosion maps, when an erosion law applies to this target.
    pub erosion: Option<ErosionMaps>,
    /// What the particles of the epoch under way have left on it, to take effect at the
    /// epoch's end (see [`crate::deposit::Pending`]).
    pub pending: Pending,
}

/// What has struck a target, in quanta of the run's volume quantum (see [`Tallied`]):
/// gathered by any number of threads and added up exactly.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TargetTally {
    /// Impacts on either side, stuck or rebounded.
    pub hits: u64,
    /// Particles stuck on the front (all in the deposit), adhering or loose.
    pub stuck: Tallied,
    /// Of those, the rebounds that came to rest loose instead of adhering: material on the
    /// surface but not in place in the layer.
    pub loose: Tallied,
    /// Of those, the rebounds that adhered where they landed again: in the layer, but as
    /// trapped rebound (a defect on floors, ACI 506R), not as sprayed material.
    pub trapped: Tallied,
    /// Particles whose first impact on a substrate was on this target's front (the material
    /// delivered to it).
    pub delivered: Tallied,
    /// Particles stuck on the back, which collects no deposit.
    pub stuck_back: Tallied,
    /// Material released by cohesive failures that landed here (front or back).
    pub received: Tallied,
    /// Of that, the volume on the back, quanta.
    pub received_back: Quanta,
    /// Material that failed and fell off: released particles and their volume.
    pub detached: Tallied,
}

impl std::ops::AddAssign for TargetTally {
    fn add_assign(&mut self, o: TargetTally) {
        self.hits += o.hits;
        self.stuck += o.stuck;
        self.loose += o.loose;
        self.trapped += o.trapped;
        self.delivered += o.delivered;
        self.stuck_back += o.stuck_back;
        self.received += o.received;
        self.received_back += o.received_back;
        self.detached += o.detached;
    }
}

impl TargetTally {
    /// Books one impact: counts it; a particle that stuck counts as released material
    /// received (front or back), as stuck on the back, or as sprayed material stuck on the
    /// front (and of that, as loose or as trapped rebound); a first impact on a substrate
    /// counts as material delivered.
    pub(crate) fn book(&mut self, impact: &Impact) {
        self.hits += 1;
        let q = impact.quanta;
        if impact.stuck {
            if impact.released {
                self.received.add(q);
                if impact.back {
                    self.received_back += Quanta::from(q);
                }
            } else if impact.back {
                self.stuck_back.add(q);
            } else {
                self.stuck.add(q);
                if impact.loose {
                    self.loose.add(q);
                } else if impact.rebound {
                    self.trapped.add(q);
                }
            }
        }
        if impact.first_substrate {
            self.delivered.add(q);
        }
    }
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

/// One impact on a target or an obstacle, as it is booked: the particle's volume and what
/// became of the particle.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Impact {
    /// The particle's volume, quanta.
    pub quanta: u64,
    /// The impact was on the back of a target, which collects no deposit.
    pub back: bool,
    /// The particle stuck (adhering or loose) instead of rebounding.
    pub stuck: bool,
    /// The particle is material a cohesive failure, a drip or a slump released.
    pub released: bool,
    /// The particle came to rest loose (a slow rebound), not adhering: with `stuck`.
    pub loose: bool,
    /// The particle had rebounded before this impact.
    pub rebound: bool,
    /// The particle's first impact on the front of a substrate target.
    pub first_substrate: bool,
}

impl Target {
    /// Applies what the epoch's particles left on this target (its [`Pending`] counters) to
    /// its layer, its impact counts and its erosion maps: each cell of `touched` once, with
    /// the run's volume quantum `q` (m³). An epoch's wear on a cell is applied as one impact
    /// of the summed volumes: the coating first, the substrate with the share of the wear the
    /// coating left did not absorb.
    pub(crate) fn settle(&mut self, touched: &[u32], q: f64) {
        for &cell in touched {
            let g = self.pending.take(cell);
            if g.hits > 0 {
                self.surface.add_hits(cell, g.hits);
            }
            if g.quanta > 0 {
                let area = self.surface.cell_area(cell);
                self.surface.add_thickness(cell, g.quanta as f64 * q / area);
            }
            if let Some(e) = &mut self.erosion
                && g.wear != [0, 0]
            {
                let area = self.surface.cell_area(cell);
                let [coat, sub] = g.wear.map(|w| w as f64 * WEAR_QUANTUM);
                e.wear(cell as usize, area, coat, sub);
            }
        }
    }

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
    /// Name the scenario gives it (unique among targets and obstacles), for outputs.
    pub name: String,
    /// What has struck it, in quanta.
    pub tally: ObstacleTally,
}

/// What has struck an obstacle, in quanta of the run's volume quantum (see [`Tallied`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ObstacleTally {
    /// Impacts, stuck or rebounded.
    pub hits: u64,
    /// Particles stuck on it.
    pub stuck: Tallied,
    /// Released material that landed on it.
    pub received: Tallied,
}

impl std::ops::AddAssign for ObstacleTally {
    fn add_assign(&mut self, o: ObstacleTally) {
        self.hits += o.hits;
        self.stuck += o.stuck;
        self.received += o.received;
    }
}

impl ObstacleTally {
    /// Books one impact: counts it, and a particle that stuck as released material received or
    /// as stuck.
    pub(crate) fn book(&mut self, impact: &Impact) {
        self.hits += 1;
        if impact.stuck {
            if impact.released { &mut self.received } else { &mut self.stuck }.add(impact.quanta);
        }
    }
}
