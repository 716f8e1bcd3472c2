//! `spraysim.Scenario`: a validated, immutable scenario, and the presets.

use crate::convert::{self, Refused};
use crate::errors::{refusal, relocated, scenario_error};
use pyo3::exceptions::{PyKeyError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use spraysim::Scenario;
use spraysim::scenario::{Preset, Value};

/// A complete, validated scenario: every default filled in (see `docs/scenario.md` for every
/// key, its unit and its default). Immutable: `set` returns a new scenario with one value
/// overridden, checked exactly as a file's value or the command's `--set` would be; a refusal
/// raises `ScenarioError` naming the key.
///
/// `Scenario()` is the built-in default scene (shotcrete onto a 2 m × 2 m wall from 1 m, with
/// a floor collecting the rebound); `Scenario(x)` reads a file (`str` or path), a `dict` or
/// copies a scenario. Two scenarios are equal when they resolve to the same values.
#[pyclass(module = "spraysim", name = "Scenario", frozen)]
#[derive(Clone)]
pub struct PyScenario {
    pub(crate) inner: Scenario,
}

/// The scenario `source` stands for: None (the default scene), a `Scenario`, a `dict`, or a
/// file path (`str` or `os.PathLike`).
pub fn scenario_from(py: Python<'_>, source: Option<&Bound<'_, PyAny>>) -> PyResult<Scenario> {
    match source.filter(|s| !s.is_none()) {
        None => Ok(Scenario::default_scene()),
        Some(s) => read(py, s, "<dict>"),
    }
}

/// The scenario `source` stands for: a `Scenario`, a `dict` (named `origin` in errors), or a
/// file path (`str` or `os.PathLike`).
pub fn read(py: Python<'_>, source: &Bound<'_, PyAny>, origin: &str) -> PyResult<Scenario> {
    if let Ok(s) = source.cast::<PyScenario>() {
        return Ok(s.get().inner.clone());
    }
    if let Ok(d) = source.cast::<PyDict>() {
        return from_dict(py, d, origin);
    }
    if source.is_instance_of::<PyString>() || source.hasattr("__fspath__")? {
        let path: std::path::PathBuf = source.extract()?;
        return Scenario::from_path(&path).map_err(|e| scenario_error(py, &e));
    }
    Err(PyTypeError::new_err(format!(
        "a scenario is a Scenario, a dict or a file path, not a {}",
        crate::args::type_name(source)
    )))
}

/// Reads a scenario from a dictionary shaped like the TOML file.
fn from_dict(py: Python<'_>, dict: &Bound<'_, PyDict>, origin: &str) -> PyResult<Scenario> {
    let table = convert::dict_to_toml(dict, "").map_err(|r| refused(py, origin, r))?;
    let text = toml::to_string(&table).map_err(|e| refusal(py, None, Some(origin.into()), e.to_string()))?;
    Scenario::from_toml(&text, origin).map_err(|e| {
        // Lines of the TOML text made from the dictionary would mean nothing to its author.
        use spraysim::ScenarioError as E;
        match e {
            E::Invalid { key, message, .. } => refusal(py, Some(key), Some(origin.into()), message),
            E::Syntax { message, .. } => refusal(py, None, Some(origin.into()), message),
            other => scenario_error(py, &other),
        }
    })
}

/// The `ScenarioError` for a Python value that has no TOML form.
fn refused(py: Python<'_>, location: &str, r: Refused) -> PyErr {
    refusal(py, Some(r.key), Some(location.to_string()), r.message)
}

#[pymethods]
impl PyScenario {
    /// `Scenario()`: the default scene; `Scenario(path)`: a scenario file; `Scenario(dict)`: a
    /// dictionary shaped like the file; `Scenario(scenario)`: the same scenario.
    #[new]
    #[pyo3(signature = (source = None))]
    fn new(py: Python<'_>, source: Option<&Bound<'_, PyAny>>) -> PyResult<Self> {
        Ok(PyScenario { inner: scenario_from(py, source)? })
    }

    /// The built-in default scene: wet-mix shotcrete for 2 s onto a 2 m × 2 m wall from 1 m,
    /// with a floor in front of the wall that collects the rebound.
    #[staticmethod]
    fn default() -> Self {
        PyScenario { inner: Scenario::default_scene() }
    }

    /// Reads and validates a scenario file (TOML). Paths it names (meshes, tool paths) are read
    /// relative to the file's folder.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        let inner = Scenario::from_path(&path).map_err(|e| scenario_error(py, &e))?;
        Ok(PyScenario { inner })
    }

    /// Parses and validates scenario text (TOML); `origin` names it in errors. Paths it names
    /// are read relative to the working directory.
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<string>"))]
    fn from_toml(py: Python<'_>, text: &str, origin: &str) -> PyResult<Self> {
        let inner = Scenario::from_toml(text, origin).map_err(|e| scenario_error(py, &e))?;
        Ok(PyScenario { inner })
    }

    /// Reads a scenario from a dictionary shaped like the TOML file (`{"simulation":
    /// {"duration": 1.0}, "target": [{"name": "wall", ...}]}`), with the same checks.
    #[staticmethod]
    #[pyo3(signature = (data, origin = "<dict>"))]
    fn from_dict(py: Python<'_>, data: &Bound<'_, PyDict>, origin: &str) -> PyResult<Self> {
        Ok(PyScenario { inner: from_dict(py, data, origin)? })
    }

    /// This scenario with the dotted `key` (`"emitter.spawn_rate"`, `"target[0].resolution"`,
    /// `"nozzle.raster.speed"`; 0-based list indices) set to `value` (a number, bool, string,
    /// list or dict, in the file's units), validated as if the file had said so. Raises
    /// `ScenarioError` naming the key when refused.
    fn set(&self, py: Python<'_>, key: &str, value: &Bound<'_, PyAny>) -> PyResult<Self> {
        self.set_many_pairs(py, vec![(key.to_string(), value.clone())], Setter::Set)
    }

    /// `set` for several keys at once, applied in order: a dict `{key: value}` or pairs.
    fn set_many(&self, py: Python<'_>, overrides: &Bound<'_, PyAny>) -> PyResult<Self> {
        let items = match overrides.cast::<PyDict>() {
            Ok(d) => d.items().into_any(),
            Err(_) => overrides.clone(),
        };
        let pairs = items.extract::<Vec<(String, Bound<'_, PyAny>)>>()?;
        self.set_many_pairs(py, pairs, Setter::SetMany)
    }

    /// `set` from `"KEY=VALUE"` text exactly as the command's `--set` takes it: the value is TOML
    /// (`3`, `2e4`, `[20, 28]`, `"painting"`) or a bare word taken as a string.
    fn assign(&self, py: Python<'_>, assignment: &str) -> PyResult<Self> {
        let key = |a: &str| a.split_once('=').map(|(k, _)| k.trim().to_string());
        let inner = self.inner.with_assignment(assignment).map_err(|e| {
            let e = relocated(e, |given| {
                if given == assignment || key(given) == key(assignment) {
                    format!("Scenario.assign({})", py_repr(py, assignment))
                } else {
                    earlier(py, given)
                }
            });
            scenario_error(py, &e)
        })?;
        Ok(PyScenario { inner })
    }

    /// The resolved value at a dotted key (`"emitter.speed"`, `"target[0].name"`), as in
    /// `to_dict()`. Raises `KeyError` for a key the resolved scenario does not hold.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let text = self.inner.to_toml();
        let table: toml::Table =
            toml::from_str(&text).map_err(|e| PyKeyError::new_err(format!("{key}: {e}")))?;
        let missing = || PyKeyError::new_err(format!("the resolved scenario has no `{key}`"));
        let mut at = toml::Value::Table(table);
        for part in key.split('.') {
            let (name, index) = match part.split_once('[') {
                Some((n, i)) => (n, Some(i.trim_end_matches(']').parse::<usize>().map_err(|_| missing())?)),
                None => (part, None),
            };
            at = at.get(name).cloned().ok_or_else(missing)?;
            if let Some(i) = index {
                at = at.get(i).cloned().ok_or_else(missing)?;
            }
        }
        convert::to_py(py, &at)
    }

    /// The scenario as TOML with every value explicit; reading it back gives an equal scenario
    /// (what runs write as `scenario.resolved.toml`, without the header).
    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    /// The resolved scenario as a dictionary shaped like the file (`Scenario.from_dict` reads it
    /// back to an equal scenario).
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let table: toml::Table = toml::from_str(&self.inner.to_toml())
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
        convert::to_py(py, &table)
    }

    /// Where the scenario came from: a file name, `"<default scene>"`, `"<dict>"`, or the origin
    /// given to `from_toml`.
    #[getter]
    fn origin(&self) -> &str {
        self.inner.origin()
    }

    /// Time step Δt, s.
    #[getter]
    fn dt(&self) -> f64 {
        self.inner.simulation().dt
    }

    /// Simulated duration, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.inner.simulation().duration
    }

    /// Seed of every random stream.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.simulation().seed
    }

    /// When the nozzle stops spraying for good, s, worked out from its motion (waypoints, tool
    /// path, raster and its speed) without running anything; None when it sprays until the run
    /// ends (a static or circling nozzle, or a path whose last waypoint sprays). May lie past
    /// `duration`, when the run stops before the path does.
    #[getter]
    fn spray_end(&self) -> Option<f64> {
        let end = self.inner.config().nozzle.spray_end();
        end.is_finite().then_some(end)
    }

    /// When the nozzle's path reaches its last waypoint, s (0 for a static or circling
    /// nozzle), without running anything.
    #[getter]
    fn path_end(&self) -> f64 {
        let config = self.inner.config();
        let path = &config.nozzle;
        if path.waypoints().len() < 2 {
            return 0.0;
        }
        path.waypoints().last().map_or(0.0, |w| w.time)
    }

    /// The targets' names, in file order.
    #[getter]
    fn target_names(&self) -> Vec<String> {
        self.inner.targets().iter().map(|t| t.name.clone()).collect()
    }

    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other.cast::<PyScenario>().is_ok_and(|o| o.get().inner == self.inner)
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario(origin={:?}, duration={} s, dt={} s, targets={:?})",
            self.inner.origin(),
            self.duration(),
            self.dt(),
            self.target_names()
        )
    }

    /// Pickling (for multiprocessing and Ray): the resolved TOML text and the origin.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, (String, String))> {
        let rebuild = slf.get_type().getattr("from_toml")?;
        let s = slf.get();
        Ok((rebuild, (s.inner.to_toml(), s.inner.origin().to_string())))
    }
}

