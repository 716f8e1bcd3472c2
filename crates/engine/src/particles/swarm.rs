//! Particle storage: one 48-byte record per particle in flight, everything included.
//!
//! # What a particle holds, and the precision of each part
//!
//! A [`Particle`] is its *anchor* (the position and velocity at its last event: its emission,
//! its last impact, or, with the Euler integrators, the end of its last step), the whole steps
//! flown since then, the step it was born, its id and its status. Its present position and
//! velocity follow from the anchor: in closed form for the exact integrator, and as the anchor
//! itself for the Euler ones, which re-anchor at every step.
//!
//! - **Positions are f64.** A particle's position is compared with layers tens of micrometres
//!   thick at coordinates up to 10⁴ m ([`crate::config::MAX_COORD`]), where an f32 resolves
//!   only a millimetre.
//! - **Velocities are f32.** Rounding a velocity to single precision changes it by at most
//!   2⁻²⁴ of itself, which moves the particle by at most `2⁻²⁴ |v| Δt` per step. An Euler
//!   particle re-anchors every step, so over a flight of `n` steps the rounding adds up to at
//!   most `n² Δt |v| 2⁻²⁵`: under 1 mm for 1000 steps (1 s at Δt = 1 ms) at 30 m/s, against the
//!   integrator's own error of about `|g| t Δt / 2` = 5 mm over the same second (and, as the
//!   rounding errors have no preferred sign, typically √n times less). An exact-integrator
//!   particle is rounded only at its events, so its flight between them is exact.
//! - **Times are whole steps.** The age is the step count since birth, the anchor's time the
//!   step count since the anchor (re-anchored before it overflows), so neither drifts.
//!
//! Volumes are not stored per particle: every particle from the nozzle carries the emitter's
//! volume, and released material (rare) carries its own, kept in a table by id ([`Volumes`]).
//! Slots stay in increasing id order.

use crate::checkpoint::{Dec, Enc, StateError};
use glam::{DVec3, Vec3};

/// Status bits of a particle (the top four bits of [`Particle::status`]).
pub mod flags {
    /// The particle is in flight.
    pub const ALIVE: u8 = 1;
    /// It has struck a substrate target at least once.
    pub const HIT_SUBSTRATE: u8 = 2;
    /// It is material released by a cohesive failure, not a particle from the nozzle.
    pub const RELEASED: u8 = 4;
    /// It has rebounded at least once.
    pub const BOUNCED: u8 = 8;
}

/// Most impacts a particle may make: its impact count has 12 bits. A particle that reaches it
/// is retired as expired.
pub const MAX_IMPACTS: u16 = (1 << 12) - 1;

/// One particle in flight (or retired and waiting for compaction): 48 bytes.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct Particle {
    /// Position at the anchor, m.
    pub anchor: DVec3,
    /// Velocity at the anchor, m/s (single precision: see the module's docs).
    pub velocity: Vec3,
    /// The step in which the particle was emitted or released: its age is the steps since.
    pub born: u32,
    /// Emission index within the run; selects the particle's random streams.
    pub id: u32,
    /// Whole steps flown since the anchor (always 0 with the Euler integrators).
    pub since: u16,
    /// Impact count (low 12 bits, at most [`MAX_IMPACTS`]) and status bits (high 4, see
    /// [`flags`]).
    pub status: u16,
}

const _: () = assert!(std::mem::size_of::<Particle>() == 48);

impl Particle {
    /// A particle at `position` (m) with `velocity` (m/s), born in step `born`, with status
    /// bits `bits` and no impact yet.
    pub fn new(position: DVec3, velocity: DVec3, born: u32, id: u32, bits: u8) -> Particle {
        Particle {
            anchor: position,
            velocity: velocity.as_vec3(),
            born,
            id,
            since: 0,
            status: u16::from(bits) << 12,
        }
    }

    /// Status bits (see [`flags`]).
    #[inline]
    pub fn flags(&self) -> u8 {
        (self.status >> 12) as u8
    }

