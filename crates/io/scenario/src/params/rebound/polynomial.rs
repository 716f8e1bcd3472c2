//! `rebound_model = "polynomial"`: the paper's rebound curve, a polynomial in the angle of
//! incidence.

use super::ReboundModel;
use crate::reader::{Check, Read, Section};
use serde::Serialize;
use spraysim_engine::process::ReboundLaw;
use spraysim_engine::process::rebound::PolynomialRebound;
use std::sync::Arc;

/// Default p_r(θ) coefficients in x = θ/90°: p_r = 0.10 + 2.4 x³. Passes through the public
/// reference points: 10 % at normal incidence (ASA: 5–15 %, about 10 % on average), 12.6 % at
/// 20° (vendors: 5–12 % with the nozzle square to the surface), 40 % at 45° (vendors: 30–50 %
/// once the nozzle is more than 20° off square), and saturates at 1 beyond about 62°.
pub const SHOTCRETE_REBOUND_POLYNOMIAL: [f64; 4] = [0.10, 0.0, 0.0, 2.4];

/// The keys of the polynomial law: p_r = Σ cᵢ xⁱ with x = θ/90°, clamped to [0, 1].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PolynomialLaw {
    /// Coefficients c₀, c₁, …, dimensionless.
    pub rebound_polynomial: Vec<f64>,
}

/// Reads `rebound_polynomial`: 1 to 16 coefficients (`default` when absent).
pub(super) fn read_polynomial(s: &Section<'_>, default: &[f64]) -> Read<Vec<f64>> {
    s.list("rebound_polynomial", Some(default.to_vec()), 16, Check::Within(-1e6, 1e6))
}

impl ReboundModel for PolynomialLaw {
    /// The shotcrete curve, [`SHOTCRETE_REBOUND_POLYNOMIAL`].
    fn defaults() -> Self {
        PolynomialLaw { rebound_polynomial: SHOTCRETE_REBOUND_POLYNOMIAL.to_vec() }
    }

    fn read_over(s: &Section<'_>, d: &Self) -> Read<Self> {
        Ok(PolynomialLaw { rebound_polynomial: read_polynomial(s, &d.rebound_polynomial)? })
    }

    fn law(&self) -> Arc<dyn ReboundLaw> {
        Arc::new(PolynomialRebound { coefficients: self.rebound_polynomial.clone() })
    }

    fn notes(&self) -> &'static [(&'static str, &'static str)] {
        &[("rebound_polynomial", "p_r = Σ cᵢ (θ/90°)ⁱ, θ from the normal (cushion: the ricochet share)")]
    }
}
