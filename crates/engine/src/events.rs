//! The observer seam: what a run reports as it happens, to whoever watches it (a viewer, the
//! Python bindings, an impact log), without the pipeline knowing them. In the spirit of
//! rapier's `EventHandler`: the caller passes a handler to `Simulation::step_with`,
//! and events reach it in a fixed order (particle order within a step), so what a handler sees
//! does not depend on the thread count.

use crate::collision::SurfaceId;
use glam::DVec3;

/// One impact of a particle on a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactEvent {
    /// Time of the impact, s.
    pub time: f64,
    /// Impact point, m.
    pub position: DVec3,
    /// Unit surface normal, facing the particle.
    pub normal: DVec3,
    /// Incoming velocity, m/s.
    pub velocity: DVec3,
    /// The surface struck.
    pub surface: SurfaceId,
    /// Whether the particle stuck (else it rebounded).
    pub stuck: bool,
    /// Volume eroded from the target, m³ (from the coating where the struck cell had some at
    /// the start of the step, else from the substrate).
    pub eroded: f32,
    /// The particle's emission index.
    pub particle: u32,
    /// The impact's number among the particle's impacts (1 for the first).
    pub impact: u16,
}

/// Particles emitted in one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmissionEvent {
    /// Time at the start of the step, s.
    pub time: f64,
    /// Emission index of the first particle.
    pub first: u64,
    /// Particles emitted in the step.
    pub count: u64,
    /// Volume each carries, m³.
    pub volume: f64,
}

/// One cohesive failure: a region of a layer that fell off.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FailureEvent {
    /// Time of the analysis that found it, s.
    pub time: f64,
    /// Target it fell from.
    pub target: String,
    /// Cells in the region.
    pub cells: usize,
    /// Area of the region, m².
    pub area: f64,
    /// Volume that fell, m³.
    pub volume: f64,
}

/// Watches a run. Every method has an empty default, so a handler implements what it needs.
pub trait EventHandler {
    /// Whether this handler wants [`EventHandler::impact`] calls; gathering impacts costs time
    /// in the parallel stage, so it is only done when asked for.
    fn wants_impacts(&self) -> bool {
        false
    }

    /// A particle struck a surface.
    fn impact(&mut self, event: &ImpactEvent) {
        let _ = event;
    }

    /// The nozzle emitted particles.
    fn emission(&mut self, event: &EmissionEvent) {
        let _ = event;
    }

    /// A region of a layer failed and fell.
    fn failure(&mut self, event: &FailureEvent) {
        let _ = event;
    }

    /// A step ended at `time` (s).
    fn step_end(&mut self, time: f64) {
        let _ = time;
    }
}

/// The handler that handles nothing, for a step without an observer.
impl EventHandler for () {}

/// A sample of the impacts of a run: a hash of particle and impact number against the sampled
/// share, so the sample is the same whatever the threads.
#[derive(Clone, Debug, PartialEq)]
pub struct ImpactLog {
    /// Share of impacts kept, 0..1.
    pub fraction: f64,
    /// Salt of the sampling hash (the run's seed).
    pub salt: u64,
    /// The impacts kept, in the order they were applied.
    pub entries: Vec<ImpactEvent>,
}

impl ImpactLog {
    /// An empty log keeping `fraction` of the impacts, sampled with `salt`.
    pub fn new(fraction: f64, salt: u64) -> Self {
        ImpactLog { fraction, salt, entries: Vec::new() }
    }

    /// Whether impact number `impact` of particle `id` belongs to the sample.
    #[inline]
    pub fn samples(&self, id: u32, impact: u16) -> bool {
        sampled(self.salt, id, impact, self.fraction)
    }
}

impl EventHandler for ImpactLog {
    fn wants_impacts(&self) -> bool {
        self.fraction > 0.0
    }

    fn impact(&mut self, event: &ImpactEvent) {
        if self.samples(event.particle, event.impact) {
            self.entries.push(*event);
        }
    }
}

/// Whether impact number `impact` of particle `id` is sampled: a hash of the pair against the
/// fraction.
#[inline]
pub(crate) fn sampled(salt: u64, id: u32, impact: u16, fraction: f64) -> bool {
    let mut z = salt ^ (u64::from(id) << 16 | u64::from(impact)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    ((z >> 11) as f64 / (1u64 << 53) as f64) < fraction
}

/// Two handlers as one: both see every event.
pub(crate) struct Both<'a>(pub &'a mut dyn EventHandler, pub &'a mut dyn EventHandler);

impl EventHandler for Both<'_> {
    fn wants_impacts(&self) -> bool {
        self.0.wants_impacts() || self.1.wants_impacts()
    }
    fn impact(&mut self, event: &ImpactEvent) {
        if self.0.wants_impacts() {
            self.0.impact(event);
        }
        if self.1.wants_impacts() {
            self.1.impact(event);
        }
    }
    fn emission(&mut self, event: &EmissionEvent) {
        self.0.emission(event);
        self.1.emission(event);
    }
    fn failure(&mut self, event: &FailureEvent) {
        self.0.failure(event);
        self.1.failure(event);
    }
    fn step_end(&mut self, time: f64) {
        self.0.step_end(time);
        self.1.step_end(time);
    }
}
