//! Per-particle random streams.
//!
//! Every random draw belongs to one particle and one event of that particle (its emission, its
//! n-th impact). The draw comes from a ChaCha8 stream keyed by the run's seed, selected by the
//! particle's id and positioned by the event number, so results do not depend on how particles
//! are spread over threads or in which order they are processed.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// 32-bit words reserved per event: far more than any event draws.
const WORDS_PER_EVENT: u128 = 1 << 16;

/// The event number of the draw that fixes what a particle is made of (see
/// [`crate::process::ImpactSite::material`]): never an impact's (those count from 1 and stop at
/// 2¹⁶).
pub const MATERIAL_EVENT: u32 = u32::MAX;

/// Key material for all streams of one run.
#[derive(Clone, Copy, Debug)]
pub struct StreamKey([u8; 32]);

impl StreamKey {
    /// Expands a 64-bit seed into a stream key (the generator's own seed expansion).
    pub fn new(seed: u64) -> Self {
        StreamKey(ChaCha8Rng::seed_from_u64(seed).get_seed())
    }

    /// The generator for `event` (0 = emission, n = n-th impact, [`MATERIAL_EVENT`]) of
    /// particle `particle`.
    #[inline]
    pub fn stream(&self, particle: u64, event: u32) -> ChaCha8Rng {
        let mut rng = ChaCha8Rng::from_seed(self.0);
        rng.set_stream(particle);
        rng.set_word_pos(u128::from(event) * WORDS_PER_EVENT);
        rng
    }
}
