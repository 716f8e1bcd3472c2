//! Forced rebound (abrasive blasting: the paper bypasses the angle curve with p_r ≡ 1).

use super::ReboundLaw;
use crate::process::ImpactSite;

/// `p_r ≡ 1`: every impact rebounds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AlwaysRebound;

impl ReboundLaw for AlwaysRebound {
    fn probability(&self, _impact: &ImpactSite) -> f64 {
        1.0
    }

    fn form(&self) -> super::ReboundForm<'_> {
        super::ReboundForm::Always
    }
}
