//! The nozzle of a running simulation: its pose now, and replacing its path between steps.

use crate::args::short_repr;
use glam::DVec3;
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use spraysim::Simulation;
use spraysim::emission::{NozzlePath, Waypoint};
use spraysim::scenario::MAX_COORD;

/// The keys of a waypoint given as a dict, in the order of a waypoint given as a tuple.
const WAYPOINT_KEYS: [&str; 4] = ["time", "position", "axis", "spray"];

/// A finite 3-vector from any sequence of three numbers; `what` names it in errors.
fn vec3(value: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let v: Vec<f64> = value.extract().map_err(|_| {
        PyValueError::new_err(format!("`{what}` must be three numbers, got {}", short_repr(value)))
    })?;
    match v.as_slice() {
        &[x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(DVec3::new(x, y, z)),
        _ => Err(PyValueError::new_err(format!("`{what}` must be three finite numbers, got {v:?}"))),
    }
}

/// A position, m: three finite numbers within ±[`MAX_COORD`] m of the origin, as a scenario
/// file's points are.
fn position(value: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let p = vec3(value, what)?;
    if p.abs().max_element() > MAX_COORD {
        return Err(PyValueError::new_err(format!(
            "`{what}` must lie within ±{MAX_COORD} m of the origin on every axis (as in scenario files), \
             got {:?} m",
            p.to_array()
        )));
    }
    Ok(p)
}

/// A unit vector along a non-zero finite 3-vector (of any length: it is scaled before it is
/// normalised, so that neither a huge nor a tiny one overflows).
fn direction(value: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let v = vec3(value, what)?;
    let largest = v.abs().max_element();
    (v / largest).try_normalize().filter(|_| largest > 0.0).ok_or_else(|| {
        PyValueError::new_err(format!("`{what}` must be a non-zero direction, got {:?}", v.to_array()))
    })
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

/// A pose asked for by `Simulation.set_nozzle`, checked.
pub struct Pose {
    /// Position, m.
    position: DVec3,
    /// Unit axis, or None to keep the present one.
    axis: Option<DVec3>,
}

impl Pose {
    /// Reads `position` (m) and `axis` (None: the present one), refusing what the engine
    /// cannot follow: non-finite numbers, a zero axis, a position beyond ±[`MAX_COORD`] m.
    pub fn read(position_value: &Bound<'_, PyAny>, axis: Option<&Bound<'_, PyAny>>) -> PyResult<Pose> {
        let position = position(position_value, "position")?;
        let axis = axis.filter(|a| !a.is_none()).map(|a| direction(a, "axis")).transpose()?;
        Ok(Pose { position, axis })
    }
}

/// Holds the nozzle at `pose` from the next step on.
pub fn hold(sim: &mut Simulation, pose: Pose, spray: bool) -> PyResult<()> {
    let axis = pose.axis.unwrap_or_else(|| sim.nozzle().at(sim.time()).0.axis);
    let roll = sim.nozzle().roll();
    let time = sim.time();
    let waypoint = Waypoint { time, position: pose.position, axis, spray };
    replace(sim, NozzlePath::through(vec![waypoint], roll))
}

/// Gives the engine a path read here; it checks the path again and refuses it unchanged.
fn replace(sim: &mut Simulation, path: NozzlePath) -> PyResult<()> {
    sim.set_nozzle_path(path)
        .map_err(|e| PyValueError::new_err(format!("the nozzle's path was refused: {e}")))
}

/// One waypoint from a dict (with the keys [`WAYPOINT_KEYS`] and no other) or a
/// `(time, position, axis[, spray])` tuple.
fn waypoint(item: &Bound<'_, PyAny>, i: usize) -> PyResult<Waypoint> {
    let at = |k: &str| format!("waypoints[{i}].{k}");
    let accepted = WAYPOINT_KEYS.join(", ");
    let fields: Vec<Option<Bound<'_, PyAny>>> = if let Ok(d) = item.cast::<PyDict>() {
        for k in d.keys() {
            let known = k.extract::<String>().is_ok_and(|k| WAYPOINT_KEYS.contains(&k.as_str()));
            if !known {
                return Err(PyValueError::new_err(format!(
                    "`waypoints[{i}]` has an unknown key {}: a waypoint's keys are {accepted}",
                    short_repr(&k)
                )));
            }
        }
        WAYPOINT_KEYS.iter().map(|k| d.get_item(k)).collect::<PyResult<_>>()?
    } else {
        let shape = || {
            format!(
                "`waypoints[{i}]` must be a dict (keys {accepted}) or a (time, position, axis[, spray]) tuple"
            )
        };
        let seq: Vec<Bound<'_, PyAny>> = item.extract().map_err(|_| PyValueError::new_err(shape()))?;
        if seq.len() > WAYPOINT_KEYS.len() {
            return Err(PyValueError::new_err(format!("{}, got {} items", shape(), seq.len())));
        }
        (0..WAYPOINT_KEYS.len()).map(|n| seq.get(n).cloned()).collect()
    };
    let missing = |k: &str| PyValueError::new_err(format!("`{}` is missing", at(k)));
    let [time, position_value, axis, spray] = <[Option<Bound<'_, PyAny>>; 4]>::try_from(fields)
        .map_err(|_| PyValueError::new_err(format!("`waypoints[{i}]` must have {accepted}")))?;
    let time: f64 = time
        .ok_or_else(|| missing("time"))?
        .extract()
        .map_err(|_| PyValueError::new_err(format!("`{}` must be a number of seconds", at("time"))))?;
    if !time.is_finite() {
        return Err(PyValueError::new_err(format!("`{}` must be finite, got {time}", at("time"))));
    }
    let position = position(&position_value.ok_or_else(|| missing("position"))?, &at("position"))?;
    let axis = direction(&axis.ok_or_else(|| missing("axis"))?, &at("axis"))?;
    let spray = match spray {
        Some(s) => s.is_truthy()?,
        None => true,
    };
    Ok(Waypoint { time, position, axis, spray })
}

/// Reads a nozzle path: `waypoints` in strictly increasing time, at least one, and `roll`
/// (rad) finite when given.
pub fn read_path(waypoints: &Bound<'_, PyAny>, roll: Option<f64>) -> PyResult<Vec<Waypoint>> {
    let mut list = Vec::new();
    let items = waypoints.try_iter().map_err(|_| {
        PyValueError::new_err(format!(
            "`waypoints` must be a list of waypoints, got {}",
            crate::args::type_name(waypoints)
        ))
    })?;
    for (i, item) in items.enumerate() {
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
    if let Some(r) = roll
        && !r.is_finite()
    {
        return Err(PyValueError::new_err(format!("`roll` must be finite, got {r}")));
    }
    Ok(list)
}

/// Replaces the nozzle's path with one through `list` (read by [`read_path`]), turned by
/// `roll` (rad; the present roll when None).
pub fn set_path(sim: &mut Simulation, list: Vec<Waypoint>, roll: Option<f64>) -> PyResult<()> {
    let roll = roll.unwrap_or_else(|| sim.nozzle().roll());
    replace(sim, NozzlePath::through(list, roll))
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
