//! The free-flight kernel of a step, over f64 lanes: the next position, velocity and age of a
//! block of particles, and whether each stays inside the domain and within its lifetime.
//!
//! The kernel is one plain loop, compiled twice: once with AVX2 and FMA enabled, selected at run
//! time where the processor has them, and once for the target's baseline (the portable
//! fallback). Rust never fuses a multiply and an add unless asked to, and the kernel does not
//! ask, so both builds round every operation alike: their results are bit-identical to each
//! other and to [`Motion::advance`], whatever the instruction set.

use super::Motion;
use crate::collision::Aabb;
use glam::DVec3;

/// Particles in one block of the kernel: its outputs (about 3 KB) stay in the first-level cache
/// until the step's scalar pass reads them.
pub const BLOCK: usize = 64;

/// Instruction sets the kernel can run on.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Lanes {
    /// The target's baseline instructions (SSE2 on x86-64): two f64 lanes.
    Portable,
    /// AVX2 with FMA: four f64 lanes. Used only where the processor has them; elsewhere the
    /// kernel falls back to [`Lanes::Portable`].
    #[default]
    Avx2,
}

impl Lanes {
    /// The instruction set the kernel actually runs when asked for `self` on this processor.
    pub fn effective(self) -> Lanes {
        match self {
            Lanes::Avx2 if avx2() => Lanes::Avx2,
            _ => Lanes::Portable,
        }
    }
}

#[cfg(target_arch = "x86_64")]
fn avx2() -> bool {
    // The standard library caches the answer: a relaxed atomic load after the first call.
    is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")
}

#[cfg(not(target_arch = "x86_64"))]
fn avx2() -> bool {
    false
}

/// What a block of particles would become after one free step.
#[derive(Clone, Debug)]
pub struct Drift {
    /// Position at the end of the step, m.
    pub pos: [DVec3; BLOCK],
    /// Velocity at the end of the step, m/s.
    pub vel: [DVec3; BLOCK],
    /// Age at the end of the step, s, as the swarm stores it.
    pub age: [f32; BLOCK],
    /// True where the end position lies inside the domain and the age (in f64, before
    /// rounding to f32) is within the lifetime.
    pub stays: [bool; BLOCK],
}

impl Default for Drift {
    fn default() -> Drift {
        Drift {
            pos: [DVec3::ZERO; BLOCK],
            vel: [DVec3::ZERO; BLOCK],
            age: [0.0; BLOCK],
            stays: [false; BLOCK],
        }
    }
}

impl Drift {
    /// Fills slot `j` alone with one step of `dt` (s) from position `x`, velocity `v` and age
    /// `age`, in scalar code, exactly as [`drift`] would: for blocks where few particles are
    /// awake.
    #[inline]
    pub fn step_one(
        &mut self,
        j: usize,
        motion: &Motion,
        dt: f64,
        limits: &Limits,
        (x, v, age): (DVec3, DVec3, f32),
    ) {
        let (x1, v1) = motion.advance(x, v, dt);
        let a = f64::from(age) + dt;
        (self.pos[j], self.vel[j], self.age[j]) = (x1, v1, a as f32);
        self.stays[j] = limits.domain.contains(x1) && a <= limits.max_age;
    }
}

/// Limits a particle must stay within to keep flying.
#[derive(Clone, Copy, Debug)]
pub struct Limits {
    /// The domain: particles outside it are retired.
    pub domain: Aabb,
    /// Greatest age, s.
    pub max_age: f64,
}

