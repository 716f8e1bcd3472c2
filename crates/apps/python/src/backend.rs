//! The `backend=` argument of `Simulation` and `run_many`: what flies the particles, `"cpu"`,
//! `"gpu"` or `"auto"` (None: the scenario's `[simulation] backend`), chosen as the command
//! chooses ([`spraysim::backend`]).

use pyo3::exceptions::{PyRuntimeError, PyRuntimeWarning, PyValueError};
use pyo3::prelude::*;
use spraysim::Scenario;
use spraysim::pipeline::FlightStage;
use spraysim::scenario::Backend;
use std::sync::Arc;

/// The flight stage `backend` (None: `scenario`'s own) asks for: None for the CPU. An unknown
/// name raises `ValueError`; `"gpu"` that cannot run (a build without it, no adapter, a feature
/// outside its scope) raises `RuntimeError` saying why; `"auto"` then runs on the CPU with a
/// `RuntimeWarning` saying why. `what` names the scenario in messages.
pub fn stage_for(
    py: Python<'_>,
    backend: Option<&str>,
    scenario: &Scenario,
    what: &str,
) -> PyResult<Option<Arc<dyn FlightStage>>> {
    let backend = match backend {
        Some(name) => Backend::parse(name).map_err(|e| PyValueError::new_err(format!("`backend`: {e}")))?,
        None => scenario.simulation().backend,
    };
    let chosen = spraysim::backend::choose(backend, scenario)
        .map_err(|e| PyRuntimeError::new_err(format!("backend \"gpu\" for {what}: {e}")))?;
    if let Some(why) = &chosen.fallback {
        let warning = py.get_type::<PyRuntimeWarning>();
        let message =
            std::ffi::CString::new(format!("backend \"auto\" for {what}: running on the CPU: {why}"))
                .unwrap_or_default();
        PyErr::warn(py, &warning, &message, 1)?;
    }
    Ok(chosen.stage)
}
