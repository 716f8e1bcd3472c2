//! Droplet (or grain) sizes: the distribution an emitter's particles are drawn from, and the
//! diameter of each particle, found again from its id whenever it is needed.
//!
//! # What a particle's size means
//!
//! A particle is a *parcel*: it stands for many droplets of one diameter. Every parcel from the
//! nozzle carries the same volume (flow rate / spawn rate), so the emitted volume is exactly
//! the flow rate times the spraying time and every map stays mass-exact; the diameter sets how
//! many droplets a parcel stands for and how it moves through the air (its Stokes relaxation
//! time), not its volume. Equal-volume parcels must therefore take their diameters from the
//! *volume-weighted* distribution: the share of the sprayed volume carried by droplets of each
//! size, which is also what laser-diffraction sizers measure and Rosin–Rammler fits describe.
//!
//! # How a diameter is drawn, and why it is not stored
//!
//! The particle record is full (48 bytes), and a diameter is needed at every step a particle
//! flies through the air, so it must be cheap to find again: the distribution is tabulated at
//! [`TABLE`] quantiles `(k + ½) / TABLE`, and particle `id` takes entry
//! `bitrev(id mod TABLE) XOR scramble(seed, id / TABLE)`. Within each block of [`TABLE`]
//! consecutive ids every quantile is used exactly once, and the bit reversal spreads the first
//! 2^m particles of a block over 2^m equal strata of the distribution, so even a short run, or
//! one step's births, samples all sizes in proportion; the scramble, keyed by the seed and the
//! block, changes which particle gets which size from block to block. The table's midpoint
//! quantiles leave out the outer 1/(2·[`TABLE`]) of each tail (0.2 %), whose volume is split
//! over the rest.

use crate::emission::inverse_normal_cdf;
use crate::particles::StreamKey;

/// Quantiles a size distribution is tabulated at: 256, so that a particle's entry is a byte of
/// its id, bit-reversed (see the module's docs).
pub const TABLE: usize = 256;

const _: () = assert!(TABLE == 1 << u8::BITS);

/// The volume-weighted distribution of droplet diameters an emitter sprays, each named by its
/// Sauter mean diameter D₃₂ (the diameter of a droplet with the spray's volume-to-surface
/// ratio: the figure atomiser data sheets and spray studies quote), m.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SizeDistribution {
    /// Every droplet has this diameter, m.
    Fixed {
        /// Diameter, m.
        diameter: f64,
    },
    /// Log-normal in number, with geometric standard deviation σ_g (> 1): in volume it is the
    /// log-normal of the same σ_g with volume median D_v50 = D₃₂ · exp(½ ln²σ_g).
    LogNormal {
        /// Sauter mean diameter D₃₂, m.
        sauter_mean: f64,
        /// Geometric standard deviation σ_g, dimensionless (> 1).
        gsd: f64,
    },
    /// Rosin–Rammler in volume: the share of the volume in droplets larger than d is
    /// exp(−(d/X)ⁿ), with spread exponent n (> 1) and X = D₃₂ · Γ(1 − 1/n).
    RosinRammler {
        /// Sauter mean diameter D₃₂, m.
        sauter_mean: f64,
        /// Spread exponent n, dimensionless (> 1; larger is narrower).
        spread: f64,
    },
}

impl SizeDistribution {
    /// The diameter (m) below which the share `u` (in (0, 1)) of the sprayed volume lies.
    pub fn volume_quantile(&self, u: f64) -> f64 {
        match *self {
            SizeDistribution::Fixed { diameter } => diameter,
            SizeDistribution::LogNormal { sauter_mean, gsd } => {
                let s = gsd.ln();
                sauter_mean * (0.5 * s * s + s * inverse_normal_cdf(u)).exp()
            }
            SizeDistribution::RosinRammler { sauter_mean, spread } => {
                let x = sauter_mean * libm::tgamma(1.0 - 1.0 / spread);
                x * (-(-u).ln_1p()).powf(1.0 / spread)
            }
        }
    }

    /// The volume median diameter D_v50, m.
    pub fn volume_median(&self) -> f64 {
        self.volume_quantile(0.5)
    }

    /// Checks the parameters: positive, finite diameters under 0.1 m, σ_g in (1, 3], n in
    /// [1.2, 100] (measured sprays lie well inside: σ_g 1.4–2.5, n 1.5–4; wider ones put the
    /// table's largest droplet far beyond the spray). The message names the parameter.
    pub fn check(&self) -> Result<(), String> {
        let diameter = |name: &str, d: f64| {
            if d.is_finite() && d > 0.0 && d <= 0.1 {
                Ok(())
            } else {
                Err(format!("{name} must be a diameter in (0, 0.1] m, got {d}"))
            }
        };
        match *self {
            SizeDistribution::Fixed { diameter: d } => diameter("diameter", d),
            SizeDistribution::LogNormal { sauter_mean, gsd } => {
                diameter("sauter_mean", sauter_mean)?;
                if gsd.is_finite() && gsd > 1.0 && gsd <= 3.0 {
                    Ok(())
                } else {
                    Err(format!("gsd must lie in (1, 3], got {gsd}"))
                }
            }
            SizeDistribution::RosinRammler { sauter_mean, spread } => {
                diameter("sauter_mean", sauter_mean)?;
                if spread.is_finite() && (1.2..=100.0).contains(&spread) {
                    Ok(())
                } else {
                    Err(format!(
                        "spread must lie in [1.2, 100] (n ≤ 1 has no finite Sauter mean), got {spread}"
                    ))
                }
            }
        }
    }
}

