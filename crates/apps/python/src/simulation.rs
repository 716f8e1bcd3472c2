//! `spraysim.Simulation` and `spraysim.Snapshot`.

use crate::args::Threads;
use crate::errors::{output_error, relocated, scenario_error, setup_error};
use crate::exclusive::{Exclusive, Turn};
use crate::scenario::{PyScenario, py_repr, scenario_from};
use crate::{convert, nozzle, views, work};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::sync::MutexExt;
use pyo3::types::PyDict;
use spraysim::deposit::DepositSurface;
use spraysim::{Scenario, Simulation};
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

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

/// What a simulation's calls work on, one thread at a time.
pub(crate) struct State {
    pub held: Held,
    /// Simulations replaced by `restore` while arrays still viewed their memory.
    retired: Vec<Held>,
}

/// What a simulation's calls only read or swap, each for an instant.
struct Setup {
    scenario: Scenario,
    threads: usize,
    /// The worker pool its slices run on (None: rayon's global pool); the engine's own pool is
    /// left unset, so that its parallel stages run on this one.
    pool: Option<Arc<rayon::ThreadPool>>,
}

/// A running simulation of a scenario.
///
/// `Simulation(scenario=None, threads=0, backend=None)`: `scenario` is a `Scenario`, a `dict`, a
/// file path or None (the default scene); `threads` is the number of worker threads (0: one per
/// core, at most `spraysim::max_threads()`). Results do not depend on `threads`. `backend` is
/// what flies the particles: `"cpu"`, `"gpu"` (the GPU's kernels; results equal the CPU's within
/// statistics, not to the bit) or `"auto"` (the GPU where it can, else the CPU with a
/// `RuntimeWarning`); None takes the scenario's `simulation.backend`. `step` and `run` release the
/// interpreter while they work, in slices of about 10 ms (on the GPU, at least one call of up to
/// 128 layer epochs): other Python threads run meanwhile, and Ctrl-C raises `KeyboardInterrupt`
/// within a slice, leaving the simulation valid at the step it reached.
///
/// Thread-safe: calls from several threads take turns, a call waiting (with the interpreter
/// released) until another thread's call on the same simulation has returned. A callback of a
/// call (`run`'s `progress`) cannot use its simulation: that raises `RuntimeError`.
///
/// Units: m, s, kg; angles in degrees, the unit in every name (`roll_deg`). Frame: z up,
/// gravity along −z. Float maps hold NaN in openings.
#[pyclass(module = "spraysim", name = "Simulation", frozen)]
pub struct PySimulation {
    state: Exclusive<State>,
    setup: Mutex<Setup>,
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

impl PySimulation {
    fn build(
        sim: Simulation,
        scenario: Scenario,
        threads: Threads,
        pool: Option<Arc<rayon::ThreadPool>>,
    ) -> Self {
        PySimulation {
            state: Exclusive::new(State { held: Held::new(sim), retired: Vec::new() }, "this Simulation"),
            setup: Mutex::new(Setup { scenario, threads: threads.0, pool }),
        }
    }

    /// This thread's turn with the simulation: waits for another thread's call to return.
    pub(crate) fn lock(&self, py: Python<'_>) -> PyResult<Turn<'_, State>> {
        self.state.lock(py)
    }

    /// The scenario, threads and pool, for an instant.
    fn setup(&self, py: Python<'_>) -> MutexGuard<'_, Setup> {
        // Held only to read or swap a field, never across a call: a panic cannot leave it
        // half-written.
        self.setup.lock_py_attached(py).unwrap_or_else(PoisonError::into_inner)
    }

    fn pool(&self, py: Python<'_>) -> Option<Arc<rayon::ThreadPool>> {
        self.setup(py).pool.clone()
    }

    /// Reads the simulation on this thread's turn.
    fn read<T>(&self, py: Python<'_>, f: impl FnOnce(&Simulation) -> T) -> PyResult<T> {
        Ok(f(&self.lock(py)?.held.sim))
    }
}

#[pymethods]
impl PySimulation {
    #[new]
    #[pyo3(
        signature = (scenario = None, threads = Threads::PER_CORE, backend = None),
        text_signature = "(scenario=None, threads=0, backend=None)"
    )]
    fn new(
        py: Python<'_>,
        scenario: Option<&Bound<'_, PyAny>>,
        threads: Threads,
        backend: Option<&str>,
    ) -> PyResult<Self> {
        let scenario = scenario_from(py, scenario)?;
        let pool = work::pool(threads)?;
        let stage = crate::backend::stage_for(py, backend, &scenario, "the scenario")?;
        let mut sim = Simulation::new(scenario.config()).map_err(|e| setup_error(&e))?;
        sim.set_flight_stage(stage);
        Ok(PySimulation::build(sim, scenario, threads, pool))
    }

