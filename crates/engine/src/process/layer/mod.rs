//! Layer stages: behaviour that acts on the deposited layers at fixed intervals, sequentially
//! and in target order (so deterministically), one stage per file.

mod cohesion;
mod drip;
mod slump;

pub use cohesion::{Analysis, CohesionStage, Region, Strength, analyse, stress_per_thickness};
pub use drip::DripStage;
pub use slump::{Relaxation, RunOff, SlumpStage, relax};

use crate::events::FailureEvent;
use crate::particles::{Particle, Swarm, flags};
use crate::tally::Tally;
use crate::world::Target;
use glam::DVec3;

/// Distance in front of the surface at which released material starts, m: clear of the surface
/// for any straight or curved flight test.
pub const RELEASE_OFFSET: f64 = 1e-6;

/// A behaviour that acts on the deposited layers every so often.
pub trait LayerStage: Send + Sync + std::fmt::Debug {
    /// Name, for reports.
    fn name(&self) -> &'static str;

    /// Acts on every target's layer.
    fn run(&self, ctx: &mut LayerContext<'_>);
}

/// What a layer stage sees and may change.
pub struct LayerContext<'a> {
    /// Time at the end of the current step, s.
    pub time: f64,
    /// Gravitational acceleration, m/s².
    pub gravity: DVec3,
    /// Density of the deposited material, kg/m³.
    pub density: f64,
    /// The targets, in configuration order.
    pub targets: &'a mut [Target],
    /// Failures found so far in the run; a stage appends the ones it finds.
    pub failures: &'a mut Vec<FailureEvent>,
    /// Hands material to the swarm.
    pub release: Releaser<'a>,
}

/// Why material leaves a layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Release {
    /// A cohesive failure.
    Failure,
    /// Film running off a sagging surface.
    Drip,
    /// A yield-stress layer slumping over the surface's edge.
    RunOff,
}

/// Turns material removed from a layer into particles.
pub struct Releaser<'a> {
    pub(crate) swarm: &'a mut Swarm,
    pub(crate) tally: &'a mut Tally,
    pub(crate) next_id: &'a mut u64,
    /// The step the released particles are born in: the first of the next epoch.
    pub(crate) born: u32,
    /// The run's volume quantum, m³ (see [`crate::SimulationConfig::volume_quantum`]).
    pub(crate) quantum: f64,
}

impl Releaser<'_> {
    /// Removes up to `volume` (m³) of `cell`'s layer of `target` and releases it as one particle
    /// at rest just in front of the surface (released material never counts towards the rebound
    /// ratio); returns the volume removed.
    pub fn release(&mut self, target: &mut Target, cell: u32, volume: f64, why: Release) -> f64 {
        use crate::deposit::DepositSurface;
        let removed = target.surface.remove(cell, volume);
        let pos = target.surface.point_above(cell, RELEASE_OFFSET);
        self.emit(target, pos, DVec3::ZERO, removed, why);
        removed
    }

    /// Releases `volume` (m³), already taken off `target`'s layer, as one particle at `pos` (m)
    /// moving at `vel` (m/s). It carries the volume in whole quanta, rounded once.
    pub fn emit(&mut self, target: &mut Target, pos: DVec3, vel: DVec3, volume: f64, why: Release) {
        let bits = flags::ALIVE | flags::RELEASED | flags::HIT_SUBSTRATE;
        let quanta = {
            let q = volume / self.quantum;
            if q.is_finite() && q > 0.0 { q.round() as u64 } else { 0 }
        };
        // Validation bounds a run's particle count by 2³², so the id fits.
        let particle = Particle::new(pos, vel, self.born, *self.next_id as u32, bits);
        self.swarm.push_released(particle, quanta);
        *self.next_id += 1;
        self.tally.released.add(quanta);
        match why {
            Release::Drip => self.tally.dripped.add(quanta),
            Release::RunOff => self.tally.ran_off.add(quanta),
            Release::Failure => {}
        }
        target.tally.detached.add(quanta);
    }
}
