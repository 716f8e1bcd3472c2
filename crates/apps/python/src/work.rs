//! Stepping with the interpreter released: work runs detached in slices of about
//! [`SLICE`], and between slices the thread re-attaches and lets Python's signal handlers run,
//! so that Ctrl-C raises `KeyboardInterrupt` within a slice and other Python threads run
//! meanwhile. A simulation interrupted this way stays valid, at the step it reached.
//!
//! Each slice runs inside a worker pool (the simulation's own, or rayon's global one) as one
//! job: the engine, whose own pool is left unset, then finds itself on a worker of that pool
//! and runs its parallel stages there, instead of handing every step over to the pool and
//! waiting for it (which costs tens of microseconds a step).

use pyo3::prelude::*;
use rayon::prelude::*;
use spraysim::Simulation;
use std::time::{Duration, Instant};

/// How long work runs detached before the thread re-attaches to look for signals.
pub const SLICE: Duration = Duration::from_millis(10);

/// Steps `sim` until it has done `until` steps or `deadline` has passed (at least one step
/// if any is due); returns the steps taken.
fn steps_until(sim: &mut Simulation, until: u64, deadline: Instant) -> u64 {
    let mut done = 0;
    while sim.steps_done() < until {
        sim.step();
        done += 1;
        if Instant::now() >= deadline {
            break;
        }
    }
    done
}

/// Runs `op` as one job on `pool` (rayon's global pool when None) and waits for it.
fn on_pool<R: Send>(pool: Option<&rayon::ThreadPool>, op: impl FnOnce() -> R + Send) -> R {
    match pool {
        Some(p) => p.install(op),
        None => rayon::scope(|_| op()),
    }
}

/// Steps `sim` until it has done `until` steps, detached, on `pool` (rayon's global pool when
/// None), calling `between` (attached) after each slice. Signals raise between slices.
pub fn run_to(
    py: Python<'_>,
    sim: &mut Simulation,
    pool: Option<&rayon::ThreadPool>,
    until: u64,
    mut between: impl FnMut(&Simulation) -> PyResult<()>,
) -> PyResult<()> {
    while sim.steps_done() < until {
        py.detach(|| on_pool(pool, || steps_until(sim, until, Instant::now() + SLICE)));
        py.check_signals()?;
        between(sim)?;
    }
    Ok(())
}

/// A pool of `threads` worker threads, or None for rayon's global pool (one per core) when
/// `threads` is 0.
pub fn pool(threads: usize) -> PyResult<Option<std::sync::Arc<rayon::ThreadPool>>> {
    if threads == 0 {
        return Ok(None);
    }
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| {
        pyo3::exceptions::PyValueError::new_err(format!("cannot start {threads} worker threads: {e}"))
    })?;
    Ok(Some(std::sync::Arc::new(pool)))
}

/// Runs every simulation to its end on `pool` (rayon's global pool when None), detached, in
/// rounds of about one [`SLICE`] in which each unfinished simulation takes at least one step.
/// Signals raise between rounds.
pub fn run_all(py: Python<'_>, sims: &mut [Simulation], pool: Option<&rayon::ThreadPool>) -> PyResult<()> {
    while sims.iter().any(|s| !s.is_finished()) {
        let round = || {
            let deadline = Instant::now() + SLICE;
            sims.par_iter_mut().for_each(|s| {
                let end = s.total_steps();
                steps_until(s, end, deadline);
            });
        };
        py.detach(|| on_pool(pool, round));
        py.check_signals()?;
    }
    Ok(())
}