    /// Advances the simulation by `n` time steps Δt (also past the configured duration).
    #[pyo3(signature = (n = None), text_signature = "(self, n=1)")]
    fn step(&self, py: Python<'_>, n: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let n = n.map_or(Ok(1), |n| crate::args::count(n, "n", "steps"))?;
        let pool = self.pool(py);
        let mut state = self.lock(py)?;
        let until = state.held.sim.steps_done().saturating_add(n);
        work::run_to(py, &mut state.held.sim, pool.as_deref(), until, |_| Ok(()))
    }

    /// Runs until simulated time reaches `until` (s; the configured duration when None).
    /// `progress=True` prints the simulated time to standard error as it goes; a callable is
    /// called as `progress(time_s, until_s)` about every 10 ms (it cannot use this simulation,
    /// which is busy with the run).
    #[pyo3(signature = (until = None, progress = None))]
    fn run(&self, py: Python<'_>, until: Option<f64>, progress: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let pool = self.pool(py);
        let mut state = self.lock(py)?;
        let sim = &mut state.held.sim;
        let dt = sim.config().dt;
        let steps = match until {
            Some(t) => steps_for(t, dt)?,
            None => sim.total_steps(),
        };
        let end = steps as f64 * dt;
        let report = progress::Report::new(py, progress, end)?;
        work::run_to(py, sim, pool.as_deref(), steps, |s| report.tick(py, s.time()))?;
        report.finish(py, sim.time())
    }

    /// Simulated time, s.
    #[getter]
    fn time(&self, py: Python<'_>) -> PyResult<f64> {
        self.read(py, Simulation::time)
    }

    /// Steps taken so far.
    #[getter]
    fn steps_done(&self, py: Python<'_>) -> PyResult<u64> {
        self.read(py, Simulation::steps_done)
    }

    /// Steps the configured duration takes.
    #[getter]
    fn total_steps(&self, py: Python<'_>) -> PyResult<u64> {
        self.read(py, Simulation::total_steps)
    }

    /// Time step Δt, s.
    #[getter]
    fn dt(&self, py: Python<'_>) -> f64 {
        self.setup(py).scenario.simulation().dt
    }

    /// Configured duration, s.
    #[getter]
    fn duration(&self, py: Python<'_>) -> f64 {
        self.setup(py).scenario.simulation().duration
    }

    /// True once the configured duration has been simulated.
    #[getter]
    fn is_finished(&self, py: Python<'_>) -> PyResult<bool> {
        self.read(py, Simulation::is_finished)
    }

    /// Worker threads that fly the particles (0: one per core, at most `spraysim::max_threads()`);
    /// results do not depend on it.
    #[getter]
    fn get_threads(&self, py: Python<'_>) -> usize {
        self.setup(py).threads
    }

    #[setter]
    fn set_threads(&self, py: Python<'_>, threads: Threads) -> PyResult<()> {
        let pool = work::pool(threads)?;
        let mut setup = self.setup(py);
        setup.pool = pool;
        setup.threads = threads.0;
        Ok(())
    }

    /// What flies the particles: `"cpu"` or `"gpu"`.
    #[getter]
    fn backend(&self, py: Python<'_>) -> PyResult<&'static str> {
        self.read(py, |s| if s.flight_stage().is_some() { "gpu" } else { "cpu" })
    }

    /// What flies the particles, in words: `"CPU"`, or `"GPU (adapter, driver, API)"`.
    #[getter]
    fn device(&self, py: Python<'_>) -> PyResult<String> {
        self.read(py, |s| spraysim::backend::describe(s.flight_stage().map(|g| &**g)))
    }

    /// The scenario being simulated.
    #[getter]
    fn scenario(&self, py: Python<'_>) -> PyScenario {
        PyScenario { inner: self.setup(py).scenario.clone() }
    }

    /// The targets' names, in scenario order.
    #[getter]
    fn target_names(&self, py: Python<'_>) -> Vec<String> {
        self.setup(py).scenario.targets().iter().map(|t| t.name.clone()).collect()
    }

    /// Particles emitted so far: `(count, volume in m³)`.
    fn emitted(&self, py: Python<'_>) -> PyResult<(u64, f64)> {
        let e = self.read(py, |s| s.tally().emitted.amount(s.config().volume_quantum()))?;
        Ok((e.count, e.volume))
    }

    /// The results so far as a dictionary: what `metrics.json` holds (keys, units and values;
    /// see docs/outputs.md), less its `files` manifest, with `targets` keyed by target name
    /// (the file lists them in scenario order).
    fn metrics<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        convert::metrics_to_py(py, &self.metrics_json(py)?)
    }

