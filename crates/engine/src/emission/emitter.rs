//! Particle emission: nozzle aperture shapes, speed sampling and spray-cone direction
//! distributions (the paper's Emitter, Figures 2 and 3).

use super::NozzleFrame;
use glam::DVec3;
use rand::Rng;
use std::f64::consts::TAU;

/// How emission directions spread within the spray cone of half-angle θ_half; angles in rad.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Direction {
    /// θ = θ_half · s, s ~ U(0, 1): uniform in polar angle, concentrated at the axis (Fig. 3a).
    UniformPolar,
    /// θ = θ_half · s, s ~ N(μ, σ) truncated to `[0, 1]` (Fig. 3b); μ and σ in units of θ_half.
    TruncatedNormal {
        /// Mean μ of s, in units of θ_half (0: the axis, 1: the cone's edge).
        mu: f64,
        /// Standard deviation σ of s, in units of θ_half.
        sigma: f64,
    },
    /// Uniform over the cone's solid angle: uniform flux per steradian.
    UniformSolidAngle,
    /// Fan: uniform angles in two planes, `wide` along the nozzle's width axis and `narrow`
    /// across it (full angles, rad); the cone half-angle plays no part.
    Fan {
        /// Full angle along the width axis, rad.
        wide: f64,
        /// Full angle across it, rad.
        narrow: f64,
    },
}

/// Shape of the nozzle's aperture, in the plane perpendicular to the spray axis; dimensions
/// in m. Start positions are uniform over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Aperture {
    /// All particles start at the nozzle point (air spray gun).
    Point,
    /// Disk of radius `r`, m.
    Circle {
        /// Radius, m.
        r: f64,
    },
    /// Rectangle with half sizes along the width and height axes, m.
    Rectangle {
        /// Half width, m.
        hw: f64,
        /// Half height, m.
        hh: f64,
    },
    /// Ring between radii `r_in` and `r_out`, m.
    Annulus {
        /// Inner radius, m.
        r_in: f64,
        /// Outer radius, m.
        r_out: f64,
    },
}

/// A nozzle's emitter: where particles start, how fast and in which directions, how many and
/// how much material each carries.
#[derive(Clone, Debug, PartialEq)]
pub struct Emitter {
    /// Where on the nozzle particles start: a point or an opening of some shape.
    pub aperture: Aperture,
    /// How the emission directions spread within the cone.
    pub direction: Direction,
    /// Half of the full cone angle, rad.
    pub cone_half_angle: f64,
    /// Speed range, m/s.
    pub speed: [f64; 2],
    /// Particles per second while spraying.
    pub spawn_rate: f64,
    /// Material volume carried by each particle, m³ (= flow rate / spawn rate).
    pub particle_volume: f64,
    /// The sizes of the droplets (or grains) the particles stand for, by volume (`None`: not
    /// modelled). Every particle carries `particle_volume` whatever its diameter (see
    /// [`super::DropletSizes`]); the diameter sets its drag in the gun's air.
    pub droplets: Option<super::SizeDistribution>,
}

impl Emitter {
    /// Number of particles to emit over `dt` seconds, given the fractional remainder `carry`
    /// of the steps before (updated). The remainder carries over, so the count over any
    /// duration is `floor(rate × duration)` or one more, never drifting.
    pub fn spawn_count(&self, dt: f64, carry: &mut f64) -> u64 {
        let want = self.spawn_rate * dt + *carry;
        let n = want.floor();
        *carry = want - n;
        n as u64
    }

    /// Samples a start position (m) and velocity (m/s) in the nozzle's frame.
    pub fn sample<R: Rng>(&self, frame: &NozzleFrame, rng: &mut R) -> (DVec3, DVec3) {
        self.sampler().sample(frame, rng)
    }

    /// The emitter's draws with what they share worked out once, for drawing many particles:
    /// each is the same as [`Emitter::sample`]'s.
    pub fn sampler(&self) -> Sampler<'_> {
        let normal = match self.direction {
            Direction::TruncatedNormal { mu, sigma } => Some(TruncatedNormal::new(mu, sigma)),
            _ => None,
        };
        Sampler { emitter: self, normal }
    }
}

/// Draws of an [`Emitter`] (see [`Emitter::sampler`]).
#[derive(Clone, Copy, Debug)]
pub struct Sampler<'a> {
    emitter: &'a Emitter,
    /// The truncated normal of the direction distribution, if it is one.
    normal: Option<TruncatedNormal>,
}

