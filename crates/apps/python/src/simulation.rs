//! `spraysim.Simulation` and `spraysim.Snapshot`.

use crate::errors::{output_error, setup_error};
use crate::scenario::{PyScenario, scenario_from};
use crate::{convert, nozzle, views, work};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use spraysim::deposit::DepositSurface;
use spraysim::{Scenario, Simulation};
use std::sync::Arc;

/// The engine's simulation and a token counting the arrays that view its memory.
pub(crate) struct Held {
    pub sim: Simulation,
    /// One strong count per live zero-copy array into `sim`, plus this one.
    pub views: Arc<()>,
}

impl Held {
    fn new(sim: Simulation) -> Held {
        Held { sim, views: Arc::new(()) }
    }
}

/// A running simulation of a scenario.
///
/// `Simulation(scenario=None, threads=0)`: `scenario` is a `Scenario`, a `dict`, a file path or
/// None (the default scene); `threads` is the number of worker threads (0: one per core).
/// Results do not depend on `threads`. `step` and `run` release the interpreter while they
/// work, in slices of about 10 ms: other Python threads run meanwhile, and Ctrl-C raises
/// `KeyboardInterrupt` within a slice, leaving the simulation valid at the step it reached.
///
/// Units: m, s, kg; angles in radians. Frame: z up, gravity along −z.
#[pyclass(module = "spraysim", name = "Simulation")]
pub struct PySimulation {
    pub(crate) held: Held,
    /// Simulations replaced by `restore` while arrays still viewed their memory.
    retired: Vec<Held>,
    scenario: Scenario,
    threads: usize,
    /// The worker pool its slices run on (None: rayon's global pool); the engine's own pool is
    /// left unset, so that its parallel stages run on this one.
    pool: Option<Arc<rayon::ThreadPool>>,
}

/// A saved state of a `Simulation` (`Simulation.snapshot()`): `Simulation.restore` continues
/// from it exactly as the original did. Immutable; restore it as often as you like.
#[pyclass(module = "spraysim", name = "Snapshot", frozen)]
pub struct PySnapshot {
    sim: Simulation,
    scenario: Scenario,
}

#[pymethods]
impl PySnapshot {
    /// Simulated time of the saved state, s.
    #[getter]
    fn time(&self) -> f64 {
        self.sim.time()
    }

    /// Steps taken up to the saved state.
    #[getter]
    fn steps_done(&self) -> u64 {
        self.sim.steps_done()
    }

    fn __repr__(&self) -> String {
        format!("Snapshot(time={} s, steps_done={})", self.sim.time(), self.sim.steps_done())
    }
}

/// Steps at which simulated time first reaches `until` (s), for time step `dt` (s).
fn steps_for(until: f64, dt: f64) -> PyResult<u64> {
    if !until.is_finite() || until < 0.0 {
        return Err(PyValueError::new_err(format!("`until` must be a time ≥ 0 s, got {until}")));
    }
    // A whole number of steps within rounding of `until` counts as reaching it.
    Ok((until / dt - 1e-9).ceil().max(0.0) as u64)
}

#[pymethods]
impl PySimulation {
    #[new]
    #[pyo3(signature = (scenario = None, threads = 0))]
    fn new(py: Python<'_>, scenario: Option<&Bound<'_, PyAny>>, threads: usize) -> PyResult<Self> {
        let scenario = scenario_from(py, scenario)?;
        let sim = Simulation::new(scenario.config()).map_err(|e| setup_error(&e))?;
        let pool = work::pool(threads)?;
        Ok(PySimulation { held: Held::new(sim), retired: Vec::new(), scenario, threads, pool })
    }

