//! Per-particle random streams.
//!
//! Every random draw belongs to one particle and one event of that particle (its emission, its
//! n-th impact). The draw comes from a stream of its own, keyed by the run's seed and selected
//! by the particle's id and the event number, so results do not depend on how particles are
//! spread over threads or in which order they are processed.
//!
//! An event draws a handful of numbers, so a stream must be cheap to open (opening a ChaCha8
//! stream computed four 64-byte blocks for them, about 6 % of a run): it is a xoshiro256++
//! generator whose four state words are the key's words, each combined with the pair
//! `(particle, event)` packed into 64 bits and mixed by SplitMix64's output function, a
//! bijection of 64-bit words. Distinct pairs therefore start from distinct, well-mixed states.

use rand::{RngCore, SeedableRng};
use rand_xoshiro::{SplitMix64, Xoshiro256PlusPlus};

/// The generator of one event of one particle.
pub type Stream = Xoshiro256PlusPlus;

/// The event number of the draw that fixes what a particle is made of (see
/// [`crate::process::ImpactSite::material`]): never an impact's (those count from 1 and stop at
/// 2¹⁶).
pub const MATERIAL_EVENT: u32 = u32::MAX;

/// Key material for all streams of one run.
#[derive(Clone, Copy, Debug)]
pub struct StreamKey([u64; 4]);

impl StreamKey {
    /// Expands a 64-bit seed into a stream key (four SplitMix64 outputs).
    pub fn new(seed: u64) -> Self {
        let mut expand = SplitMix64::seed_from_u64(seed);
        StreamKey(std::array::from_fn(|_| expand.next_u64()))
    }

    /// The generator for `event` (0 = emission, n = n-th impact, [`MATERIAL_EVENT`]) of
    /// the particle with id `particle`.
    #[inline]
    pub fn stream(&self, particle: u32, event: u32) -> Stream {
        let pair = (u64::from(particle) << 32) | u64::from(event);
        let mut seed = [0u8; 32];
        for (bytes, key) in seed.chunks_exact_mut(8).zip(self.0) {
            let word = SplitMix64::seed_from_u64(key ^ pair).next_u64();
            bytes.copy_from_slice(&word.to_le_bytes());
        }
        Stream::from_seed(seed)
    }

    /// A well-mixed 64-bit word keyed by the run's key and `x`, without opening a stream: for
    /// a draw that must be found again cheaply and often (a particle's droplet size, see
    /// [`crate::emission::DropletSizes`]).
    #[inline]
    pub fn word(&self, x: u64) -> u64 {
        SplitMix64::seed_from_u64(self.0[0] ^ x.rotate_left(17) ^ self.0[3]).next_u64()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    /// Pearson's correlation of two equally long samples.
    fn correlation(a: &[f64], b: &[f64]) -> f64 {
        let n = a.len() as f64;
        let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
        let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
        let (va, vb): (f64, f64) =
            (a.iter().map(|x| (x - ma).powi(2)).sum(), b.iter().map(|y| (y - mb).powi(2)).sum());
        cov / (va * vb).sqrt()
    }

    /// The `k`-th draw (from 1) of each stream.
    fn draw(key: &StreamKey, streams: impl Iterator<Item = (u32, u32)>, k: usize) -> Vec<f64> {
        streams.map(|(p, e)| key.stream(p, e).random_iter::<f64>().nth(k - 1).unwrap_or(f64::NAN)).collect()
    }

    /// Neighbouring particles and neighbouring events (what a weak mixing of the id or the event
    /// into the state would show first) give uniform, uncorrelated draws, the first (which
    /// xoshiro256++ takes from two of its four state words) and the fourth (from all four), and
    /// no two of these streams start alike.
    #[test]
    fn neighbouring_streams_are_uniform_uncorrelated_and_distinct() {
        let key = StreamKey::new(20_261_125);
        let n = 100_000_u32;
        let limit = 6.0 / f64::from(n).sqrt();
        for k in [1, 4] {
            let by_particle = draw(&key, (0..n).map(|p| (p, 1)), k);
            let by_event = draw(&key, (0..n).map(|e| (7, e)), k);
            let next_event = draw(&key, (0..n).map(|p| (p, 2)), k);
            let material = draw(&key, (0..n).map(|p| (p, MATERIAL_EVENT)), k);
            for draws in [&by_particle, &by_event, &material] {
                // χ² over 64 bins, 63 degrees of freedom: mean 63, standard deviation 11.2.
                let mut bins = [0.0_f64; 64];
                draws.iter().for_each(|&x| bins[(x * 64.0) as usize] += 1.0);
                let expected = f64::from(n) / 64.0;
                let chi2: f64 = bins.iter().map(|b| (b - expected).powi(2) / expected).sum();
                assert!(chi2 < 63.0 + 6.0 * 11.2, "draw {k}: χ² = {chi2}");
                // Lag-one correlation within 6 standard errors of 0.
                let r = correlation(&draws[1..], &draws[..draws.len() - 1]);
                assert!(r.abs() < limit, "draw {k}: lag-one correlation {r}");
            }
            for other in [&next_event, &material] {
                let r = correlation(&by_particle, other);
                assert!(r.abs() < limit, "draw {k}: correlation between events {r}");
            }
        }
        // Whole first outputs: 3 × 10⁵ 64-bit words collide with probability about 10⁻⁹.
        let events = [1, 2, MATERIAL_EVENT];
        let mut words: Vec<u64> = (0..n).flat_map(|p| events.map(|e| key.stream(p, e).next_u64())).collect();
        words.sort_unstable();
        words.dedup();
        assert_eq!(words.len(), 3 * n as usize, "two streams start alike");
    }

    /// The key decides the streams: another seed gives other draws.
    #[test]
    fn another_seed_gives_other_streams() {
        let (a, b) = (StreamKey::new(1), StreamKey::new(2));
        let same = (0..1000).filter(|&p| a.stream(p, 0).next_u64() == b.stream(p, 0).next_u64()).count();
        assert_eq!(same, 0);
    }

    /// The streams are part of what a seed reproduces: a change of the generator or of its
    /// keying (a dependency's update, say) must be deliberate, with the checkpoint version and
    /// the documented figures, not slip through.
    #[test]
    fn the_streams_of_a_seed_stay_what_they_were() {
        let key = StreamKey::new(1);
        let words = [
            key.stream(0, 0).next_u64(),
            key.stream(12_345, 3).next_u64(),
            key.stream(7, MATERIAL_EVENT).next_u64(),
        ];
        assert_eq!(words, [5_803_885_887_805_190_641, 9_482_626_306_977_773_561, 6_142_177_828_558_001_977]);
    }
}
