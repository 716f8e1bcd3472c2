//! `spraysim.step_together`: simulations stepped together, the calls of those on the GPU flown
//! in shared dispatches: the vectorised Gymnasium environment's step.

use crate::exclusive::Turn;
use crate::simulation::{PySimulation, State};
use crate::work;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use spraysim::Simulation;
use std::sync::atomic::AtomicBool;

/// Advances each simulation of `sims` by `n` steps (1 when None; fewer where its run ends),
/// together: each on a thread of its own, the calls of those on the GPU flown in shared
/// dispatches (one dispatch for all of a batch), the others on the CPU. Each one's results
/// equal stepping it alone. The simulations must be distinct; each is busy until all are done.
/// Ctrl-C raises `KeyboardInterrupt` once the calls under way end.
#[pyfunction]
#[pyo3(signature = (sims, n = None), text_signature = "(sims, n=None)")]
pub fn step_together(
    py: Python<'_>,
    sims: Vec<PyRef<'_, PySimulation>>,
    n: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let n = n.map_or(Ok(1), |n| crate::args::count(n, "n", "steps"))?;
    // Turns taken in one order (by address), whatever the list's, so that two threads stepping
    // overlapping sets cannot each hold what the other waits for.
    let mut order: Vec<usize> = (0..sims.len()).collect();
    order.sort_by_key(|&k| std::ptr::from_ref::<PySimulation>(&sims[k]) as usize);
    let mut turns: Vec<Option<Turn<'_, State>>> = (0..sims.len()).map(|_| None).collect();
    for k in order {
        turns[k] = Some(sims[k].lock(py)?);
    }
    let mut refs: Vec<&mut Simulation> = turns.iter_mut().flatten().map(|t| &mut t.held.sim).collect();
    let stop = AtomicBool::new(false);
    let stepped = work::watched(py, &stop, || spraysim::backend::step_together(&mut refs, n, &stop))?;
    stepped.map_err(|e| PyRuntimeError::new_err(format!("step_together: {e}")))
}