    /// The text `metrics.json` would hold now, without the `files` manifest that only a
    /// written set of outputs has.
    fn metrics_json(&self, py: Python<'_>) -> PyResult<String> {
        let scenario = self.setup(py).scenario.clone();
        self.read(py, |sim| spraysim::output::run_metrics_json(sim, &scenario))?.map_err(|e| output_error(&e))
    }

    /// Writes every output (`metrics.json`, `.npy` arrays, heatmaps, `scenario.resolved.toml`)
    /// into `directory` (the scenario's `output.directory` when None), as `spraysim run -o
    /// DIRECTORY` does, all or nothing. Returns the paths written.
    #[pyo3(signature = (directory = None))]
    fn write_outputs(&self, py: Python<'_>, directory: Option<std::path::PathBuf>) -> PyResult<Vec<String>> {
        let state = self.lock(py)?;
        let scenario = self.setup(py).scenario.clone();
        // As the command does: the resolved scenario names the directory it was written to.
        let scenario = match &directory {
            Some(d) => scenario.with("output.directory", d.display().to_string()).map_err(|e| {
                let called =
                    format!("Simulation.write_outputs(directory={})", py_repr(py, &d.display().to_string()));
                scenario_error(py, &relocated(e, |_| called.clone()))
            })?,
            None => scenario,
        };
        let dir = std::path::PathBuf::from(&scenario.output().directory);
        let sim = &state.held.sim;
        let files = py
            .detach(|| spraysim::output::write_outputs(sim, &scenario, &dir))
            .map_err(|e| output_error(&e))?;
        Ok(files.iter().map(|p| p.display().to_string()).collect())
    }

    /// Saves the present state; `restore` continues from it exactly as this simulation would.
    fn snapshot(&self, py: Python<'_>) -> PyResult<PySnapshot> {
        let sim = self.read(py, Simulation::clone)?;
        Ok(PySnapshot { sim, scenario: self.setup(py).scenario.clone() })
    }

    /// Returns to a saved state (of this simulation or another one). Arrays taken earlier with
    /// `copy=False` keep showing the state they were taken from.
    fn restore(&self, py: Python<'_>, snapshot: &Bound<'_, PySnapshot>) -> PyResult<()> {
        let s = snapshot.get();
        let mut state = self.lock(py)?;
        let old = std::mem::replace(&mut state.held, Held::new(s.sim.clone()));
        self.setup(py).scenario = s.scenario.clone();
        // Arrays still viewing the old state keep it alive; the others let it go.
        state.retired.push(old);
        state.retired.retain(|h| Arc::strong_count(&h.views) > 1);
        Ok(())
    }

    /// An independent copy that continues exactly as this one would.
    fn copy(&self, py: Python<'_>) -> PyResult<PySimulation> {
        let sim = self.read(py, Simulation::clone)?;
        let setup = self.setup(py);
        let copy =
            PySimulation::build(sim, setup.scenario.clone(), Threads(setup.threads), setup.pool.clone());
        Ok(copy)
    }

    fn __copy__(&self, py: Python<'_>) -> PyResult<PySimulation> {
        self.copy(py)
    }

    fn __deepcopy__(&self, py: Python<'_>, _memo: &Bound<'_, PyAny>) -> PyResult<PySimulation> {
        self.copy(py)
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let origin = self.setup(py).scenario.origin().to_string();
        self.read(py, |s| {
            format!(
                "Simulation(scenario={origin:?}, time={:.6} s of {} s, steps_done={}, in_flight={})",
                s.time(),
                s.config().duration,
                s.steps_done(),
                s.swarm().alive()
            )
        })
    }

    /// The particles in flight, as numpy arrays of one row per particle: `position` (n, 3) m,
    /// `velocity` (n, 3) m/s, `age` (n,) s since emission, `id` (n,) emission index, `impacts`
    /// (n,) impacts so far, `state` (n,) status bits (`ALIVE | HIT_SUBSTRATE | RELEASED`).
    fn particles<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        views::particles(py, &self.lock(py)?.held.sim)
    }

