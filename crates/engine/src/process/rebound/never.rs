//! No rebound: every impact sticks.

use super::ReboundLaw;
use crate::process::ImpactSite;

/// `p_r ≡ 0`: every impact sticks.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NeverRebound;

impl ReboundLaw for NeverRebound {
    fn probability(&self, _impact: &ImpactSite) -> f64 {
        0.0
    }

    fn form(&self) -> super::ReboundForm<'_> {
        super::ReboundForm::Never
    }
}
