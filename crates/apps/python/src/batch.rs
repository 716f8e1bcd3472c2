//! `spraysim.run_many`: many scenarios in parallel inside Rust.

use crate::convert;
use crate::errors::{output_error, setup_error};
use crate::scenario::scenario_from;
use crate::views;
use crate::work;
use numpy::ToPyArray;
use numpy::ndarray::ArrayViewD;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use spraysim::Simulation;
use spraysim::deposit::DepositSurface;

/// Runs every scenario to its end, in parallel on `threads` worker threads (0: one per core),
/// with the interpreter released (Ctrl-C raises `KeyboardInterrupt` within a fraction of a
/// second). Each item of `scenarios` is a `Scenario`, a `dict` or a file path.
///
/// Returns, in the order given, each run's metrics as a dictionary equal to its
/// `metrics.json`; with `maps=True`, `(metrics, maps)` pairs instead, where `maps` holds each
/// target's thickness (m, a (rows, cols) float64 array laid out as
/// `Simulation.thickness`) by target name. Results equal those of running the scenarios one
/// after the other, whatever `threads`.
#[pyfunction]
#[pyo3(signature = (scenarios, threads = 0, maps = false))]
pub fn run_many<'py>(
    py: Python<'py>,
    scenarios: &Bound<'py, PyAny>,
    threads: usize,
    maps: bool,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let mut sims = Vec::new();
    for (i, item) in scenarios.try_iter()?.enumerate() {
        let scenario = scenario_from(py, Some(&item?))?;
        let sim = Simulation::new(scenario.config())
            .map_err(|e| PyValueError::new_err(format!("scenarios[{i}]: {}", setup_error(&e))))?;
        sims.push(sim);
    }
    let pool = work::pool(threads)?;
    work::run_all(py, &mut sims, pool.as_deref())?;
    sims.iter().map(|sim| result(py, sim, maps)).collect()
}

/// One run's metrics, with its thickness maps when `maps`.
fn result<'py>(py: Python<'py>, sim: &Simulation, maps: bool) -> PyResult<Bound<'py, PyAny>> {
    let text = spraysim::output::metrics_json(sim).map_err(|e| output_error(&e))?;
    let metrics = convert::json_to_py(py, &text)?;
    if !maps {
        return Ok(metrics);
    }
    let arrays = PyDict::new(py);
    for t in sim.targets() {
        let view = ArrayViewD::from_shape(views::shape(t), t.surface.thickness())
            .map_err(|e| PyValueError::new_err(format!("target {}: {e}", t.name)))?;
        arrays.set_item(&t.name, view.to_pyarray(py))?;
    }
    Ok(PyTuple::new(py, [metrics, arrays.into_any()])?.into_any())
}
