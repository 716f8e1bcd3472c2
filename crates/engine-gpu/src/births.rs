//! The newborns of a call, laid out for the `born` kernel (`births.wgsl`), which samples each
//! one's start in its slot on the GPU: the emitter's laws, and each step's batch of births (its
//! ids and the nozzle's pose), in words of the member's own table. Only these words cross to
//! the GPU, not the newborns.

use crate::GpuError;
use crate::pack::{put_f, put_v};
use spraysim_engine::emission::{Aperture, Direction, Emitter, normal_cdf, normal_sf};
use spraysim_engine::pipeline::FlightJob;

/// Words of the emitter's laws.
pub const EMITTER_WORDS: usize = 16;
/// Words of one step's batch of births.
pub const BATCH_WORDS: usize = 20;

/// A call's births as the kernel reads them.
#[derive(Debug)]
pub struct BirthWords {
    /// The emitter's words, then each batch's.
    pub words: Vec<u32>,
    /// Batches of births (steps that spray).
    pub batches: u32,
    /// Newborns in all of them.
    pub newborns: u32,
}

/// The births of `job` laid out: the emitter's words, then per batch its birth step, first id,
/// count, the index of its first newborn among the call's, the nozzle's position, axis, width
/// and height axes, and the velocity added to each newborn (m, m/s).
pub fn words(job: &FlightJob<'_>) -> Result<BirthWords, GpuError> {
    let mut words = emitter_words(&job.config.emitter).to_vec();
    let mut newborns = 0u32;
    let too_large = |what: &str| GpuError::TooLarge(format!("{what} of a call's births beyond 32 bits"));
    for b in job.births.iter().filter(|b| b.count > 0) {
        let mut w = [0u32; BATCH_WORDS];
        w[0] = u32::try_from(b.step).map_err(|_| too_large("a step"))?;
        w[1] = u32::try_from(b.first).map_err(|_| too_large("an id"))?;
        w[2] = u32::try_from(b.count).map_err(|_| too_large("a count"))?;
        w[3] = newborns;
        newborns = newborns.checked_add(w[2]).ok_or_else(|| too_large("the count"))?;
        let f = &b.frame;
        put_v(&mut w, 4, f.position);
        put_v(&mut w, 7, f.axis);
        put_v(&mut w, 10, f.width_axis);
        put_v(&mut w, 13, f.height_axis);
        put_v(&mut w, 16, b.carried);
        words.extend_from_slice(&w);
    }
    let batches = ((words.len() - EMITTER_WORDS) / BATCH_WORDS) as u32;
    Ok(BirthWords { words, batches, newborns })
}

/// The emitter's laws: the aperture (0 a point, 1 a disc of radius r, 2 a rectangle of half
/// sizes, 3 a ring of radii, m) and its two sizes; the direction law (0 uniform in polar angle,
/// 1 a truncated normal, 2 uniform in solid angle, 3 a fan), the cone's half-angle (rad) and
/// 1 − its cosine; the truncated normal's μ, σ, its distribution function at 0 and 1 and
/// whether those are survival probabilities (as the engine's sampler works them out); the fan's
/// full angles (rad); the speed range (m/s).
fn emitter_words(e: &Emitter) -> [u32; EMITTER_WORDS] {
    let mut w = [0u32; EMITTER_WORDS];
    let (kind, a, b) = match e.aperture {
        Aperture::Point => (0, 0.0, 0.0),
        Aperture::Circle { r } => (1, r, 0.0),
        Aperture::Rectangle { hw, hh } => (2, hw, hh),
        Aperture::Annulus { r_in, r_out } => (3, r_in, r_out),
    };
    w[0] = kind;
    put_f(&mut w, 1, a);
    put_f(&mut w, 2, b);
    let half = e.cone_half_angle;
    put_f(&mut w, 4, half);
    // 1 − cos θ without the cancellation near the axis.
    put_f(&mut w, 5, 2.0 * (0.5 * half).sin().powi(2));
    w[3] = match e.direction {
        Direction::UniformPolar => 0,
        Direction::TruncatedNormal { mu, sigma } => {
            let (lo, hi) = (-mu / sigma, (1.0 - mu) / sigma);
            // The tail that keeps the probabilities away from 1, as the engine's sampler.
            let upper = lo > 0.0;
            let ends = if upper { (normal_sf(lo), normal_sf(hi)) } else { (normal_cdf(lo), normal_cdf(hi)) };
            put_f(&mut w, 6, mu);
            put_f(&mut w, 7, sigma);
            put_f(&mut w, 8, ends.0);
            put_f(&mut w, 9, ends.1);
            w[10] = u32::from(upper);
            1
        }
        Direction::UniformSolidAngle => 2,
        Direction::Fan { wide, narrow } => {
            put_f(&mut w, 11, wide);
            put_f(&mut w, 12, narrow);
            3
        }
    };
    put_f(&mut w, 13, e.speed[0]);
    put_f(&mut w, 14, e.speed[1]);
    w
}
