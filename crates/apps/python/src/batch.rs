//! `spraysim.run_many`: many scenarios in parallel inside Rust, streamed through a bounded
//! number of simulations.
//!
//! The scenarios are read and checked first (cheap: no simulation is built), and the batch's
//! memory is checked against the limit: at most `threads` simulations at a time, each bounded
//! by its scenario's budget ([`spraysim::Scenario::budget`]), and every result kept until the
//! end. Then the simulations run, each built when a worker frees and dropped once its result
//! (metrics, and maps when asked) is taken.

use crate::args::{Threads, type_name};
use crate::convert;
use crate::errors::setup_error;
use crate::scenario::{PyScenario, read};
use crate::views;
use crate::work;
use numpy::IntoPyArray;
use numpy::ndarray::{ArrayD, IxDyn};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyString, PyTuple};
use spraysim::deposit::DepositSurface;
use spraysim::scenario::bytes_text;
use spraysim::{Scenario, SetupError, Simulation, SimulationConfig};

/// Most runs flown together on the GPU (see `run_many`'s `backend`).
const GPU_BATCH: usize = 64;

/// Bytes one run's metrics take as a Python dictionary, about (its `metrics.json` is a few
/// kB; the dictionary's objects take several times that).
const METRICS_BYTES: f64 = 32.0 * 1024.0;

/// Runs every scenario to its end, in parallel on `threads` worker threads (0: one per core,
/// at most `spraysim::max_threads()`), with the interpreter released (Ctrl-C raises
/// `KeyboardInterrupt` within a fraction of a second). `scenarios` is a list (or any iterable,
/// a generator included) whose items are each a `Scenario`, a `dict` or a file path.
///
/// The scenarios are all read and checked first (no simulation is built then). At most
/// `threads` simulations (one per core for 0) are alive at a time, fewer when the memory limit
/// needs it: each is built when a worker frees and dropped once its result is taken. Before
/// any runs, the batch is checked against the memory limit (the largest
/// `simulation.max_memory` of its scenarios, by default half of this machine's memory): a
/// batch whose results (with `maps=True`, every map of every run) cannot fit raises
/// `MemoryError`, saying what to change.
///
/// Returns, in the order given, each run's metrics as a dictionary (its `metrics.json`, with
/// `targets` keyed by name, as `Simulation.metrics` gives it); with `maps=True`, `(metrics,
/// maps)` pairs instead, where `maps` holds each target's thickness (m, a (rows, cols) float64
/// array laid out as `Simulation.thickness`, NaN in openings) by target name. Results equal those of running the scenarios one
/// after the other, whatever `threads`.
///
/// `backend` is what flies each run's particles, as for `Simulation`: `"cpu"`, `"gpu"` or
/// `"auto"`; None takes each scenario's `simulation.backend`. With `"gpu"`, a scenario the GPU
/// cannot run raises `RuntimeError` before any run starts, and the runs go in batches of up to
/// 64 (fewer where memory needs it; `threads` does not bound them), each run on a thread of its
/// own and the batch's calls flown together, one dispatch for all (batches whose grids outgrow
/// one GPU binding are split and run side by side). Each run's results equal its run alone on
/// the GPU.
#[pyfunction]
#[pyo3(
    signature = (scenarios, threads = Threads::PER_CORE, maps = false, backend = None),
    text_signature = "(scenarios, threads=0, maps=False, backend=None)"
)]
pub fn run_many<'py>(
    py: Python<'py>,
    scenarios: &Bound<'py, PyAny>,
    threads: Threads,
    maps: bool,
    backend: Option<&str>,
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let variants = read_all(py, scenarios, maps)?;
    let stages = variants
        .iter()
        .enumerate()
        .map(|(i, v)| crate::backend::stage_for(py, backend, &v.scenario, &format!("`scenarios[{i}]`")))
        .collect::<PyResult<Vec<_>>>()?;
    let pool = work::pool(threads)?;
    // On the GPU, the runs of a batch fly together: as many at once as memory allows, up to
    // GPU_BATCH.
    let on_gpu = !stages.is_empty() && stages.iter().all(Option::is_some);
    let at_once = plan(&variants, if on_gpu { GPU_BATCH } else { work::workers(pool.as_deref()) }, maps)?;
    let mut results: Vec<Option<Bound<'py, PyAny>>> = (0..variants.len()).map(|_| None).collect();
    let (configs, scenarios): (Vec<_>, Vec<_>) =
        variants.into_iter().zip(stages).map(|(v, stage)| ((v.config, stage), v.scenario)).unzip();
    let finish = |index: usize, sim: &Simulation| Outcome::of(sim, &scenarios[index], maps);
    let deliver = |index: usize, outcome: Result<Outcome, SetupError>| {
        let outcome = outcome.map_err(|e| built_error(index, &e))?;
        results[index] = Some(outcome.into_py(py, index, maps)?);
        Ok(())
    };
    if on_gpu {
        work::run_batches(py, configs, at_once, finish, deliver)?;
    } else {
        work::run_stream(py, configs, at_once, pool.as_deref(), finish, deliver)?;
    }
    results
        .into_iter()
        .enumerate()
        .map(|(i, r)| r.ok_or_else(|| PyRuntimeError::new_err(format!("scenarios[{i}] gave no result"))))
        .collect()
}