/// Fills `out` with one step of `dt` (s) of the first `pos.len()` (at most [`BLOCK`]) particles
/// of `pos`, `vel` and `age`, on the instruction set `lanes` (or the portable one where the
/// processor lacks it). Every slot is computed, in flight or not: the caller picks.
///
/// # Panics
/// If the slices differ in length or hold more than [`BLOCK`] particles.
pub fn drift(
    lanes: Lanes,
    motion: &Motion,
    dt: f64,
    limits: &Limits,
    (pos, vel, age): (&[DVec3], &[DVec3], &[f32]),
    out: &mut Drift,
) {
    assert!(pos.len() <= BLOCK && vel.len() == pos.len() && age.len() == pos.len());
    #[cfg(target_arch = "x86_64")]
    if lanes.effective() == Lanes::Avx2 {
        // SAFETY: `effective` has checked that this processor runs AVX2 and FMA.
        unsafe { drift_avx2(motion, dt, limits, (pos, vel, age), out) };
        return;
    }
    let _ = lanes;
    drift_lanes(motion, dt, limits, (pos, vel, age), out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn drift_avx2(
    motion: &Motion,
    dt: f64,
    limits: &Limits,
    slots: (&[DVec3], &[DVec3], &[f32]),
    out: &mut Drift,
) {
    drift_lanes(motion, dt, limits, slots, out);
}

/// The kernel: one loop per case of [`Motion::advance`], so that each is branch-free.
#[inline(always)]
fn drift_lanes(
    motion: &Motion,
    dt: f64,
    limits: &Limits,
    slots: (&[DVec3], &[DVec3], &[f32]),
    out: &mut Drift,
) {
    use super::Integrator::{Euler, Exact, SemiImplicitEuler};
    let g = motion.gravity;
    match (motion.integrator, motion.drag == 0.0) {
        (Euler, true) => each(dt, limits, slots, out, |x, v| (x + v * dt, v + g * dt)),
        (SemiImplicitEuler, true) => each(dt, limits, slots, out, |x, v| {
            let v1 = v + g * dt;
            (x + v1 * dt, v1)
        }),
        (Exact, true) => each(dt, limits, slots, out, |x, v| (x + v * dt + 0.5 * g * dt * dt, v + g * dt)),
        _ => each(dt, limits, slots, out, |x, v| motion.advance(x, v, dt)),
    }
}

#[inline(always)]
fn each(
    dt: f64,
    limits: &Limits,
    (pos, vel, age): (&[DVec3], &[DVec3], &[f32]),
    out: &mut Drift,
    step: impl Fn(DVec3, DVec3) -> (DVec3, DVec3),
) {
    let n = pos.len();
    for ((x1, v1), (&x, &v)) in out.pos[..n].iter_mut().zip(&mut out.vel[..n]).zip(pos.iter().zip(vel)) {
        (*x1, *v1) = step(x, v);
    }
    for (((a1, stays), &a), x1) in
        out.age[..n].iter_mut().zip(&mut out.stays[..n]).zip(age).zip(&out.pos[..n])
    {
        let a = f64::from(a) + dt;
        *a1 = a as f32;
        *stays = limits.domain.contains(*x1) & (a <= limits.max_age);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{GRAVITY, Integrator};
    use rand::{Rng, SeedableRng};

    /// Every build of the kernel gives, bit for bit, what the scalar step gives, block or slot.
    #[test]
    fn every_instruction_set_steps_exactly_as_the_scalar_motion() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let limits =
            Limits { domain: Aabb { min: DVec3::splat(-1.0), max: DVec3::splat(1.0) }, max_age: 0.5 };
        for integrator in [Integrator::Euler, Integrator::SemiImplicitEuler, Integrator::Exact] {
            for drag in [0.0, 0.37] {
                let motion = Motion { gravity: GRAVITY, drag, integrator };
                let n = BLOCK - 3;
                let mut v3 = |s: f64| {
                    DVec3::new(rng.random_range(-s..s), rng.random_range(-s..s), rng.random_range(-s..s))
                };
                let pos: Vec<DVec3> = (0..n).map(|_| v3(1.05)).collect();
                let vel: Vec<DVec3> = (0..n).map(|_| v3(30.0)).collect();
                let age: Vec<f32> = (0..n).map(|k| 0.5 - 1e-3 * (k % 3) as f32).collect();
                let dt = 1.3e-3;
                for lanes in [Lanes::Portable, Lanes::Avx2] {
                    let mut out = Drift::default();
                    drift(lanes, &motion, dt, &limits, (&pos, &vel, &age), &mut out);
                    let mut one = Drift::default();
                    for k in 0..n {
                        one.step_one(k, &motion, dt, &limits, (pos[k], vel[k], age[k]));
                    }
                    assert_eq!(format!("{out:?}"), format!("{one:?}"));
                    for k in 0..n {
                        let (x1, v1) = motion.advance(pos[k], vel[k], dt);
                        let a = f64::from(age[k]) + dt;
                        assert_eq!(
                            (out.pos[k].to_array(), out.vel[k].to_array()),
                            (x1.to_array(), v1.to_array())
                        );
                        assert_eq!(out.age[k].to_bits(), (a as f32).to_bits());
                        assert_eq!(
                            out.stays[k],
                            limits.domain.contains(x1) && a <= limits.max_age,
                            "{lanes:?}"
                        );
                    }
                }
            }
        }
    }
}
