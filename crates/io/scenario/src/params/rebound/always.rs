//! `rebound_model = "always"`: forced rebound (abrasive blasting), no keys of its own.

use super::ReboundModel;
use crate::reader::{Read, Section};
use serde::Serialize;
use spraysim_engine::process::ReboundLaw;
use spraysim_engine::process::rebound::AlwaysRebound;
use std::sync::Arc;

/// The always law, p_r ≡ 1: it has no keys.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AlwaysLaw;

impl ReboundModel for AlwaysLaw {
    fn defaults() -> Self {
        AlwaysLaw
    }

    fn read_over(_s: &Section<'_>, _d: &Self) -> Read<Self> {
        Ok(AlwaysLaw)
    }

    fn law(&self) -> Arc<dyn ReboundLaw> {
        Arc::new(AlwaysRebound)
    }
}