impl Sampler<'_> {
    /// Samples a start position (m) and velocity (m/s) in the nozzle's frame.
    pub fn sample<R: Rng>(&self, frame: &NozzleFrame, rng: &mut R) -> (DVec3, DVec3) {
        let e = self.emitter;
        let (du, dw) = e.sample_aperture(rng);
        let pos = frame.position + frame.width_axis * du + frame.height_axis * dw;
        let dir = e.sample_direction(frame, self.normal.as_ref(), rng);
        let speed = e.speed[0] + (e.speed[1] - e.speed[0]) * rng.random::<f64>();
        (pos, dir * speed)
    }
}

impl Emitter {
    fn sample_aperture<R: Rng>(&self, rng: &mut R) -> (f64, f64) {
        match self.aperture {
            Aperture::Point => (0.0, 0.0),
            Aperture::Rectangle { hw, hh } => {
                (hw * (2.0 * rng.random::<f64>() - 1.0), hh * (2.0 * rng.random::<f64>() - 1.0))
            }
            Aperture::Circle { r } => polar_point(0.0, r, rng),
            Aperture::Annulus { r_in, r_out } => polar_point(r_in, r_out, rng),
        }
    }

    /// A direction; `normal` is the truncated normal of [`Direction::TruncatedNormal`].
    fn sample_direction<R: Rng>(
        &self,
        frame: &NozzleFrame,
        normal: Option<&TruncatedNormal>,
        rng: &mut R,
    ) -> DVec3 {
        let half = self.cone_half_angle;
        let theta = match self.direction {
            Direction::Fan { wide, narrow } => {
                let a = wide * (rng.random::<f64>() - 0.5);
                let b = narrow * (rng.random::<f64>() - 0.5);
                let d = frame.axis + frame.width_axis * a.tan() + frame.height_axis * b.tan();
                return d.normalize();
            }
            Direction::UniformPolar => half * rng.random::<f64>(),
            Direction::UniformSolidAngle => {
                (1.0 - rng.random::<f64>() * (1.0 - half.cos())).clamp(-1.0, 1.0).acos()
            }
            Direction::TruncatedNormal { mu, sigma } => {
                let u = rng.random::<f64>();
                half * normal.map_or_else(|| TruncatedNormal::new(mu, sigma).at(u), |n| n.at(u))
            }
        };
        let phi = TAU * rng.random::<f64>();
        let (s, c) = theta.sin_cos();
        frame.axis * c + (frame.width_axis * phi.cos() + frame.height_axis * phi.sin()) * s
    }
}

/// Uniform point on a ring of radii `[r0, r1]` (m), as offsets along the frame's two axes.
fn polar_point<R: Rng>(r0: f64, r1: f64, rng: &mut R) -> (f64, f64) {
    let r = (r0 * r0 + rng.random::<f64>() * (r1 * r1 - r0 * r0)).sqrt();
    let phi = TAU * rng.random::<f64>();
    (r * phi.cos(), r * phi.sin())
}

/// A draw from N(μ, σ) truncated to `[0, 1]`, by inverting its distribution function.
///
/// One uniform per draw, mapped monotonically: with the same random stream, a small change of
/// μ or σ moves each particle's angle a little, so an objective built on a fixed seed (common
/// random numbers, as in calibration) is continuous in μ and σ. Rejection sampling would not be.
pub fn truncated_normal_unit<R: Rng>(mu: f64, sigma: f64, rng: &mut R) -> f64 {
    let u = rng.random::<f64>();
    TruncatedNormal::new(mu, sigma).at(u)
}

/// N(μ, σ) truncated to `[0, 1]`, with the probabilities at its bounds worked out once (see
/// [`truncated_normal_unit`]).
#[derive(Clone, Copy, Debug)]
struct TruncatedNormal {
    mu: f64,
    sigma: f64,
    /// The distribution function (or, in the upper tail, the survival function) at 0 and 1.
    ends: (f64, f64),
    /// Whether `ends` are survival probabilities.
    upper: bool,
}

impl TruncatedNormal {
    fn new(mu: f64, sigma: f64) -> TruncatedNormal {
        let (a, b) = (-mu / sigma, (1.0 - mu) / sigma);
        // Work in whichever tail keeps the probabilities away from 1, where they lose digits.
        let upper = a > 0.0;
        let ends = if upper { (normal_sf(a), normal_sf(b)) } else { (normal_cdf(a), normal_cdf(b)) };
        TruncatedNormal { mu, sigma, ends, upper }
    }

    /// The draw for the uniform number `u` in `[0, 1)`.
    fn at(&self, u: f64) -> f64 {
        let (mu, sigma) = (self.mu, self.sigma);
        if sigma.is_nan() || sigma <= 0.0 {
            return mu.clamp(0.0, 1.0);
        }
        let x = if self.upper {
            let (qa, qb) = self.ends;
            -inverse_normal_cdf(qa - u * (qa - qb))
        } else {
            let (pa, pb) = self.ends;
            inverse_normal_cdf(pa + u * (pb - pa))
        };
        (mu + sigma * x).clamp(0.0, 1.0)
    }
}