/// An emitter's size distribution tabulated for its particles (see the module's docs).
#[derive(Clone, Debug, PartialEq)]
pub struct DropletSizes {
    /// Diameters at the quantiles `(k + ½) / TABLE`, increasing, m.
    diameters: Vec<f64>,
}

impl DropletSizes {
    /// The table of `distribution`.
    pub fn new(distribution: &SizeDistribution) -> DropletSizes {
        let diameters =
            (0..TABLE).map(|k| distribution.volume_quantile((k as f64 + 0.5) / TABLE as f64)).collect();
        DropletSizes { diameters }
    }

    /// The diameters of the table, increasing, m: each stands for 1/[`TABLE`] of the volume.
    pub fn diameters(&self) -> &[f64] {
        &self.diameters
    }

    /// The table entry of the particle with emission index `id`, under the run's `key`.
    #[inline]
    pub fn entry(key: &StreamKey, id: u32) -> usize {
        let within = (id as u8).reverse_bits();
        let scramble = key.word(u64::from(id >> 8)) as u8;
        usize::from(within ^ scramble)
    }

    /// Diameter of the particle with emission index `id`, m.
    #[inline]
    pub fn diameter(&self, key: &StreamKey, id: u32) -> f64 {
        self.diameters[DropletSizes::entry(key, id)]
    }

    /// Sauter mean diameter of the table, m: Σd³/Σd² over droplets, which for equal volume per
    /// entry is 1 / mean(1/d).
    pub fn sauter_mean(&self) -> f64 {
        TABLE as f64 / self.diameters.iter().map(|d| 1.0 / d).sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table reproduces the distribution's Sauter mean (the midpoint rule over 256 strata,
    /// with the outer 0.2 % of each tail left out) and its volume median, and the blocks use
    /// every entry once.
    #[test]
    fn tables_keep_the_sauter_mean_and_use_every_size_once_per_block() {
        for dist in [
            SizeDistribution::LogNormal { sauter_mean: 25e-6, gsd: 1.8 },
            SizeDistribution::RosinRammler { sauter_mean: 60e-6, spread: 2.5 },
            SizeDistribution::Fixed { diameter: 1e-3 },
        ] {
            let table = DropletSizes::new(&dist);
            let d32 = match dist {
                SizeDistribution::Fixed { diameter } => diameter,
                SizeDistribution::LogNormal { sauter_mean, .. }
                | SizeDistribution::RosinRammler { sauter_mean, .. } => sauter_mean,
            };
            assert!((table.sauter_mean() / d32 - 1.0).abs() < 0.01, "{dist:?}: {}", table.sauter_mean());
            let median = 0.5 * (table.diameters()[TABLE / 2 - 1] + table.diameters()[TABLE / 2]);
            assert!((median / dist.volume_median() - 1.0).abs() < 0.02, "{dist:?}");
            assert!(table.diameters().windows(2).all(|w| w[0] <= w[1]));
        }
        let key = StreamKey::new(7);
        for block in [0u32, 1, 4711] {
            let mut seen = [false; TABLE];
            (0..TABLE as u32).for_each(|j| seen[DropletSizes::entry(&key, block * TABLE as u32 + j)] = true);
            assert!(seen.iter().all(|&s| s), "block {block} misses a size");
            // The first 16 of a block fall in 16 different strata of 16 entries.
            let mut strata = [false; 16];
            (0..16u32).for_each(|j| strata[DropletSizes::entry(&key, block * TABLE as u32 + j) / 16] = true);
            assert!(strata.iter().all(|&s| s), "block {block}: the first 16 share a stratum");
        }
    }

    /// The log-normal's D₃₂ = D_v50 · exp(−½ ln²σ_g) and the Rosin–Rammler's
    /// D₃₂ = X / Γ(1 − 1/n), each checked against the moments of its own quantile function.
    #[test]
    fn sauter_means_follow_the_closed_forms() {
        let fine = |dist: SizeDistribution| {
            let n = 200_000;
            let inv: f64 = (0..n).map(|k| 1.0 / dist.volume_quantile((k as f64 + 0.5) / n as f64)).sum();
            n as f64 / inv
        };
        let ln = SizeDistribution::LogNormal { sauter_mean: 30e-6, gsd: 2.0 };
        assert!((fine(ln) / 30e-6 - 1.0).abs() < 2e-3);
        let rr = SizeDistribution::RosinRammler { sauter_mean: 80e-6, spread: 3.0 };
        assert!((fine(rr) / 80e-6 - 1.0).abs() < 2e-3);
        assert!(SizeDistribution::RosinRammler { sauter_mean: 1e-5, spread: 1.0 }.check().is_err());
        assert!(SizeDistribution::LogNormal { sauter_mean: f64::NAN, gsd: 2.0 }.check().is_err());
    }
}
