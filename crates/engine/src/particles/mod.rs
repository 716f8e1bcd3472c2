//! Particles: their lean 48-byte records and the random streams each particle draws from.

pub mod rng;
pub mod swarm;

pub use rng::{MATERIAL_EVENT, StreamKey};
pub use swarm::{MAX_IMPACTS, Particle, Swarm, Volumes, flags};