/// Probability that N(μ, σ) falls in `[0, 1]`, the truncated normal's acceptance rate.
pub fn truncated_normal_mass(mu: f64, sigma: f64) -> f64 {
    normal_cdf((1.0 - mu) / sigma) - normal_cdf(-mu / sigma)
}

/// Standard normal cumulative distribution function.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// Standard normal survival function, 1 − Φ(x), accurate in the upper tail.
pub fn normal_sf(x: f64) -> f64 {
    0.5 * libm::erfc(x / std::f64::consts::SQRT_2)
}

/// Inverse of the standard normal distribution function, Φ⁻¹(p), for p in (0, 1); ±∞ at the
/// ends. Acklam's rational approximation (relative error 1.2e-9) polished by one Halley step on
/// `erfc`, which brings it to a few ulps.
pub fn inverse_normal_cdf(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549671464120693,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [7.784695709041462e-3, 3.224671290700398e-1, 2.445134137142996, 3.754408661907416];
    const LOW: f64 = 0.02425;
    if p.is_nan() || p <= 0.0 {
        return if p == 0.0 { f64::NEG_INFINITY } else { f64::NAN };
    }
    if p >= 1.0 {
        return if p == 1.0 { f64::INFINITY } else { f64::NAN };
    }
    let tail = |q: f64| {
        let t = (-2.0 * q.ln()).sqrt();
        (((((C[0] * t + C[1]) * t + C[2]) * t + C[3]) * t + C[4]) * t + C[5])
            / ((((D[0] * t + D[1]) * t + D[2]) * t + D[3]) * t + 1.0)
    };
    let x = if p < LOW {
        tail(p)
    } else if p > 1.0 - LOW {
        -tail(1.0 - p)
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    // Halley's step on f(x) = Φ(x) − p, with f' = φ(x) and f'' = −x φ(x).
    let e = normal_cdf(x) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (0.5 * x * x).exp();
    x - u / (1.0 + 0.5 * x * u)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn apertures_and_speeds_stay_within_bounds() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let f = NozzleFrame::new(DVec3::ZERO, DVec3::Z, 0.0);
        for aperture in [
            Aperture::Circle { r: 0.02 },
            Aperture::Annulus { r_in: 0.01, r_out: 0.03 },
            Aperture::Rectangle { hw: 0.1, hh: 0.01 },
        ] {
            let e = Emitter {
                aperture,
                direction: Direction::Fan { wide: 1.0, narrow: 0.2 },
                cone_half_angle: 0.5,
                speed: [20.0, 30.0],
                spawn_rate: 1.0,
                particle_volume: 1.0,
                droplets: None,
            };
            let mut mean_r2 = 0.0;
            for _ in 0..10_000 {
                let (p, v) = e.sample(&f, &mut rng);
                assert!(p.z == 0.0 && (20.0..=30.0).contains(&v.length()));
                let (a, b) = (v.x.atan2(v.z), v.y.atan2(v.z));
                assert!(a.abs() <= 0.5 + 1e-12 && b.abs() <= 0.1 + 1e-12, "outside the fan");
                let r = p.truncate().length();
                match aperture {
                    Aperture::Circle { r: rr } => assert!(r <= rr),
                    Aperture::Annulus { r_in, r_out } => assert!(r >= r_in - 1e-15 && r <= r_out + 1e-15),
                    Aperture::Rectangle { hw, hh } => assert!(p.x.abs() <= hw && p.y.abs() <= hh),
                    Aperture::Point => {}
                }
                mean_r2 += r * r / 10_000.0;
            }
            // Uniform over the area: E[r²] = (r_in² + r_out²) / 2 for rings.
            if let Aperture::Annulus { r_in, r_out } = aperture {
                let expected = (r_in * r_in + r_out * r_out) / 2.0;
                assert!((mean_r2 / expected - 1.0).abs() < 0.02, "{mean_r2} vs {expected}");
            }
        }
    }

    #[test]
    fn the_spawn_count_carries_its_remainder_and_never_drifts() {
        let e = Emitter {
            aperture: Aperture::Point,
            direction: Direction::UniformPolar,
            cone_half_angle: 0.1,
            speed: [1.0, 1.0],
            spawn_rate: 333.3,
            particle_volume: 1.0,
            droplets: None,
        };
        let mut carry = 0.0;
        let total: u64 = (0..1000).map(|_| e.spawn_count(1e-3, &mut carry)).sum();
        assert!(total == 333 || total == 334, "{total}");
    }
}
