//! Oka's erosion model.

use super::ErosionLaw;

/// Oka's model: `V = g(γ) · E90 · m`, with `E90 = e90 (v / v_ref)^k₂ (d / d_ref)^k₃`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oka {
    /// E90 at the reference speed and grain size, m³/kg.
    pub e90: f64,
    /// Angle exponent n₁.
    pub n1: f64,
    /// Angle exponent n₂.
    pub n2: f64,
    /// Vickers hardness of the target, GPa.
    pub hv: f64,
    /// Speed exponent k₂.
    pub k2: f64,
    /// Grain-size exponent k₃.
    pub k3: f64,
    /// Reference speed, m/s.
    pub v_ref: f64,
    /// Reference grain diameter, m.
    pub d_ref: f64,
    /// Diameter of the abrasive grains, m.
    pub grain_diameter: f64,
}

/// Oka's angle function g(γ) = (sin γ)^n₁ (1 + Hv (1 − sin γ))^n₂, γ from the surface (rad).
pub fn oka_g(gamma: f64, n1: f64, n2: f64, hv: f64) -> f64 {
    let s = gamma.sin().max(0.0);
    s.powf(n1) * (1.0 + hv * (1.0 - s)).powf(n2)
}

impl ErosionLaw for Oka {
    fn removed_volume(&self, mass: f64, speed: f64, gamma: f64) -> f64 {
        let e90 =
            self.e90 * (speed / self.v_ref).powf(self.k2) * (self.grain_diameter / self.d_ref).powf(self.k3);
        oka_g(gamma, self.n1, self.n2, self.hv) * e90 * mass
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn oka_is_largest_at_normal_incidence_for_hard_erodents_on_soft_targets() {
        assert!((oka_g(std::f64::consts::FRAC_PI_2, 0.71, 2.4, 1.6) - 1.0).abs() < 1e-12);
        assert_eq!(oka_g(0.0, 0.71, 2.4, 1.6), 0.0);
    }
}
