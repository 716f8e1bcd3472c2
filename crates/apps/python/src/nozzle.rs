//! The nozzle of a running simulation: its pose now, and replacing its path between steps.

use glam::DVec3;
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use spraysim::Simulation;
use spraysim::emission::{NozzlePath, Waypoint};

/// A finite 3-vector from any sequence of three numbers; `what` names it in errors.
fn vec3(value: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let v: Vec<f64> = value
        .extract()
        .map_err(|_| PyValueError::new_err(format!("`{what}` must be three numbers, got {value}")))?;
    match v.as_slice() {
        &[x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(DVec3::new(x, y, z)),
        _ => Err(PyValueError::new_err(format!("`{what}` must be three finite numbers, got {v:?}"))),
    }
}

/// A unit vector from a non-zero finite 3-vector.
fn direction(value: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let v = vec3(value, what)?;
    if v.length() < 1e-12 {
        return Err(PyValueError::new_err(format!("`{what}` must not be zero")));
    }
    Ok(v.normalize())
}

fn array<'py>(py: Python<'py>, v: DVec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, &v.to_array())
}

/// The nozzle's pose, velocity and spray state now.
pub fn pose<'py>(py: Python<'py>, sim: &Simulation) -> PyResult<Bound<'py, PyDict>> {
    let t = sim.time();
    let (frame, spraying) = sim.nozzle().at(t);
    let d = PyDict::new(py);
    d.set_item("position", array(py, frame.position))?;
    d.set_item("axis", array(py, frame.axis))?;
    d.set_item("velocity", array(py, sim.nozzle().velocity(t)))?;
    d.set_item("spraying", spraying)?;
    Ok(d)
}

/// Holds the nozzle at a pose from the next step on.
pub fn hold(
    sim: &mut Simulation,
    position: &Bound<'_, PyAny>,
    axis: Option<&Bound<'_, PyAny>>,
    spray: bool,
) -> PyResult<()> {
    let position = vec3(position, "position")?;
    let axis = match axis.filter(|a| !a.is_none()) {
        Some(a) => direction(a, "axis")?,
        None => sim.nozzle().at(sim.time()).0.axis,
    };
    let roll = sim.nozzle().roll();
    let time = sim.time();
    sim.set_nozzle_path(NozzlePath::through(vec![Waypoint { time, position, axis, spray }], roll));
    Ok(())
}

/// One waypoint from a dict or a `(time, position, axis[, spray])` tuple.
fn waypoint(item: &Bound<'_, PyAny>, i: usize) -> PyResult<Waypoint> {
    let at = |k: &str| format!("waypoints[{i}].{k}");
    let field = |k: &str, n: usize| -> PyResult<Option<Bound<'_, PyAny>>> {
        if let Ok(d) = item.cast::<PyDict>() {
            return d.get_item(k);
        }
        let seq: Vec<Bound<'_, PyAny>> = item.extract().map_err(|_| {
            PyValueError::new_err(format!(
                "`waypoints[{i}]` must be a dict or a (time, position, axis[, spray]) tuple"
            ))
        })?;
        Ok(seq.get(n).cloned())
    };
    let missing = |k: &str| PyValueError::new_err(format!("`{}` is missing", at(k)));
    let time: f64 = field("time", 0)?.ok_or_else(|| missing("time"))?.extract()?;
    if !time.is_finite() {
        return Err(PyValueError::new_err(format!("`{}` must be finite, got {time}", at("time"))));
    }
    let position = vec3(&field("position", 1)?.ok_or_else(|| missing("position"))?, &at("position"))?;
    let axis = direction(&field("axis", 2)?.ok_or_else(|| missing("axis"))?, &at("axis"))?;
    let spray = match field("spray", 3)? {
        Some(s) => s.is_truthy()?,
        None => true,
    };
    Ok(Waypoint { time, position, axis, spray })
}

/// Replaces the nozzle's path with one through `waypoints`.
pub fn set_path(sim: &mut Simulation, waypoints: &Bound<'_, PyAny>, roll: Option<f64>) -> PyResult<()> {
    let mut list = Vec::new();
    for (i, item) in waypoints.try_iter()?.enumerate() {
        let w = waypoint(&item?, i)?;
        if let Some(prev) = list.last().map(|p: &Waypoint| p.time)
            && w.time <= prev
        {
            return Err(PyValueError::new_err(format!(
                "`waypoints[{i}].time` must be later than the waypoint before ({prev} s), got {} s",
                w.time
            )));
        }
        list.push(w);
    }
    if list.is_empty() {
        return Err(PyValueError::new_err("`waypoints` must hold at least one waypoint"));
    }
    let roll = roll.unwrap_or_else(|| sim.nozzle().roll());
    if !roll.is_finite() {
        return Err(PyValueError::new_err(format!("`roll` must be finite, got {roll}")));
    }
    sim.set_nozzle_path(NozzlePath::through(list, roll));
    Ok(())
}

/// The nozzle's waypoints as a list of dicts.
pub fn waypoints<'py>(py: Python<'py>, sim: &Simulation) -> PyResult<Bound<'py, PyList>> {
    let out = PyList::empty(py);
    for w in sim.nozzle().waypoints() {
        let d = PyDict::new(py);
        d.set_item("time", w.time)?;
        d.set_item("position", array(py, w.position))?;
        d.set_item("axis", array(py, w.axis))?;
        d.set_item("spray", w.spray)?;
        out.append(d)?;
    }
    Ok(out)
}
