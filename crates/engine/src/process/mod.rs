//! Process behaviour, as small modules tagged by the stage they act in (in the spirit of
//! bevy_hanabi's modifiers). A process (shotcrete, painting, blasting) is a choice of modules
//! and their parameters; a new behaviour is a new file implementing one of these traits, added
//! to a `SimulationConfig` without touching the pipeline:
//!
//! - **impact** stage, per impact, in the parallel update: a [`ReboundLaw`] gives the
//!   probability p_r that an impact rebounds ([`rebound`]); the [`ImpactModel`] combines it with
//!   the anti-adhesion factor α and turns a rebound into an outgoing velocity ([`impact`]); an
//!   [`ErosionLaw`] says how much an impact wears the target ([`erosion`]);
//! - **layer** stage, at fixed intervals, sequential over the deposits: a [`LayerStage`] such as
//!   cohesive failure or dripping acts on every target's layer and may release material as
//!   particles ([`layer`]).

pub mod erosion;
pub mod impact;
pub mod layer;
pub mod rebound;

pub use erosion::{ErosionForm, ErosionLaw};
pub use impact::{ImpactModel, ImpactSite, Outcome};
pub use layer::{LayerContext, LayerStage};
pub use rebound::{ReboundForm, ReboundLaw};
