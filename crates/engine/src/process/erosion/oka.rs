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

impl Oka {
    /// Oka's model for silica-like grit on a material of Vickers hardness `hv` (GPa), with the
    /// angle and speed exponents of Oka et al. (Wear 259, 2005) fitted on hardness: n₁ = 0.71
    /// Hv^0.14, n₂ = 2.4 Hv^−0.94, k₂ = 2.3 Hv^0.038. `e90` (m³/kg) is the volume removed per
    /// kg at normal incidence, `v_ref` (m/s) and `d_ref` (m); `k3` the grain-size exponent;
    /// `grain_diameter` (m) that of the grit used.
    pub fn for_hardness(hv: f64, e90: f64, v_ref: f64, d_ref: f64, k3: f64, grain_diameter: f64) -> Oka {
        Oka {
            e90,
            n1: 0.71 * hv.powf(0.14),
            n2: 2.4 * hv.powf(-0.94),
            hv,
            k2: 2.3 * hv.powf(0.038),
            k3,
            v_ref,
            d_ref,
            grain_diameter,
        }
    }
}

impl ErosionLaw for Oka {
    fn form(&self) -> super::ErosionForm<'_> {
        super::ErosionForm::Oka(self)
    }

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
    fn a_soft_coat_erodes_most_at_shallow_angles_and_steel_nearer_square() {
        // The angle of largest wear, from the hardness-fitted exponents (Oka et al. 2005: soft,
        // ductile materials peak at shallow angles; harder ones closer to normal incidence).
        let peak = |hv: f64| {
            let law = Oka::for_hardness(hv, 1.0, 104.0, 326e-6, 0.19, 326e-6);
            (1..900).map(|k| f64::from(k) / 10.0).max_by(|a, b| {
                let g = |deg: f64| law.removed_volume(1.0, 104.0, deg.to_radians());
                g(*a).total_cmp(&g(*b))
            })
        };
        let (coat, steel) = (peak(0.2).unwrap_or(0.0), peak(1.4).unwrap_or(0.0));
        assert!((14.0..22.0).contains(&coat) && (25.0..40.0).contains(&steel), "{coat}° vs {steel}°");
    }

    #[test]
    fn oka_is_largest_at_normal_incidence_for_hard_erodents_on_soft_targets() {
        assert!((oka_g(std::f64::consts::FRAC_PI_2, 0.71, 2.4, 1.6) - 1.0).abs() < 1e-12);
        assert_eq!(oka_g(0.0, 0.71, 2.4, 1.6), 0.0);
    }
}