/// One scenario of a batch, checked, with what it costs.
struct Variant {
    config: SimulationConfig,
    /// The scenario it was read from, whose sanity warnings its metrics carry.
    scenario: Scenario,
    /// Bound on the memory of its simulation, bytes.
    memory: f64,
    /// The limit its scenario holds a run to, bytes.
    limit: f64,
    /// Bytes its result keeps until the batch ends.
    result: f64,
}

/// Reads and checks every item of `scenarios`, without building any simulation.
fn read_all(py: Python<'_>, scenarios: &Bound<'_, PyAny>, maps: bool) -> PyResult<Vec<Variant>> {
    refuse_single(scenarios)?;
    let items = scenarios.try_iter().map_err(|_| {
        PyTypeError::new_err(format!(
            "`scenarios` must be a list (or other iterable) of scenarios, got {}",
            type_name(scenarios)
        ))
    })?;
    let mut variants = Vec::new();
    for (i, item) in items.enumerate() {
        let item = item?;
        if item.is_none() {
            return Err(PyTypeError::new_err(format!(
                "`scenarios[{i}]` is None: each item must be a Scenario, a dict or a file path \
                 (spraysim.Scenario() is the default scene)"
            )));
        }
        let scenario = read(py, &item, &format!("scenarios[{i}]")).map_err(|e| at_item(py, i, e))?;
        let config = scenario.config();
        config.check().map_err(|e| built_error(i, &SetupError::from(e)))?;
        let budget = scenario.budget();
        let result = METRICS_BYTES + if maps { map_bytes(&scenario) } else { 0.0 };
        variants.push(Variant { config, scenario, memory: budget.memory, limit: budget.limit, result });
    }
    Ok(variants)
}

/// Refuses a single scenario (or a path, whose characters would be read as paths) given where a
/// list of them belongs.
fn refuse_single(scenarios: &Bound<'_, PyAny>) -> PyResult<()> {
    let single = if scenarios.is_instance_of::<PyString>() {
        "str (a file path, which would be read one character at a time)"
    } else if scenarios.is_instance_of::<PyBytes>() {
        "bytes"
    } else if scenarios.cast::<PyDict>().is_ok() {
        "dict (one scenario, whose keys would be read as file paths)"
    } else if scenarios.cast::<PyScenario>().is_ok() {
        "Scenario"
    } else if scenarios.hasattr("__fspath__")? {
        "path"
    } else {
        return Ok(());
    };
    Err(PyTypeError::new_err(format!(
        "`scenarios` must be a list of scenarios, not a single {single}: pass a list, e.g. \
         run_many([scenario]) to run one"
    )))
}

/// An error reading `scenarios[index]`: a `ScenarioError` names its file or `scenarios[i]`
/// already; other errors get the item's place in front.
fn at_item(py: Python<'_>, index: usize, e: PyErr) -> PyErr {
    if e.is_instance_of::<crate::errors::ScenarioError>(py) {
        return e;
    }
    let text = format!("`scenarios[{index}]`: {}", e.value(py));
    if e.is_instance_of::<PyTypeError>(py) { PyTypeError::new_err(text) } else { PyValueError::new_err(text) }
}

