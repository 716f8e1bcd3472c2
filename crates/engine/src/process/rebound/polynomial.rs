//! The paper's rebound curve: a polynomial in the angle of incidence (a fit to Melbye's curves).

use super::ReboundLaw;
use crate::process::ImpactSite;
use std::f64::consts::FRAC_PI_2;

/// `p_r(θ) = Σ cᵢ xⁱ` with `x = θ / 90°`, clamped to `[0, 1]` (θ from the surface normal).
#[derive(Clone, Debug, PartialEq)]
pub struct PolynomialRebound {
    /// Coefficients `c₀, c₁, …`, dimensionless.
    pub coefficients: Vec<f64>,
}

impl PolynomialRebound {
    /// `p_r(θ)` for an angle of incidence `theta` (rad) from the normal.
    pub fn at(&self, theta: f64) -> f64 {
        let x = theta / FRAC_PI_2;
        self.coefficients.iter().rev().fold(0.0, |acc, &ci| acc * x + ci).clamp(0.0, 1.0)
    }
}

impl ReboundLaw for PolynomialRebound {
    fn probability(&self, impact: &ImpactSite) -> f64 {
        self.at(impact.theta)
    }

    fn form(&self) -> super::ReboundForm<'_> {
        super::ReboundForm::Polynomial(self)
    }
}
