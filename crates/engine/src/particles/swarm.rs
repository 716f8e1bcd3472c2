//! Particle storage: one array per attribute (structure of arrays), so the update stage is a
//! plain loop over parallel slices.

use crate::checkpoint::{Dec, Enc, StateError};
use glam::DVec3;

/// Status bits of a particle.
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

/// Material volume of each particle, without an array over all of them: every particle from
/// the nozzle carries the emitter's volume, and released material (rare) carries its own, kept
/// in a table by id.
#[derive(Clone, Debug, Default)]
pub struct Volumes {
    /// Volume of every particle from the nozzle, m³.
    pub nozzle: f32,
    /// `(id, volume in m³)` of each released particle, by increasing id.
    released: Vec<(u32, f32)>,
}

impl Volumes {
    /// Volume carried by the particle with emission index `id` and status bits `bits`, m³.
    #[inline]
    pub fn of(&self, id: u32, bits: u8) -> f32 {
        if bits & flags::RELEASED == 0 {
            return self.nozzle;
        }
        // Every released particle in flight is in the table.
        self.released.binary_search_by_key(&id, |&(i, _)| i).map_or(0.0, |k| self.released[k].1)
    }
}

/// All particles of a run: in flight, or retired and waiting for compaction.
///
/// Per particle: position and velocity (2 × 24 bytes), age (4), id (4), wake step (4), impact
/// count (2) and flags (1): 63 bytes. Volumes are not stored per particle (see [`Volumes`]).
/// Slots stay in increasing id order.
#[derive(Clone, Debug, Default)]
pub struct Swarm {
    /// Position, m.
    pub pos: Vec<DVec3>,
    /// Velocity, m/s.
    pub vel: Vec<DVec3>,
    /// Time since emission, s.
    pub age: Vec<f32>,
    /// Emission index within the run; selects the particle's random stream.
    pub id: Vec<u32>,
    /// Impacts so far; numbers the particle's random events.
    pub impacts: Vec<u16>,
    /// Status bits, see [`flags`].
    pub flags: Vec<u8>,
    /// Step at which the particle is next updated. With the exact integrator, a particle whose
    /// flight certainly meets nothing for a while is moved in closed form to the start of the
    /// step of its next event and skips the steps in between; its position and velocity are
    /// then those at the start of that step.
    pub wake: Vec<u32>,
    /// Material volume carried by each particle.
    pub volumes: Volumes,
}

impl Swarm {
    /// Bytes of storage per particle slot, summed over the arrays.
    pub const BYTES_PER_PARTICLE: usize = 2 * std::mem::size_of::<DVec3>()
        + std::mem::size_of::<f32>()
        + 2 * std::mem::size_of::<u32>()
        + std::mem::size_of::<u16>()
        + std::mem::size_of::<u8>();

    /// An empty swarm whose nozzle particles each carry `nozzle_volume` (m³).
    pub fn new(nozzle_volume: f32) -> Swarm {
        Swarm { volumes: Volumes { nozzle: nozzle_volume, released: Vec::new() }, ..Swarm::default() }
    }

    /// Number of slots (in flight or retired since the last compaction).
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// True when no slot is used.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Number of particles in flight.
    pub fn alive(&self) -> usize {
        self.flags.iter().filter(|&&f| f & flags::ALIVE != 0).count()
    }

    /// Material volume carried by the particle in slot `i`, m³.
    pub fn volume(&self, i: usize) -> f32 {
        self.volumes.of(self.id[i], self.flags[i])
    }

    /// Adds a particle from the nozzle, in flight; `id` must exceed every id so far.
    pub fn push(&mut self, pos: DVec3, vel: DVec3, id: u32) {
        self.push_slot(pos, vel, id, flags::ALIVE);
    }

    /// Adds released material of `volume` (m³) with the given status bits (which must include
    /// [`flags::RELEASED`]); `id` must exceed every id so far.
    pub fn push_released(&mut self, pos: DVec3, vel: DVec3, volume: f32, id: u32, bits: u8) {
        debug_assert!(bits & flags::RELEASED != 0);
        self.volumes.released.push((id, volume));
        self.push_slot(pos, vel, id, bits);
    }

    fn push_slot(&mut self, pos: DVec3, vel: DVec3, id: u32, bits: u8) {
        debug_assert!(self.id.last().is_none_or(|&last| last < id), "ids must increase");
        self.pos.push(pos);
        self.vel.push(vel);
        self.age.push(0.0);
        self.id.push(id);
        self.impacts.push(0);
        self.flags.push(bits);
        self.wake.push(0);
    }

