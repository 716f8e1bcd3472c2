//! The emitter's direction laws against their densities: χ² of 2 × 10⁵ draws in 20 bins of
//! θ/θ_half (19 degrees of freedom; χ² > 50 happens by chance about once in 10⁴ runs).

use spraysim_engine::emission::Direction;
use spraysim_validate::checks::{direction_histogram, solid_angle_bin, truncated_normal_bin};

const N: u64 = 200_000;
const CHI2_LIMIT: f64 = 50.0;

#[test]
fn truncated_normal_matches_its_density_and_a_wrong_sigma_is_detected() {
    let half = 7f64.to_radians();
    let law = Direction::TruncatedNormal { mu: 0.255, sigma: 0.102 };
    let c = direction_histogram(law, half, N, truncated_normal_bin(0.255, 0.102)).chi2;
    assert!(c < CHI2_LIMIT, "χ² = {c}");
    let wrong = Direction::TruncatedNormal { mu: 0.255, sigma: 0.112 };
    let w = direction_histogram(wrong, half, N, truncated_normal_bin(0.255, 0.102)).chi2;
    assert!(w > CHI2_LIMIT, "a σ off by 10 % passed: χ² = {w}");
}

#[test]
fn uniform_polar_is_uniform_in_angle() {
    let c = direction_histogram(Direction::UniformPolar, 0.3, N, |a, b| b - a).chi2;
    assert!(c < CHI2_LIMIT, "χ² = {c}");
}

#[test]
fn uniform_solid_angle_is_uniform_in_cosine() {
    let half: f64 = 0.6;
    let c = direction_histogram(Direction::UniformSolidAngle, half, N, solid_angle_bin(half)).chi2;
    assert!(c < CHI2_LIMIT, "χ² = {c}");
    // The same draws are not uniform in angle.
    let polar = direction_histogram(Direction::UniformSolidAngle, half, N, |a, b| b - a).chi2;
    assert!(polar > CHI2_LIMIT, "χ² = {polar}");
}
