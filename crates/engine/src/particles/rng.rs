//! Per-particle random streams.
//!
//! Every random draw belongs to one particle and one event of that particle (its emission, its
//! n-th impact). The draw comes from a stream of its own, keyed by the run's seed and selected
//! by the particle's id and the event number, so results do not depend on how particles are
//! spread over threads or in which order they are processed.
//!
//! An event draws a handful of numbers, so a stream must be cheap to open (a block cipher's
//! stream costs about as much to open as the rest of an impact): it is a xoshiro256++ generator
//! whose four state words are the key's words, each combined with the particle and the event
//! and mixed by SplitMix64's output function, a bijection of 64-bit words. For particle ids
//! below 2³² (every id of a run) distinct `(particle, event)` pairs therefore start from
//! distinct, well-mixed states.

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
    /// particle `particle` (an id below 2³²; higher bits fold into the event's).
    #[inline]
    pub fn stream(&self, particle: u64, event: u32) -> Stream {
        let pair = (particle << 32) ^ u64::from(event);
        let mut seed = [0u8; 32];
        for (bytes, key) in seed.chunks_exact_mut(8).zip(self.0) {
            let word = SplitMix64::seed_from_u64(key ^ pair).next_u64();
            bytes.copy_from_slice(&word.to_le_bytes());
        }
        Stream::from_seed(seed)
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

    /// Neighbouring particles and neighbouring events (what a weak mixing of the id or the event
    /// into the state would show first) give uniform, uncorrelated first draws, and no two of
    /// these streams start alike.
    #[test]
    fn neighbouring_streams_are_uniform_uncorrelated_and_distinct() {
        let key = StreamKey::new(20_261_125);
        let n = 100_000_u64;
        let first = |p: u64, e: u32| key.stream(p, e).random::<f64>();
        let by_particle: Vec<f64> = (0..n).map(|p| first(p, 1)).collect();
        let by_event: Vec<f64> = (0..n as u32).map(|e| first(7, e)).collect();
        let next_event: Vec<f64> = (0..n).map(|p| first(p, 2)).collect();
        for draws in [&by_particle, &by_event] {
            // χ² over 64 bins, 63 degrees of freedom: mean 63, standard deviation 11.2.
            let mut bins = [0.0_f64; 64];
            draws.iter().for_each(|&x| bins[(x * 64.0) as usize] += 1.0);
            let expected = n as f64 / 64.0;
            let chi2: f64 = bins.iter().map(|b| (b - expected).powi(2) / expected).sum();
            assert!(chi2 < 63.0 + 6.0 * 11.2, "χ² = {chi2}");
            // Lag-one correlation within 6 standard errors of 0.
            let r = correlation(&draws[1..], &draws[..draws.len() - 1]);
            assert!(r.abs() < 6.0 / (n as f64).sqrt(), "lag-one correlation {r}");
        }
        let r = correlation(&by_particle, &next_event);
        assert!(r.abs() < 6.0 / (n as f64).sqrt(), "correlation between events {r}");
        // Whole first outputs: 2 × 10⁵ 64-bit words collide with probability about 10⁻⁹.
        let mut words: Vec<u64> =
            (0..n).flat_map(|p| [key.stream(p, 1).next_u64(), key.stream(p, 2).next_u64()]).collect();
        words.sort_unstable();
        words.dedup();
        assert_eq!(words.len(), 2 * n as usize, "two streams start alike");
    }

    /// The key decides the streams: another seed gives other draws.
    #[test]
    fn another_seed_gives_other_streams() {
        let (a, b) = (StreamKey::new(1), StreamKey::new(2));
        let same = (0..1000).filter(|&p| a.stream(p, 0).next_u64() == b.stream(p, 0).next_u64()).count();
        assert_eq!(same, 0);
    }
}
