//! Particle storage: one array per attribute (structure of arrays), so the update stage is a
//! plain loop over parallel slices.

use glam::DVec3;

/// Status bits of a particle.
pub mod flags {
    /// The particle is in flight.
    pub const ALIVE: u8 = 1;
    /// It has struck a substrate target at least once.
    pub const HIT_SUBSTRATE: u8 = 2;
    /// It is material released by a cohesive failure, not a particle from the nozzle.
    pub const RELEASED: u8 = 4;
}

/// All particles of a run: in flight, or retired and waiting for compaction.
///
/// Per particle: position and velocity (2 × 24 bytes), age and volume (2 × 4), id (4), wake
/// step (4), impact count (2) and flags (1): 67 bytes.
#[derive(Clone, Debug, Default)]
pub struct Swarm {
    /// Position, m.
    pub pos: Vec<DVec3>,
    /// Velocity, m/s.
    pub vel: Vec<DVec3>,
    /// Time since emission, s.
    pub age: Vec<f32>,
    /// Material volume carried, m³.
    pub volume: Vec<f32>,
    /// Emission index within the run; selects the particle's random stream.
    pub id: Vec<u32>,
    /// Impacts so far; numbers the particle's random events.
    pub impacts: Vec<u16>,
    /// Status bits, see [`flags`].
    pub flags: Vec<u8>,
    /// Step at which the particle is next updated. With the exact integrator, a particle whose
    /// flight certainly meets nothing for a while is moved there in closed form and skips the
    /// steps in between; its position and velocity are then those at the start of that step.
    pub wake: Vec<u32>,
}

impl Swarm {
    /// Bytes of storage per particle slot, summed over the arrays.
    pub const BYTES_PER_PARTICLE: usize = 2 * std::mem::size_of::<DVec3>()
        + 2 * std::mem::size_of::<f32>()
        + 2 * std::mem::size_of::<u32>()
        + std::mem::size_of::<u16>()
        + std::mem::size_of::<u8>();

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

    /// Adds a particle in flight.
    pub fn push(&mut self, pos: DVec3, vel: DVec3, volume: f32, id: u32) {
        self.push_with_flags(pos, vel, volume, id, flags::ALIVE);
    }

    /// Adds a particle with the given status bits.
    pub fn push_with_flags(&mut self, pos: DVec3, vel: DVec3, volume: f32, id: u32, bits: u8) {
        self.pos.push(pos);
        self.vel.push(vel);
        self.age.push(0.0);
        self.volume.push(volume);
        self.id.push(id);
        self.impacts.push(0);
        self.flags.push(bits);
        self.wake.push(0);
    }

    /// Drops retired particles, keeping the others in order (so processing order, and with it
    /// every result, is independent of when compaction runs).
    pub fn compact(&mut self) {
        let keep: Vec<bool> = self.flags.iter().map(|f| f & flags::ALIVE != 0).collect();
        fn retain<T: Copy>(v: &mut Vec<T>, keep: &[bool]) {
            let mut k = keep.iter();
            v.retain(|_| *k.next().unwrap_or(&false));
        }
        retain(&mut self.pos, &keep);
        retain(&mut self.vel, &keep);
        retain(&mut self.age, &keep);
        retain(&mut self.volume, &keep);
        retain(&mut self.id, &keep);
        retain(&mut self.impacts, &keep);
        retain(&mut self.flags, &keep);
        retain(&mut self.wake, &keep);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_particle_slot_takes_67_bytes_and_compaction_keeps_order() {
        assert_eq!(Swarm::BYTES_PER_PARTICLE, 67);
        let mut s = Swarm::default();
        s.push(DVec3::ONE, DVec3::X, 1e-6, 7);
        s.push(DVec3::ZERO, DVec3::Y, 2e-6, 8);
        s.flags[0] &= !flags::ALIVE;
        s.compact();
        assert_eq!((s.len(), s.id[0], s.alive()), (1, 8, 1));
    }
}
