//! Rebound laws: the probability p_r that an impact rebounds (before the anti-adhesion factor
//! α scales it), one law per file.

mod always;
mod cushion;
mod never;
mod polynomial;

pub use always::AlwaysRebound;
pub use cushion::CushionCapture;
pub use never::NeverRebound;
pub use polynomial::PolynomialRebound;

use super::ImpactSite;

/// The angle-dependent part of the stick-or-rebound decision: `P(rebound) = α · p_r · m`, where
/// this law gives p_r and the [`super::ImpactModel`] the rest. Implementations must be pure
/// functions of the impact (they run in parallel, and results must not depend on the order).
pub trait ReboundLaw: Send + Sync + std::fmt::Debug {
    /// p_r for this impact, in `[0, 1]`.
    fn probability(&self, impact: &ImpactSite) -> f64;

    /// Which built-in law this is, with its parameters, for a backend that evaluates the laws
    /// itself (the GPU's kernels); [`ReboundForm::Opaque`] (the default) for a law known only
    /// through [`ReboundLaw::probability`], which such a backend refuses.
    fn form(&self) -> ReboundForm<'_> {
        ReboundForm::Opaque
    }
}

/// A built-in rebound law as plain parameters (see [`ReboundLaw::form`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ReboundForm<'a> {
    /// p_r ≡ 1 ([`AlwaysRebound`]).
    Always,
    /// p_r ≡ 0 ([`NeverRebound`]).
    Never,
    /// The polynomial in θ / 90° ([`PolynomialRebound`]).
    Polynomial(&'a PolynomialRebound),
    /// The cushion law ([`CushionCapture`]).
    Cushion(&'a CushionCapture),
    /// A law defined outside the engine.
    Opaque,
}
