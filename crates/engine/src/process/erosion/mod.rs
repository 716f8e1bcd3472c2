//! Erosion laws: how much material one abrasive impact removes from a target (the Finnie and
//! Oka models), one law per file. The pipeline applies the removed volume to the struck cell:
//! it deepens the erosion map and wears the coating away.

mod finnie;
mod oka;

pub use finnie::{Finnie, finnie_f};
pub use oka::{Oka, oka_g};

/// Volume removed by one impact. Implementations must be pure functions of the impact.
pub trait ErosionLaw: Send + Sync + std::fmt::Debug {
    /// Volume (m³) one impact of `mass` (kg) at `speed` (m/s) and `gamma` (rad, the impact
    /// angle from the surface) removes.
    fn removed_volume(&self, mass: f64, speed: f64, gamma: f64) -> f64;

    /// Which built-in law this is, with its parameters, for a backend that evaluates the laws
    /// itself (the GPU's kernels); [`ErosionForm::Opaque`] (the default) for a law known only
    /// through [`ErosionLaw::removed_volume`], which such a backend refuses.
    fn form(&self) -> ErosionForm<'_> {
        ErosionForm::Opaque
    }
}

/// A built-in erosion law as plain parameters (see [`ErosionLaw::form`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ErosionForm<'a> {
    /// Finnie's model ([`Finnie`]).
    Finnie(&'a Finnie),
    /// Oka's model ([`Oka`]).
    Oka(&'a Oka),
    /// A law defined outside the engine.
    Opaque,
}