/// A `ValueError` for a scenario of the batch that the engine refused.
fn built_error(index: usize, e: &SetupError) -> PyErr {
    PyValueError::new_err(format!("`scenarios[{index}]`: {}", setup_error(e)))
}

/// Bytes of a run's thickness maps: 8 per cell of each target (per triangle of a mesh).
fn map_bytes(scenario: &Scenario) -> f64 {
    8.0 * scenario.targets().iter().map(|t| t.shape.cells() as f64).sum::<f64>()
}

/// How many simulations of the batch may be alive at once (at most `workers`), or the
/// `MemoryError` of a batch whose results alone cannot fit.
fn plan(variants: &[Variant], workers: usize, maps: bool) -> PyResult<usize> {
    // The first of the largest, to name it.
    let Some((largest_at, largest)) =
        variants.iter().enumerate().rev().max_by(|a, b| a.1.memory.total_cmp(&b.1.memory))
    else {
        return Ok(1);
    };
    let limit = variants.iter().map(|v| v.limit).fold(0.0, f64::max);
    let results: f64 = variants.iter().map(|v| v.result).sum();
    let room = limit - results;
    if room < largest.memory {
        let most_result = variants.iter().map(|v| v.result).fold(0.0, f64::max);
        let part = ((limit - largest.memory) / most_result).floor().max(1.0);
        let change = if maps {
            format!(
                "pass maps=False (or take fewer cells), or run the batch in parts of at most {part} scenarios"
            )
        } else {
            format!("run the batch in parts of at most {part} scenarios")
        };
        return Err(PyMemoryError::new_err(format!(
            "run_many: the results of {n} scenarios need about {results}{with_maps}, and one simulation \
             (scenarios[{largest_at}], the largest) up to {one} more: beyond the memory limit of {limit} \
             (the largest simulation.max_memory of the batch, by default half of this machine's memory). \
             Nothing was run: {change}",
            n = variants.len(),
            results = bytes_text(results),
            with_maps = if maps { " (with maps=True every run's thickness maps are kept)" } else { "" },
            one = bytes_text(largest.memory),
            limit = bytes_text(limit),
        )));
    }
    // At least one fits, by the test above.
    let fit = (room / largest.memory).floor() as usize;
    Ok(workers.min(variants.len()).min(fit).max(1))
}

/// What a finished run leaves: its metrics and, when asked, its thickness maps; taken before
/// its simulation is dropped.
struct Outcome {
    /// `metrics.json`'s text, or why it could not be made.
    metrics: Result<String, String>,
    /// Each target's name, map shape and thickness (m).
    maps: Vec<(String, IxDyn, Vec<f64>)>,
}

impl Outcome {
    /// The outcome of `sim`, a run of `scenario`: its metrics with their sanity warnings, as a
    /// single simulation's `metrics()` gives them, and its maps when `maps`.
    fn of(sim: &Simulation, scenario: &Scenario, maps: bool) -> Outcome {
        let metrics = spraysim::output::run_metrics_json(sim, scenario).map_err(|e| e.to_string());
        let maps = if maps {
            sim.targets()
                .iter()
                .map(|t| (t.name.clone(), views::shape(t), views::with_nan(t, t.surface.thickness())))
                .collect()
        } else {
            Vec::new()
        };
        Outcome { metrics, maps }
    }

    /// The run's result as Python returns it: metrics, or `(metrics, maps)` when `maps`.
    fn into_py(self, py: Python<'_>, index: usize, maps: bool) -> PyResult<Bound<'_, PyAny>> {
        let text = self.metrics.map_err(|e| PyOSError::new_err(format!("scenarios[{index}]: {e}")))?;
        let metrics = convert::metrics_to_py(py, &text)?;
        if !maps {
            return Ok(metrics);
        }
        let arrays = PyDict::new(py);
        for (name, shape, data) in self.maps {
            let array = ArrayD::from_shape_vec(shape, data)
                .map_err(|e| PyValueError::new_err(format!("scenarios[{index}], target {name}: {e}")))?;
            arrays.set_item(&name, array.into_pyarray(py))?;
        }
        Ok(PyTuple::new(py, [metrics, arrays.into_any()])?.into_any())
    }
}
