//! Particles: structure-of-arrays storage and the random streams each particle draws from.

pub mod rng;
pub mod swarm;

pub use rng::{MATERIAL_EVENT, StreamKey};
pub use swarm::{Swarm, Volumes, flags};