    /// Deposited thickness on a target (name, or index from 0), m. On a rectangle a (rows,
    /// cols) float64 array: row 0 is the target's bottom edge (rows grow along its `up`),
    /// columns grow along `right` = `up × normal` (the viewer's right, looking at the target
    /// from the spray side): plot it with `origin="lower"`. On a cylinder shell the unrolled
    /// (along the axis, around it) map; on a mesh one value per triangle, in the file's order.
    /// Cells cut away by openings hold NaN, as in the `.npy` files (`mask(target)` is False
    /// there): use `np.nanmean` and the like. With `copy=False` (the default) a read-only view
    /// of the simulation's own memory, no copy, when the target has no openings: it shows later
    /// steps as they happen (do not read it while another thread runs this simulation); a
    /// target with openings, or `copy=True`, gives an independent array. An unknown name raises
    /// `KeyError`, a negative or too large index `IndexError`, both listing the targets.
    #[pyo3(signature = (target, copy = false))]
    fn thickness<'py>(
        slf: &Bound<'py, Self>,
        target: &Bound<'py, PyAny>,
        copy: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        views::float_map(slf, target, copy, |t| t.surface.thickness())
    }

    /// Where a target's surface is: a bool array laid out as `thickness`, True on the
    /// surface, False in cells cut away by openings (where `thickness` holds NaN).
    fn mask<'py>(&self, py: Python<'py>, target: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        views::mask(py, &self.lock(py)?.held.sim, target)
    }

    /// Impacts per cell (stuck or rebounded) on a target (name or index): a uint32 array laid
    /// out as `thickness` (0 in openings: see `mask`), viewed or copied as `copy` says.
    #[pyo3(signature = (target, copy = false))]
    fn hits<'py>(
        slf: &Bound<'py, Self>,
        target: &Bound<'py, PyAny>,
        copy: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        views::grid(slf, target, copy, |t| t.surface.hits())
    }

    /// Eroded depth per cell on a target (name or index), m, laid out as `thickness` (a copy,
    /// NaN in openings), or None when the process erodes nothing.
    fn erosion<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        views::erosion(py, &self.lock(py)?.held.sim, target)
    }

    /// Coating left per cell on a target (name or index), m, laid out as `thickness` (a copy,
    /// NaN in openings; 0 where blasting cleaned to bare substrate), or None when the process
    /// erodes nothing. It starts at the target's `coating`.
    fn coating<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        views::coating(py, &self.lock(py)?.held.sim, target)
    }

    /// The dry film per cell on a target (name or index), m: the wet `thickness` times the
    /// paint's `process.volume_solids`, laid out as `thickness` (a copy, NaN in openings), or
    /// None when the scenario gives no volume solids.
    fn dry_thickness<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        views::dry_thickness(py, &self.lock(py)?.held.sim, target)
    }

    /// A target's geometry (name or index): `name`, `role`, `shape`, `cells`, `solid_cells`
    /// (cells not cut away by openings), `rows`, `cols`, `cell_size` (width, height) m, `size`
    /// (width, height) m, and unit vectors `normal`, `up`, `right` and the `center` (m) as
    /// numpy arrays; a shell's `axis`, `radius`, `angles_deg` and `side`.
    fn target_info<'py>(&self, py: Python<'py>, target: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
        views::target_info(py, &self.lock(py)?.held.sim, target)
    }

    /// The surface of a rectangle or a cylinder shell at the unrolled coordinates `(u, v)` (m
    /// from the middle of its map, `u` along its columns, `v` along its rows), raised by
    /// `height` (m) on the receiving side: `position` (m), the receiving unit `normal`, and the
    /// unit directions `right` (growing `u`) and `up` (growing `v`) there. A mesh raises
    /// `ValueError`.
    #[pyo3(signature = (target, u, v, height = 0.0))]
    fn surface_frame<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
        u: f64,
        v: f64,
        height: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        views::surface_frame(py, &self.lock(py)?.held.sim, target, [u, v, height])
    }

    /// The nozzle now: `position` (m), unit `axis`, `quaternion` (w, x, y, z: the rotation
    /// taking the tool's x, y, z axes to the aperture's width axis, its height axis and the
    /// spray axis), the 4 × 4 pose `matrix` (columns: those three axes and the position),
    /// `velocity` (m/s) as numpy arrays, `roll_deg` and `spraying` (bool).
    fn nozzle<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        nozzle::pose(py, &self.lock(py)?.held.sim)
    }

    /// Holds the nozzle at a pose from the next step on, spraying or not as `spray` says
    /// (closed-loop control). The pose is `position` (m, three finite numbers within ±10⁴ m, as
    /// in scenario files) with one orientation: `axis` (the spray direction, a finite non-zero
    /// vector, normalised), `quaternion` (w, x, y, z: scalar first; the spray axis is the
    /// tool's z axis rotated by it, as in `nozzle.path_csv`), or none (the present axis); or
    /// `matrix`, a 4 × 4 homogeneous pose (rotation and position; the spray axis is its third
    /// column) given without `position`. The rotation about the spray axis is the path's roll
    /// (`roll_deg` of `set_nozzle_path`), not the quaternion's or matrix's.
    #[pyo3(signature = (position = None, axis = None, spray = true, *, quaternion = None, matrix = None))]
    fn set_nozzle(
        &self,
        py: Python<'_>,
        position: Option<&Bound<'_, PyAny>>,
        axis: Option<&Bound<'_, PyAny>>,
        spray: bool,
        quaternion: Option<&Bound<'_, PyAny>>,
        matrix: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let pose = nozzle::Pose::read(&nozzle::PoseArgs { position, axis, quaternion, matrix })?;
        nozzle::hold(&mut self.lock(py)?.held.sim, pose, spray)
    }

    /// Replaces the nozzle's path from the next step on. `waypoints` is a list of dicts with
    /// `time` (s, absolute simulated time, strictly increasing), `position` (m, within ±10⁴ m)
    /// and one orientation, `axis`, `quaternion` (w, x, y, z) or `matrix` (4 × 4, holding the
    /// position instead of `position`), as `set_nozzle` takes them, and optionally `spray`
    /// (default True: spray from this waypoint until the next); other keys are refused. A
    /// `(time, position, axis[, spray])` tuple is a waypoint too. Position is interpolated
    /// linearly, the axis spherically; before the first and after the last waypoint the
    /// nozzle holds that pose. `roll_deg` (degrees) turns the aperture about the axis (the
    /// present roll when None); `roll` (radians) is its deprecated former name.
    #[pyo3(signature = (waypoints, roll_deg = None, *, roll = None))]
    fn set_nozzle_path(
        &self,
        py: Python<'_>,
        waypoints: &Bound<'_, PyAny>,
        roll_deg: Option<f64>,
        roll: Option<f64>,
    ) -> PyResult<()> {
        let roll = nozzle::roll(py, roll_deg, roll)?;
        let list = nozzle::read_path(waypoints)?;
        nozzle::set_path(&mut self.lock(py)?.held.sim, list, roll)
    }

    /// The nozzle's path as flown, as a list of waypoint dicts (`time`, `position`, `axis`,
    /// `spray`) that `set_nozzle_path` takes back: the path's own waypoints when no circle is
    /// superposed on it; with a circle (a circling nozzle, a raster with `circle_radius`), the
    /// path sampled `samples_per_turn` times per revolution (and at each of its own
    /// waypoints), circle included, from its first waypoint to its last or to the configured
    /// duration, whichever is later. `nozzle_path()` gives the path's parts exactly.
    #[pyo3(signature = (samples_per_turn = None), text_signature = "(self, samples_per_turn=16)")]
    fn nozzle_waypoints<'py>(
        &self,
        py: Python<'py>,
        samples_per_turn: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, pyo3::types::PyList>> {
        let samples =
            samples_per_turn.map_or(Ok(16), |n| crate::args::count(n, "samples_per_turn", "samples"))?;
        nozzle::waypoints(py, &self.lock(py)?.held.sim, samples)
    }

    /// The nozzle's path exactly: `waypoints` (its own, without the circle), `roll_deg`, and
    /// `circle`, None or a dict of its `radius` (m), `frequency` (Hz), `start` (s, when the
    /// offset is `radius · first`) and unit vectors `first`, `second` (the offset a quarter
    /// turn later) and `axis` (the spray axis the circle's plane is perpendicular to).
    fn nozzle_path<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        nozzle::path(py, &self.lock(py)?.held.sim)
    }

    /// The nozzle's pose at each of `times` (s, any order), circle included, without running:
    /// `position` (n, 3) m, `axis` (n, 3) and `spraying` (n,) bool, as numpy arrays.
    fn nozzle_at<'py>(&self, py: Python<'py>, times: Vec<f64>) -> PyResult<Bound<'py, PyDict>> {
        nozzle::sample(py, &self.lock(py)?.held.sim, times)
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
