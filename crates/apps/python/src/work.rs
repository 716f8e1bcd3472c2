//! Stepping with the interpreter released: work runs detached in slices of about
//! [`SLICE`], and between slices the thread re-attaches and lets Python's signal handlers run,
//! so that Ctrl-C raises `KeyboardInterrupt` within a slice and other Python threads run
//! meanwhile. A simulation interrupted this way stays valid, at the step it reached.
//!
//! Each slice runs inside a worker pool (the simulation's own, or rayon's global one) as one
//! job: the engine, whose own pool is left unset, then finds itself on a worker of that pool
//! and runs its parallel stages there, instead of handing every step over to the pool and
//! waiting for it (which costs tens of microseconds a step).

use crate::args::Threads;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rayon::prelude::*;
use spraysim::pipeline::FlightStage;
use spraysim::{SetupError, Simulation, SimulationConfig};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// How long work runs detached before the thread re-attaches to look for signals.
pub const SLICE: Duration = Duration::from_millis(10);

/// Advances `sim` until it has done `until` steps or `deadline` has passed (at least one
/// call if any step is due), a call at a time (a layer epoch, or several on the GPU); returns
/// the steps taken. How the steps are split into calls never changes a result on the CPU.
fn steps_until(sim: &mut Simulation, until: u64, deadline: Instant) -> u64 {
    let mut done = 0;
    while sim.steps_done() < until {
        let k = sim.steps_to_call_end().min(until - sim.steps_done());
        done += sim.advance_call(k);
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
pub fn pool(threads: Threads) -> PyResult<Option<Arc<rayon::ThreadPool>>> {
    let Threads(threads) = threads;
    if threads == 0 {
        return Ok(None);
    }
    // Checked when the argument was read; checked again here, before any thread starts.
    spraysim::check_threads(threads).map_err(|e| PyValueError::new_err(format!("`threads`: {e}")))?;
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().map_err(|e| {
        PyValueError::new_err(format!("`threads`: cannot start {threads} worker threads: {e}"))
    })?;
    Ok(Some(Arc::new(pool)))
}

/// The worker threads of `pool` (rayon's global pool when None).
pub fn workers(pool: Option<&rayon::ThreadPool>) -> usize {
    pool.map_or_else(rayon::current_num_threads, rayon::ThreadPool::current_num_threads)
}

/// A run of a batch: its configuration, and the flight stage its particles fly on (None: the
/// CPU engine's own).
pub type Job = (SimulationConfig, Option<Arc<dyn FlightStage>>);

/// Runs simulations of `configs` to their ends on `pool` (rayon's global pool when None),
/// detached, with at most `at_once` of them built and alive at a time: each is built when a
/// worker frees, and once finished, `finish` makes its result from the index of its config and the
/// simulation (detached), and the simulation is dropped.
/// Between rounds of about one [`SLICE`], attached, `deliver` receives each result finished
/// meanwhile with the index of its config (or why its simulation could not be built), and
/// signals raise. A simulation's result does not depend on `at_once`, the pool or the rounds.
pub fn run_stream<R: Send>(
    py: Python<'_>,
    configs: Vec<Job>,
    at_once: usize,
    pool: Option<&rayon::ThreadPool>,
    finish: impl Fn(usize, &Simulation) -> R + Sync,
    mut deliver: impl FnMut(usize, Result<R, SetupError>) -> PyResult<()>,
) -> PyResult<()> {
    let queue = Mutex::new(configs.into_iter().enumerate());
    let done = Mutex::new(Vec::new());
    let mut slots: Vec<Option<(usize, Simulation)>> = (0..at_once.max(1)).map(|_| None).collect();
    loop {
        let round = |slots: &mut [Option<(usize, Simulation)>]| {
            let deadline = Instant::now() + SLICE;
            slots.par_iter_mut().for_each(|slot| work_slot(slot, &queue, &done, &finish, deadline));
        };
        py.detach(|| on_pool(pool, || round(&mut slots)));
        let finished = std::mem::take(&mut *done.lock().unwrap_or_else(PoisonError::into_inner));
        for (index, result) in finished {
            deliver(index, result)?;
        }
        py.check_signals()?;
        let idle = slots.iter().all(Option::is_none);
        if idle && queue.lock().unwrap_or_else(PoisonError::into_inner).len() == 0 {
            return Ok(());
        }
    }
}

/// Runs `configs` to their ends in batches of `at_once` on the process's GPU: the simulations of
/// a batch each on a thread of its own, their calls flown together in shared dispatches
/// (`spraysim::backend::run_together`; each config's own stage is not used). Each finished
/// simulation's result is made by `finish` from the index of its config, and `deliver` receives
/// it (or why its simulation could not be built). The batch runs on a thread of its own, so
/// that this one, attached every [`SLICE`], lets signals raise; then the batch stops after the
/// calls under way. A simulation's result does not depend on `at_once` or the batches.
pub fn run_batches<R: Send>(
    py: Python<'_>,
    configs: Vec<Job>,
    at_once: usize,
    finish: impl Fn(usize, &Simulation) -> R + Sync,
    mut deliver: impl FnMut(usize, Result<R, SetupError>) -> PyResult<()>,
) -> PyResult<()> {
    let mut queue = configs.into_iter().enumerate().peekable();
    while queue.peek().is_some() {
        let (mut sims, mut indices) = (Vec::new(), Vec::new());
        for (index, (config, _)) in queue.by_ref().take(at_once.max(1)) {
            match Simulation::new(config) {
                Ok(sim) => {
                    sims.push(sim);
                    indices.push(index);
                }
                Err(e) => deliver(index, Err(e))?,
            }
        }
        let stop = AtomicBool::new(false);
        let finished = watched(py, &stop, || {
            spraysim::backend::run_together(sims, &stop)
                .map(|done| done.iter().zip(&indices).map(|(sim, &i)| finish(i, sim)).collect::<Vec<R>>())
        })?;
        let results = finished.map_err(|e| PyRuntimeError::new_err(format!("backend \"gpu\": {e}")))?;
        for (index, result) in indices.into_iter().zip(results) {
            deliver(index, Ok(result))?;
        }
    }
    Ok(())
}

/// Runs `op` on a thread of its own and waits for it, attached every [`SLICE`] so that signal
/// handlers run; on a signal's error, sets `stop` (which `op` must heed, returning soon after),
/// waits for `op` and raises it.
pub fn watched<R: Send>(py: Python<'_>, stop: &AtomicBool, op: impl FnOnce() -> R + Send) -> PyResult<R> {
    std::thread::scope(|scope| {
        let worker = scope.spawn(op);
        while !worker.is_finished() {
            py.detach(|| std::thread::sleep(SLICE));
            if let Err(e) = py.check_signals() {
                stop.store(true, Ordering::Relaxed);
                let _ = worker.join();
                return Err(e);
            }
        }
        Ok(worker.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
    })
}

/// The configs still to run, with their indices.
type Queue = Mutex<std::iter::Enumerate<std::vec::IntoIter<Job>>>;

/// Works on one slot of [`run_stream`] until `deadline`: steps its simulation, and when it
/// finishes (or the slot is empty) builds the next one from `queue`.
fn work_slot<R>(
    slot: &mut Option<(usize, Simulation)>,
    queue: &Queue,
    done: &Mutex<Vec<(usize, Result<R, SetupError>)>>,
    finish: &(impl Fn(usize, &Simulation) -> R + Sync),
    deadline: Instant,
) {
    let report = |index: usize, result: Result<R, SetupError>| {
        done.lock().unwrap_or_else(PoisonError::into_inner).push((index, result));
    };
    loop {
        if slot.is_none() {
            let next = queue.lock().unwrap_or_else(PoisonError::into_inner).next();
            let Some((index, (config, stage))) = next else { return };
            match Simulation::new(config) {
                Ok(mut sim) => {
                    sim.set_flight_stage(stage);
                    *slot = Some((index, sim));
                }
                Err(e) => return report(index, Err(e)),
            }
        }
        let Some((index, sim)) = slot.as_mut() else { return };
        let end = sim.total_steps();
        steps_until(sim, end, deadline);
        if sim.steps_done() >= end {
            report(*index, Ok(finish(*index, sim)));
            // The simulation goes now, before the next one is built.
            *slot = None;
        }
        if Instant::now() >= deadline {
            return;
        }
    }
}