    /// Sets the status bits (see [`flags`]).
    #[inline]
    pub fn set_flags(&mut self, bits: u8) {
        self.status = (self.status & MAX_IMPACTS) | (u16::from(bits & 0xF) << 12);
    }

    /// True while the particle is in flight.
    #[inline]
    pub fn is_alive(&self) -> bool {
        self.flags() & flags::ALIVE != 0
    }

    /// Impacts so far; numbers the particle's random events.
    #[inline]
    pub fn impacts(&self) -> u16 {
        self.status & MAX_IMPACTS
    }

    /// Sets the impact count (at most [`MAX_IMPACTS`]).
    #[inline]
    pub fn set_impacts(&mut self, n: u16) {
        self.status = (self.status & !MAX_IMPACTS) | n.min(MAX_IMPACTS);
    }

    /// The anchor velocity, m/s, in double precision.
    #[inline]
    pub fn anchor_velocity(&self) -> DVec3 {
        self.velocity.as_dvec3()
    }

    /// Position (m) and velocity (m/s) `since` steps of `dt` (s) after the anchor, in closed
    /// form under the acceleration `gravity` (m/s²): where an exact-integrator particle is now.
    /// With `since` 0 (always so for the Euler integrators, which re-anchor every step), the
    /// anchor itself.
    #[inline]
    pub fn now(&self, dt: f64, gravity: DVec3) -> (DVec3, DVec3) {
        let v = self.anchor_velocity();
        if self.since == 0 {
            return (self.anchor, v);
        }
        let tau = f64::from(self.since) * dt;
        (self.anchor + v * tau + 0.5 * gravity * tau * tau, v + gravity * tau)
    }
}

/// Material volume of each particle, without an array over all of them: every particle from
/// the nozzle carries the emitter's volume, and released material (rare) carries its own, kept
/// in a table by id. Volumes are in quanta of the run's volume quantum (see
/// [`crate::SimulationConfig::volume_quantum`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Volumes {
    /// Volume of every particle from the nozzle, quanta.
    pub nozzle: u64,
    /// `(id, volume in quanta)` of each released particle, by increasing id.
    released: Vec<(u32, u64)>,
}

impl Volumes {
    /// Volume carried by the particle with emission index `id` and status bits `bits`, quanta.
    #[inline]
    pub fn of(&self, id: u32, bits: u8) -> u64 {
        if bits & flags::RELEASED == 0 {
            return self.nozzle;
        }
        // Every released particle in flight is in the table.
        self.released.binary_search_by_key(&id, |&(i, _)| i).map_or(0, |k| self.released[k].1)
    }
}

/// All particles of a run: in flight, or retired and waiting for compaction. Slots stay in
/// increasing id order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Swarm {
    /// The particles, by increasing id.
    pub particles: Vec<Particle>,
    /// Material volume carried by each particle.
    pub volumes: Volumes,
}

impl Swarm {
    /// Bytes of storage per particle slot.
    pub const BYTES_PER_PARTICLE: usize = std::mem::size_of::<Particle>();

    /// An empty swarm whose nozzle particles each carry `nozzle_volume` quanta.
    pub fn new(nozzle_volume: u64) -> Swarm {
        Swarm { particles: Vec::new(), volumes: Volumes { nozzle: nozzle_volume, released: Vec::new() } }
    }

    /// Number of slots (in flight or retired since the last compaction).
    pub fn len(&self) -> usize {
        self.particles.len()
    }

    /// True when no slot is used.
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// Number of particles in flight.
    pub fn alive(&self) -> usize {
        self.particles.iter().filter(|p| p.is_alive()).count()
    }

    /// Material volume carried by the particle in slot `i`, quanta.
    pub fn volume(&self, i: usize) -> u64 {
        let p = &self.particles[i];
        self.volumes.of(p.id, p.flags())
    }

    /// Adds released material of `quanta` volume; its id must exceed every id so far.
    pub fn push_released(&mut self, particle: Particle, quanta: u64) {
        debug_assert!(particle.flags() & flags::RELEASED != 0);
        self.volumes.released.push((particle.id, quanta));
        self.push(particle);
    }