/// The Python method that set values, to name it in errors.
#[derive(Clone, Copy)]
enum Setter {
    /// `Scenario.set(key, value)`.
    Set,
    /// `Scenario.set_many({key: value})`.
    SetMany,
}

impl PyScenario {
    fn set_many_pairs(
        &self,
        py: Python<'_>,
        pairs: Vec<(String, Bound<'_, PyAny>)>,
        setter: Setter,
    ) -> PyResult<Self> {
        // How each pair is named in errors: the call that gave it, with the value as given.
        let call = |key: &str, value: &Bound<'_, PyAny>| {
            let (key, value) = (py_repr(py, key), crate::args::short_repr(value));
            match setter {
                Setter::Set => format!("Scenario.set({key}, {value})"),
                Setter::SetMany => format!("Scenario.set_many({{{key}: {value}}})"),
            }
        };
        let mut overrides = Vec::with_capacity(pairs.len());
        let mut named = Vec::with_capacity(pairs.len());
        for (key, value) in &pairs {
            let v = convert::to_toml(value, key).map_err(|r| refused(py, &call(key, value), r))?;
            let text = v.to_string();
            named.push((format!("{key}={text}"), call(key, value)));
            overrides.push((key.clone(), Value::Toml(text)));
        }
        let inner = self.inner.with_all(&overrides).map_err(|e| {
            let e = relocated(e, |assignment| match named.iter().rev().find(|(a, _)| a == assignment) {
                Some((_, call)) => call.clone(),
                None => earlier(py, assignment),
            });
            scenario_error(py, &e)
        })?;
        Ok(PyScenario { inner })
    }
}

