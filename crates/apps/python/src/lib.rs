//! # spraysim-python
//!
//! The `spraysim._core` extension module: spraysim's scenarios, simulations and batches for
//! Python, with results as numpy arrays and dictionaries. The pure-Python package `spraysim`
//! (`python/src/spraysim`) re-exports it and adds the Gymnasium environment.
//!
//! Everything here is a thin layer over the `spraysim` crate: a scenario is a
//! [`spraysim::Scenario`] (overrides go through [`spraysim::Scenario::with`], so a Python
//! override is checked exactly as a file's value or the command's `--set`), a simulation is a
//! [`spraysim::Simulation`] stepped with the interpreter released in slices of about 10 ms, so
//! that other Python threads run meanwhile and Ctrl-C raises `KeyboardInterrupt` between two
//! slices. SI units throughout (m, s, kg); angles in degrees, with the unit in every name
//! (`roll_deg`); quaternions as `(w, x, y, z)`; float maps hold NaN in openings, as the `.npy`
//! files do; errors begin with the key or argument they are about.
//!
//! Limits, each refused with a Python exception that names the argument or key:
//! - a scenario value (a `dict` or a `Scenario.set` value) nests dicts and lists at most 32
//!   levels deep (`convert::MAX_DEPTH`) and never holds itself (`ScenarioError`);
//! - `threads=` is 0 (one per core) up to [`spraysim::max_threads`] (`ValueError`);
//! - `backend=` is `"cpu"`, `"gpu"` or `"auto"` (`ValueError`), and `"gpu"` raises
//!   `RuntimeError` where it cannot run (module `backend`);
//! - `run_many` keeps at most `threads` simulations alive at a time and checks its results
//!   against the memory limit before it starts (`MemoryError`);
//! - a `Simulation` is used by one thread at a time: other threads' calls wait their turn, in
//!   order, with the interpreter released (module `exclusive`).

mod args;
mod backend;
mod batch;
mod convert;
mod errors;
mod exclusive;
mod nozzle;
mod scenario;
mod simulation;
mod together;
mod views;
mod work;

use pyo3::prelude::*;

/// The extension module `spraysim._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scenario::PyScenario>()?;
    m.add_class::<simulation::PySimulation>()?;
    m.add_class::<simulation::PySnapshot>()?;
    m.add_function(wrap_pyfunction!(batch::run_many, m)?)?;
    m.add_function(wrap_pyfunction!(together::step_together, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::presets, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::presets_toml, m)?)?;
    m.add("ScenarioError", m.py().get_type::<errors::ScenarioError>())?;
    m.add("ALIVE", spraysim::particles::flags::ALIVE)?;
    m.add("HIT_SUBSTRATE", spraysim::particles::flags::HIT_SUBSTRATE)?;
    m.add("RELEASED", spraysim::particles::flags::RELEASED)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