    /// Adds a particle; its id must exceed every id so far.
    pub fn push(&mut self, particle: Particle) {
        debug_assert!(self.particles.last().is_none_or(|last| last.id < particle.id), "ids must increase");
        self.particles.push(particle);
    }

    /// Writes every particle slot and the released volumes, for a checkpoint.
    pub(crate) fn save_state(&self, e: &mut Enc) {
        e.u64(self.volumes.nozzle);
        e.list(&self.volumes.released, |e, &(id, v)| {
            e.u32(id);
            e.u64(v);
        });
        e.list(&self.particles, |e, p| {
            e.vec3(p.anchor);
            p.velocity.to_array().into_iter().for_each(|x| e.f32(x));
            e.u32(p.born);
            e.u32(p.id);
            e.u16(p.since);
            e.u16(p.status);
        });
    }

    /// Reads what [`Swarm::save_state`] wrote.
    pub(crate) fn load_state(d: &mut Dec<'_>) -> Result<Swarm, StateError> {
        let nozzle = d.u64()?;
        let released = d.list(12, |d| Ok((d.u32()?, d.u64()?)))?;
        let particles = d.list(48, |d| {
            Ok(Particle {
                anchor: d.vec3()?,
                velocity: Vec3::new(d.f32()?, d.f32()?, d.f32()?),
                born: d.u32()?,
                id: d.u32()?,
                since: d.u16()?,
                status: d.u16()?,
            })
        })?;
        if particles.windows(2).any(|w| w[0].id >= w[1].id) {
            return Err(StateError::Mismatch("particle ids out of order".into()));
        }
        if released.windows(2).any(|w| w[0].0 >= w[1].0) {
            return Err(StateError::Mismatch("released particle ids out of order".into()));
        }
        Ok(Swarm { particles, volumes: Volumes { nozzle, released } })
    }

    /// Drops retired particles, keeping the others in order (so processing order, and with it
    /// every result, is independent of when compaction runs).
    pub fn compact(&mut self) {
        self.particles.retain(Particle::is_alive);
        // The released particles still in flight, in slot (so id) order.
        let v = &self.volumes;
        let kept = self.particles.iter().filter(|p| p.flags() & flags::RELEASED != 0);
        self.volumes.released = kept.map(|p| (p.id, v.of(p.id, p.flags()))).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_bits_and_impact_count_share_a_word_without_spilling() {
        let mut p = Particle::new(DVec3::ONE, DVec3::X, 7, 3, flags::ALIVE | flags::RELEASED);
        assert_eq!((p.flags(), p.impacts()), (flags::ALIVE | flags::RELEASED, 0));
        p.set_impacts(MAX_IMPACTS + 10);
        assert_eq!((p.flags(), p.impacts()), (flags::ALIVE | flags::RELEASED, MAX_IMPACTS));
        p.set_flags(flags::BOUNCED);
        assert_eq!((p.flags(), p.impacts()), (flags::BOUNCED, MAX_IMPACTS));
        assert!(!p.is_alive());
    }

    #[test]
    fn compaction_keeps_live_particles_in_order_with_their_volumes() {
        let mut s = Swarm::new(100);
        for id in 0..6u32 {
            let bits = if id % 2 == 0 { flags::ALIVE | flags::RELEASED } else { flags::ALIVE };
            let p = Particle::new(DVec3::ZERO, DVec3::ZERO, 0, id, bits);
            if bits & flags::RELEASED != 0 { s.push_released(p, u64::from(id) + 1) } else { s.push(p) }
        }
        s.particles[2].set_flags(flags::RELEASED);
        s.particles[3].set_flags(0);
        s.compact();
        let ids: Vec<u32> = s.particles.iter().map(|p| p.id).collect();
        assert_eq!(ids, [0, 1, 4, 5]);
        assert_eq!((0..4).map(|i| s.volume(i)).collect::<Vec<_>>(), [1, 100, 5, 100]);
    }
}
