//! The rebound laws a scenario names in `rebound_model` (in `[process.impact]` and a surface's
//! `impact` table), tagged by that key.
//!
//! Each law is a file here declaring its keys (units and defaults), how they are read and
//! written back, and the engine's law it builds; the list in [`ReboundParams`] names each once.
//! A new law is its file, its `mod` line and its line in that list (and the law itself, in the
//! engine's `process::rebound`, unless an existing one serves).

mod always;
mod cushion;
mod never;
mod polynomial;
#[cfg(test)]
mod threshold;

pub use always::AlwaysLaw;
pub use cushion::CushionLaw;
pub use never::NeverLaw;
pub use polynomial::{PolynomialLaw, SHOTCRETE_REBOUND_POLYNOMIAL};

use super::registry::{Variant, kinds};
use crate::reader::{Read, Section};
use spraysim_engine::process::ReboundLaw;
use std::sync::Arc;

/// What each rebound law declares besides its keys: their defaults and the engine's law.
pub(crate) trait ReboundModel {
    /// The law's keys when neither the file nor the process gives them.
    fn defaults() -> Self
    where
        Self: Sized;

    /// Reads the law's keys from an impact table, each over its value in `d` when absent.
    fn read_over(s: &Section<'_>, d: &Self) -> Read<Self>
    where
        Self: Sized;

    /// Reads the law's keys from an impact table over `given` (the process's law, for a
    /// surface's table) where it is this law, else over the law's defaults.
    fn read(s: &Section<'_>, given: Option<&ReboundParams>) -> Read<Self>
    where
        Self: Sized + Clone + Variant<ReboundParams>,
    {
        Self::read_over(s, &given.and_then(Self::of).cloned().unwrap_or_else(Self::defaults))
    }

    /// The engine's law.
    fn law(&self) -> Arc<dyn ReboundLaw>;

    /// The meaning (and unit) of each of the law's keys, for the commented presets
    /// ([`crate::presets_toml`]).
    fn notes(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }
}

kinds! {
    /// The rebound curve p_r(θ), θ from the surface normal.
    pub enum ReboundParams, tagged "rebound_model", kinds ReboundKind, read with Option<&ReboundParams>,
        as dyn ReboundModel {
        /// p_r = Σ cᵢ xⁱ with x = θ/90°, clamped to [0, 1].
        "polynomial" => Polynomial(PolynomialLaw),
        /// Cushion capture: mortar sticks; an aggregate grain bounces off a plastic layer thinner
        /// than `capture_ratio` × its diameter, and ricochets off a thicker one with the share
        /// `rebound_polynomial` of the angle curve.
        "cushion" => Cushion(CushionLaw),
        /// p_r ≡ 1 (forced rebound).
        "always" => Always(AlwaysLaw),
        /// p_r ≡ 0.
        "never" => Never(NeverLaw),
        /// A law only the tests know: it shows that a new law is its file and this line.
        #[cfg(test)]
        "threshold" => Threshold(threshold::ThresholdLaw),
    }
}

impl ReboundParams {
    /// The engine's rebound law.
    pub fn law(&self) -> Arc<dyn ReboundLaw> {
        self.as_dyn().law()
    }
}