/// `text` as a Python string literal (`'emitter.speed'`).
pub(crate) fn py_repr(py: Python<'_>, text: &str) -> String {
    let s = PyString::new(py, text);
    s.repr().map_or_else(|_| format!("{text:?}"), |r| r.to_string())
}

/// How an override made by an earlier call (`KEY=VALUE`, the value as TOML) is named in errors.
fn earlier(py: Python<'_>, assignment: &str) -> String {
    match assignment.split_once('=') {
        Some((key, value)) => format!("Scenario.set({}, {value})", py_repr(py, key)),
        None => format!("Scenario.assign({})", py_repr(py, assignment)),
    }
}

/// The process presets (the paper's Table 1) by name (`"shotcrete"`, `"painting"`,
/// `"blasting"`): each preset's `process` and `emitter` sections as dictionaries, in the
/// file's units.
#[pyfunction]
pub fn presets(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let out = PyDict::new(py);
    for preset in Preset::ALL {
        let sections = PyDict::new(py);
        sections.set_item("process", convert::to_py(py, &preset.resolved_process())?)?;
        sections.set_item("emitter", convert::to_py(py, &preset.resolved_emitter())?)?;
        out.set_item(preset.name(), sections)?;
    }
    Ok(out)
}

/// The presets as TOML with units and sources, as `spraysim presets` prints them.
#[pyfunction]
pub fn presets_toml() -> String {
    spraysim::scenario::presets_toml()
}