    /// Advances the simulation by `n` time steps Δt (also past the configured duration).
    #[pyo3(signature = (n = 1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        let until = self.held.sim.steps_done().saturating_add(n);
        work::run_to(py, &mut self.held.sim, self.pool.as_deref(), until, |_| Ok(()))
    }

    /// Runs until simulated time reaches `until` (s; the configured duration when None).
    /// `progress=True` prints the simulated time to standard error as it goes; a callable is
    /// called as `progress(time_s, until_s)` about every 10 ms.
    #[pyo3(signature = (until = None, progress = None))]
    fn run(
        &mut self,
        py: Python<'_>,
        until: Option<f64>,
        progress: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let dt = self.held.sim.config().dt;
        let steps = match until {
            Some(t) => steps_for(t, dt)?,
            None => self.held.sim.total_steps(),
        };
        let end = steps as f64 * dt;
        let report = progress::Report::new(py, progress, end)?;
        work::run_to(py, &mut self.held.sim, self.pool.as_deref(), steps, |s| report.tick(py, s.time()))?;
        report.finish(py, self.held.sim.time())
    }

    /// Simulated time, s.
    #[getter]
    fn time(&self) -> f64 {
        self.held.sim.time()
    }

    /// Steps taken so far.
    #[getter]
    fn steps_done(&self) -> u64 {
        self.held.sim.steps_done()
    }

    /// Steps the configured duration takes.
    #[getter]
    fn total_steps(&self) -> u64 {
        self.held.sim.total_steps()
    }

    /// Time step Δt, s.
    #[getter]
    fn dt(&self) -> f64 {
        self.held.sim.config().dt
    }

    /// Configured duration, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.held.sim.config().duration
    }

    /// True once the configured duration has been simulated.
    #[getter]
    fn is_finished(&self) -> bool {
        self.held.sim.is_finished()
    }

    /// Worker threads of the update stage (0: one per core); results do not depend on it.
    #[getter]
    fn get_threads(&self) -> usize {
        self.threads
    }

    #[setter]
    fn set_threads(&mut self, threads: usize) -> PyResult<()> {
        self.pool = work::pool(threads)?;
        self.threads = threads;
        Ok(())
    }

    /// The scenario being simulated.
    #[getter]
    fn scenario(&self) -> PyScenario {
        PyScenario { inner: self.scenario.clone() }
    }

    /// The targets' names, in scenario order.
    #[getter]
    fn target_names(&self) -> Vec<String> {
        self.held.sim.targets().iter().map(|t| t.name.clone()).collect()
    }

    /// Particles emitted so far: `(count, volume in m³)`.
    fn emitted(&self) -> (u64, f64) {
        let e = self.held.sim.tally().emitted;
        (e.count, e.volume)
    }

    /// The results so far as a dictionary equal to what `metrics.json` holds (keys, units and
    /// values; see the README's Outputs section), less its `files` manifest.
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        convert::json_to_py(py, &self.metrics_json()?)
    }

    /// The text `metrics.json` would hold now, without the `files` manifest that only a
    /// written set of outputs has.
    fn metrics_json(&self) -> PyResult<String> {
        spraysim::output::metrics_json(&self.held.sim).map_err(|e| output_error(&e))
    }

    /// Writes every output (`metrics.json`, `.npy` arrays, heatmaps, `scenario.resolved.toml`)
    /// into `directory` (the scenario's `output.directory` when None), as `spraysim run -o
    /// DIRECTORY` does, all or nothing. Returns the paths written.
    #[pyo3(signature = (directory = None))]
    fn write_outputs(&self, py: Python<'_>, directory: Option<std::path::PathBuf>) -> PyResult<Vec<String>> {
        // As the command does: the resolved scenario names the directory it was written to.
        let scenario = match &directory {
            Some(d) => self
                .scenario
                .with("output.directory", d.display().to_string())
                .map_err(|e| crate::errors::scenario_error(py, &e))?,
            None => self.scenario.clone(),
        };
        let dir = std::path::PathBuf::from(&scenario.output().directory);
        let sim = &self.held.sim;
        let files = py
            .detach(|| spraysim::output::write_outputs(sim, &scenario, &dir))
            .map_err(|e| output_error(&e))?;
        Ok(files.iter().map(|p| p.display().to_string()).collect())
    }

    /// Saves the present state; `restore` continues from it exactly as this simulation would.
    fn snapshot(&self) -> PySnapshot {
        PySnapshot { sim: self.held.sim.clone(), scenario: self.scenario.clone() }
    }

    /// Returns to a saved state (of this simulation or another one). Arrays taken earlier with
    /// `copy=False` keep showing the state they were taken from.
    fn restore(&mut self, snapshot: &Bound<'_, PySnapshot>) -> PyResult<()> {
        let s = snapshot.get();
        let old = std::mem::replace(&mut self.held, Held::new(s.sim.clone()));
        self.scenario = s.scenario.clone();
        // Arrays still viewing the old state keep it alive; the others let it go.
        self.retired.push(old);
        self.retired.retain(|h| Arc::strong_count(&h.views) > 1);
        Ok(())
    }

    /// An independent copy that continues exactly as this one would.
    fn copy(&self) -> PySimulation {
        PySimulation {
            held: Held::new(self.held.sim.clone()),
            retired: Vec::new(),
            scenario: self.scenario.clone(),
            threads: self.threads,
            pool: self.pool.clone(),
        }
    }

    fn __copy__(&self) -> PySimulation {
        self.copy()
    }

    fn __deepcopy__(&self, _memo: &Bound<'_, PyAny>) -> PySimulation {
        self.copy()
    }

    fn __repr__(&self) -> String {
        let s = &self.held.sim;
        format!(
            "Simulation(scenario={:?}, time={:.6} s of {} s, steps_done={}, in_flight={})",
            self.scenario.origin(),
            s.time(),
            s.config().duration,
            s.steps_done(),
            s.swarm().alive()
        )
    }

    /// The particles in flight, as numpy arrays of one row per particle: `position` (n, 3) m,
    /// `velocity` (n, 3) m/s, `age` (n,) s since emission, `id` (n,) emission index, `impacts`
    /// (n,) impacts so far, `state` (n,) status bits (`ALIVE | HIT_SUBSTRATE | RELEASED`).
    fn particles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        views::particles(py, &self.held.sim)
    }

    /// Deposited thickness on a target (name or index), m. On a rectangle a (rows, cols)
    /// float64 array: row 0 is the target's bottom edge (rows grow along its `up`), columns grow
    /// along `right` = `up × normal` (the viewer's right, looking at the target from the spray
    /// side): plot it with `origin="lower"`. On a cylinder shell the unrolled (along the axis,
    /// around it) map; on a mesh one value per triangle, in the file's order. With
    /// `copy=False` (the default) a read-only view of the simulation's own memory, no copy: it
    /// shows later steps as they happen (do not read it while another thread runs this
    /// simulation); `copy=True` gives an independent array.
    #[pyo3(signature = (target, copy = false))]
    fn thickness<'py>(
        slf: &Bound<'py, Self>,
        target: &Bound<'py, PyAny>,
        copy: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        views::grid(slf, target, copy, |t| t.surface.thickness())
    }

    /// Impacts per cell (stuck or rebounded) on a target: a uint32 array laid out
    /// as `thickness`, with the same `copy` choice.
    #[pyo3(signature = (target, copy = false))]
    fn hits<'py>(
        slf: &Bound<'py, Self>,
        target: &Bound<'py, PyAny>,
        copy: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        views::grid(slf, target, copy, |t| t.surface.hits())
    }

    /// Eroded depth per cell on a target, m, laid out as `thickness` (a copy), or None when
    /// the process erodes nothing.
    fn erosion<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        views::erosion(py, &self.held.sim, target)
    }

    /// A target's geometry: `name`, `role`, `rows`, `cols`, `cell_size` (width, height) m,
    /// `size` (width, height) m, and unit vectors `normal`, `up`, `right` and the `center` (m)
    /// as numpy arrays.
    fn target_info<'py>(&self, py: Python<'py>, target: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        views::target_info(py, &self.held.sim, target)
    }

    /// The nozzle now: `position` (m), unit `axis`, `velocity` (m/s) as numpy arrays, and
    /// `spraying` (bool).
    fn nozzle<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        nozzle::pose(py, &self.held.sim)
    }

    /// Holds the nozzle at `position` (m) spraying along `axis` (unit vector; the present axis
    /// when None) from the next step on, spraying or not as `spray` says (closed-loop control).
    #[pyo3(signature = (position, axis = None, spray = true))]
    fn set_nozzle(
        &mut self,
        position: &Bound<'_, PyAny>,
        axis: Option<&Bound<'_, PyAny>>,
        spray: bool,
    ) -> PyResult<()> {
        nozzle::hold(&mut self.held.sim, position, axis, spray)
    }

    /// Replaces the nozzle's path from the next step on. `waypoints` is a list of dicts (or
    /// tuples in this order) with `time` (s, absolute simulated time, strictly increasing),
    /// `position` (m), `axis` (unit vector) and optionally `spray` (default True: spray from
    /// this waypoint until the next). Position is interpolated linearly, the axis spherically;
    /// before the first and after the last waypoint the nozzle holds that pose. `roll` (rad)
    /// turns the aperture about the axis (the present roll when None).
    #[pyo3(signature = (waypoints, roll = None))]
    fn set_nozzle_path(&mut self, waypoints: &Bound<'_, PyAny>, roll: Option<f64>) -> PyResult<()> {
        nozzle::set_path(&mut self.held.sim, waypoints, roll)
    }

    /// The nozzle's path: a list of waypoint dicts (`time`, `position`, `axis`, `spray`).
    fn nozzle_waypoints<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyList>> {
        nozzle::waypoints(py, &self.held.sim)
    }
}