    /// Writes every particle slot and the released volumes, for a checkpoint.
    pub(crate) fn save_state(&self, e: &mut Enc) {
        e.f32(self.volumes.nozzle);
        e.list(&self.volumes.released, |e, &(id, v)| {
            e.u32(id);
            e.f32(v);
        });
        e.list(&self.pos, |e, &p| e.vec3(p));
        e.list(&self.vel, |e, &v| e.vec3(v));
        e.list(&self.age, |e, &x| e.f32(x));
        e.list(&self.id, |e, &x| e.u32(x));
        e.list(&self.impacts, |e, &x| e.u16(x));
        e.list(&self.flags, |e, &x| e.u8(x));
        e.list(&self.wake, |e, &x| e.u32(x));
    }

    /// Reads what [`Swarm::save_state`] wrote.
    pub(crate) fn load_state(d: &mut Dec<'_>) -> Result<Swarm, StateError> {
        let nozzle = d.f32()?;
        let released = d.list(8, |d| Ok((d.u32()?, d.f32()?)))?;
        let pos = d.list(24, Dec::vec3)?;
        let n = pos.len();
        let swarm = Swarm {
            pos,
            vel: d.list_of(n, "the velocities", 24, Dec::vec3)?,
            age: d.list_of(n, "the ages", 4, Dec::f32)?,
            id: d.list_of(n, "the ids", 4, Dec::u32)?,
            impacts: d.list_of(n, "the impact counts", 2, Dec::u16)?,
            flags: d.list_of(n, "the flags", 1, Dec::u8)?,
            wake: d.list_of(n, "the wake steps", 4, Dec::u32)?,
            volumes: Volumes { nozzle, released },
        };
        if swarm.id.windows(2).any(|w| w[0] >= w[1]) {
            return Err(StateError::Mismatch("particle ids out of order".into()));
        }
        Ok(swarm)
    }

    /// Drops retired particles, keeping the others in order (so processing order, and with it
    /// every result, is independent of when compaction runs).
    pub fn compact(&mut self) {
        // One pass over every array, moving each kept slot down to the next free one.
        let mut kept = 0;
        for i in 0..self.len() {
            if self.flags[i] & flags::ALIVE == 0 {
                continue;
            }
            self.pos[kept] = self.pos[i];
            self.vel[kept] = self.vel[i];
            self.age[kept] = self.age[i];
            self.id[kept] = self.id[i];
            self.impacts[kept] = self.impacts[i];
            self.flags[kept] = self.flags[i];
            self.wake[kept] = self.wake[i];
            kept += 1;
        }
        self.pos.truncate(kept);
        self.vel.truncate(kept);
        self.age.truncate(kept);
        self.id.truncate(kept);
        self.impacts.truncate(kept);
        self.flags.truncate(kept);
        self.wake.truncate(kept);
        // The released particles still in flight, in slot (so id) order.
        let v = &self.volumes;
        let kept = self.id.iter().zip(&self.flags).filter(|&(_, f)| f & flags::RELEASED != 0);
        self.volumes.released = kept.map(|(&id, &f)| (id, v.of(id, f))).collect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_particle_slot_takes_63_bytes_and_compaction_keeps_order_and_volumes() {
        assert_eq!(Swarm::BYTES_PER_PARTICLE, 63);
        let mut s = Swarm::new(1e-6);
        let released = flags::ALIVE | flags::RELEASED;
        s.push(DVec3::ONE, DVec3::X, 7);
        s.push_released(DVec3::ZERO, DVec3::ZERO, 3e-6, 8, released);
        s.push(DVec3::ZERO, DVec3::Y, 9);
        s.push_released(DVec3::ZERO, DVec3::ZERO, 5e-6, 10, released);
        s.push_released(DVec3::ZERO, DVec3::ZERO, 6e-6, 11, released);
        s.flags[0] &= !flags::ALIVE;
        s.flags[3] &= !flags::ALIVE;
        s.compact();
        assert_eq!(s.id, [8, 9, 11]);
        assert_eq!(s.alive(), 3);
        assert_eq!([s.volume(0), s.volume(1), s.volume(2)], [3e-6, 1e-6, 6e-6]);
        // The retired released particle's entry is gone with it.
        assert_eq!(s.volumes.released.len(), 2);
    }
}
