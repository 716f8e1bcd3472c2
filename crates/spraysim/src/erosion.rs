//! Erosion by abrasive impacts: how much material one impact removes (the Finnie and Oka
//! models of physics-notes.md), applied to a target's coating and recorded as an erosion map.

use crate::scenario::{ErosionModel, ErosionParams};

/// Finnie's angle function f(γ) for ductile targets, γ the impact angle from the surface (rad):
/// sin 2γ − 3 sin²γ up to tan γ = 1/3, cos²γ / 3 beyond; its peak lies near 17°, and it is zero
/// at 90°.
pub fn finnie_f(gamma: f64) -> f64 {
    if gamma.tan() <= 1.0 / 3.0 {
        (2.0 * gamma).sin() - 3.0 * gamma.sin().powi(2)
    } else {
        gamma.cos().powi(2) / 3.0
    }
}

/// Oka's angle function g(γ) = (sin γ)^n₁ (1 + Hv (1 − sin γ))^n₂, γ from the surface (rad).
pub fn oka_g(gamma: f64, n1: f64, n2: f64, hv: f64) -> f64 {
    let s = gamma.sin().max(0.0);
    s.powf(n1) * (1.0 + hv * (1.0 - s)).powf(n2)
}

/// Volume (m³) one impact of `mass` (kg) at `speed` (m/s) and `gamma` (rad from the surface)
/// removes.
pub fn removed_volume(p: &ErosionParams, mass: f64, speed: f64, gamma: f64) -> f64 {
    match p.model {
        ErosionModel::None => 0.0,
        ErosionModel::Finnie => p.finnie_k * mass * speed * speed * finnie_f(gamma).max(0.0),
        ErosionModel::Oka => {
            let e90 = p.oka_e90
                * (speed / p.oka_v_ref).powf(p.oka_k2)
                * (p.grain_diameter / p.oka_d_ref).powf(p.oka_k3);
            oka_g(gamma, p.oka_n1, p.oka_n2, p.oka_hv) * e90 * mass
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finnie_peaks_near_17_degrees_and_vanishes_at_normal_incidence() {
        let (mut best, mut at) = (0.0, 0.0);
        for k in 0..=9000 {
            let g = (k as f64 / 100.0).to_radians();
            if finnie_f(g) > best {
                best = finnie_f(g);
                at = k as f64 / 100.0;
            }
        }
        assert!((at - 17.0).abs() < 1.0, "peak at {at}°");
        assert!(finnie_f(90f64.to_radians()).abs() < 1e-15);
        assert_eq!(finnie_f(0.0), 0.0);
        // Continuous where the two branches meet (tan γ = 1/3).
        let joint = (1.0f64 / 3.0).atan();
        assert!((finnie_f(joint - 1e-9) - finnie_f(joint + 1e-9)).abs() < 1e-6);
    }

    #[test]
    fn oka_is_largest_at_normal_incidence_for_hard_erodents_on_soft_targets() {
        assert!((oka_g(std::f64::consts::FRAC_PI_2, 0.71, 2.4, 1.6) - 1.0).abs() < 1e-12);
        assert_eq!(oka_g(0.0, 0.71, 2.4, 1.6), 0.0);
    }
}