/// Progress reports of `Simulation.run`.
mod progress {
    use pyo3::prelude::*;
    use std::cell::Cell;
    use std::time::{Duration, Instant};

    /// What to do with progress: nothing, a line on standard error, or a callback.
    pub enum Report<'py> {
        Quiet,
        Line { end: f64, last: Cell<Instant> },
        Call { f: Bound<'py, PyAny>, end: f64 },
    }

    impl<'py> Report<'py> {
        pub fn new(_py: Python<'py>, progress: Option<&Bound<'py, PyAny>>, end: f64) -> PyResult<Self> {
            let Some(p) = progress.filter(|p| !p.is_none()) else { return Ok(Report::Quiet) };
            if p.is_callable() {
                return Ok(Report::Call { f: p.clone(), end });
            }
            Ok(if p.is_truthy()? {
                Report::Line { end, last: Cell::new(Instant::now()) }
            } else {
                Report::Quiet
            })
        }

        pub fn tick(&self, py: Python<'py>, time: f64) -> PyResult<()> {
            match self {
                Report::Quiet => Ok(()),
                Report::Call { f, end } => f.call1((time, *end)).map(|_| ()),
                Report::Line { end, last } => {
                    if last.get().elapsed() < Duration::from_millis(200) {
                        return Ok(());
                    }
                    last.set(Instant::now());
                    let pct = if *end > 0.0 { 100.0 * time / end } else { 100.0 };
                    write(py, &format!("\rt = {time:.3} s of {end:.3} s ({pct:3.0} %)"))
                }
            }
        }

        pub fn finish(&self, py: Python<'py>, time: f64) -> PyResult<()> {
            match self {
                Report::Line { end, .. } => write(py, &format!("\rt = {time:.3} s of {end:.3} s (done)\n")),
                _ => Ok(()),
            }
        }
    }

    fn write(py: Python<'_>, text: &str) -> PyResult<()> {
        let err = py.import("sys")?.getattr("stderr")?;
        err.call_method1("write", (text,))?;
        err.call_method0("flush")?;
        Ok(())
    }
}
