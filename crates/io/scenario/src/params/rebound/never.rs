//! `rebound_model = "never"`: nothing rebounds, no keys of its own.

use super::ReboundModel;
use crate::reader::{Read, Section};
use serde::Serialize;
use spraysim_engine::process::ReboundLaw;
use spraysim_engine::process::rebound::NeverRebound;
use std::sync::Arc;

/// The never law, p_r ≡ 0: it has no keys.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NeverLaw;

impl ReboundModel for NeverLaw {
    fn defaults() -> Self {
        NeverLaw
    }

    fn read_over(_s: &Section<'_>, _d: &Self) -> Read<Self> {
        Ok(NeverLaw)
    }

    fn law(&self) -> Arc<dyn ReboundLaw> {
        Arc::new(NeverRebound)
    }
}
