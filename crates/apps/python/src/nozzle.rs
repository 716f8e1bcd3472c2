//! The nozzle of a running simulation: its pose now, and replacing its path between steps.

use crate::args::short_repr;
use glam::{DQuat, DVec3};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use spraysim::Simulation;
use spraysim::emission::{NozzleFrame, NozzlePath, Waypoint};
use spraysim::scenario::MAX_COORD;

/// The keys a waypoint dict may have. A tuple waypoint is `(time, position, axis[, spray])`.
const WAYPOINT_KEYS: [&str; 6] = ["time", "position", "axis", "quaternion", "matrix", "spray"];

/// How far a pose matrix's rotation part may be from orthonormal, and its last row from
/// `[0, 0, 0, 1]`.
const MATRIX_TOLERANCE: f64 = 1e-6;

/// Most samples `nozzle_waypoints` gives for a path with a circle.
const MAX_SAMPLES: f64 = 1e6;

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
    check_reach(p, what)?;
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

/// A list of `n` finite numbers from any sequence; `what` names it in errors.
fn numbers(value: &Bound<'_, PyAny>, n: usize, what: &str, shape: &str) -> PyResult<Vec<f64>> {
    let v: Vec<f64> = value
        .extract()
        .map_err(|_| PyValueError::new_err(format!("`{what}` must be {shape}, got {}", short_repr(value))))?;
    if v.len() != n || !v.iter().all(|x| x.is_finite()) {
        return Err(PyValueError::new_err(format!("`{what}` must be {shape} of finite numbers, got {v:?}")));
    }
    Ok(v)
}

/// The spray axis a unit quaternion `(w, x, y, z)` (scalar first; of any length, normalised)
/// gives: the tool's z axis rotated by it, as for `nozzle.path_csv`.
fn quaternion_axis(value: &Bound<'_, PyAny>, what: &str) -> PyResult<DVec3> {
    let q = numbers(value, 4, what, "four numbers (w, x, y, z)")?;
    let largest = q.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    let zero =
        || PyValueError::new_err(format!("`{what}` must be a non-zero quaternion (w, x, y, z), got {q:?}"));
    if largest == 0.0 {
        return Err(zero());
    }
    let quat = DQuat::from_xyzw(q[1] / largest, q[2] / largest, q[3] / largest, q[0] / largest);
    let length = quat.length();
    if length <= 1e-9 {
        return Err(zero());
    }
    Ok(((quat / length) * DVec3::Z).normalize())
}

/// The position (m) and spray axis of a 4 × 4 homogeneous pose matrix: the translation column
/// and the rotated z axis (third column). Its rotation part must be orthonormal and right-handed
/// and its last row `[0, 0, 0, 1]`, within [`MATRIX_TOLERANCE`].
fn matrix_pose(value: &Bound<'_, PyAny>, what: &str) -> PyResult<(DVec3, DVec3)> {
    let shape = "a 4 × 4 matrix (four rows of four numbers)";
    let rows: Vec<Bound<'_, PyAny>> = value
        .extract()
        .map_err(|_| PyValueError::new_err(format!("`{what}` must be {shape}, got {}", short_repr(value))))?;
    if rows.len() != 4 {
        return Err(PyValueError::new_err(format!("`{what}` must be {shape}, got {} rows", rows.len())));
    }
    let mut m = [[0.0; 4]; 4];
    for (i, row) in rows.iter().enumerate() {
        let r = numbers(row, 4, &format!("{what}[{i}]"), "four numbers")?;
        m[i].copy_from_slice(&r);
    }
    let column = |j: usize| DVec3::new(m[0][j], m[1][j], m[2][j]);
    let rotation = glam::DMat3::from_cols(column(0), column(1), column(2));
    let off_identity = (rotation.transpose() * rotation - glam::DMat3::IDENTITY)
        .to_cols_array()
        .iter()
        .fold(0.0_f64, |a, x| a.max(x.abs()));
    if off_identity > MATRIX_TOLERANCE || rotation.determinant() <= 0.0 {
        return Err(PyValueError::new_err(format!(
            "`{what}`: its upper-left 3 × 3 block must be a rotation (orthonormal columns, determinant +1, \
             within {MATRIX_TOLERANCE}), got {:?}",
            rotation.transpose().to_cols_array_2d()
        )));
    }
    let last = [m[3][0], m[3][1], m[3][2], m[3][3] - 1.0];
    if last.iter().any(|x| x.abs() > MATRIX_TOLERANCE) {
        return Err(PyValueError::new_err(format!(
            "`{what}`: its last row must be [0, 0, 0, 1], got {:?}",
            m[3]
        )));
    }
    let position = column(3);
    check_reach(position, &format!("{what}[:3, 3]"))?;
    Ok((position, column(2).normalize()))
}

/// Refuses a position beyond ±[`MAX_COORD`] m of the origin.
fn check_reach(p: DVec3, what: &str) -> PyResult<()> {
    if p.abs().max_element() > MAX_COORD {
        return Err(PyValueError::new_err(format!(
            "`{what}` must lie within ±{MAX_COORD} m of the origin on every axis (as in scenario files), \
             got {:?} m",
            p.to_array()
        )));
    }
    Ok(())
}

fn array<'py>(py: Python<'py>, v: DVec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, &v.to_array())
}

/// A frame's orientation as a quaternion `(w, x, y, z)`: the rotation taking the tool's x, y
/// and z axes to the aperture's width axis, its height axis and the spray axis.
fn frame_quaternion(frame: &NozzleFrame) -> [f64; 4] {
    let q = DQuat::from_mat3(&glam::DMat3::from_cols(frame.width_axis, frame.height_axis, frame.axis));
    [q.w, q.x, q.y, q.z]
}

/// A frame as a 4 × 4 homogeneous matrix: columns width axis, height axis, spray axis,
/// position.
fn frame_matrix<'py>(py: Python<'py>, frame: &NozzleFrame) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let (w, h, a, p) = (frame.width_axis, frame.height_axis, frame.axis, frame.position);
    let rows = vec![
        vec![w.x, h.x, a.x, p.x],
        vec![w.y, h.y, a.y, p.y],
        vec![w.z, h.z, a.z, p.z],
        vec![0.0, 0.0, 0.0, 1.0],
    ];
    Ok(PyArray2::from_vec2(py, &rows)?)
}

/// The nozzle's pose, velocity and spray state now.
pub fn pose<'py>(py: Python<'py>, sim: &Simulation) -> PyResult<Bound<'py, PyDict>> {
    let t = sim.time();
    let (frame, spraying) = sim.nozzle().at(t);
    let d = PyDict::new(py);
    d.set_item("position", array(py, frame.position))?;
    d.set_item("axis", array(py, frame.axis))?;
    d.set_item("quaternion", PyArray1::from_slice(py, &frame_quaternion(&frame)))?;
    d.set_item("matrix", frame_matrix(py, &frame)?)?;
    d.set_item("roll_deg", sim.nozzle().roll().to_degrees())?;
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

/// The optional parts of a pose: at most one of `axis`, `quaternion` and `matrix`; `position`
/// with `axis` or `quaternion`, not with `matrix` (which holds it).
pub struct PoseArgs<'a, 'py> {
    pub position: Option<&'a Bound<'py, PyAny>>,
    pub axis: Option<&'a Bound<'py, PyAny>>,
    pub quaternion: Option<&'a Bound<'py, PyAny>>,
    pub matrix: Option<&'a Bound<'py, PyAny>>,
}

/// `v` unless it is None or Python's None.
fn given<'py>(v: Option<&Bound<'py, PyAny>>) -> Option<Bound<'py, PyAny>> {
    v.filter(|v| !v.is_none()).cloned()
}

impl PoseArgs<'_, '_> {
    /// The position and axis (None: not given) they stand for; `prefix` goes in front of each
    /// argument's name in errors (`waypoints[2].`).
    fn read(&self, prefix: &str) -> PyResult<(DVec3, Option<DVec3>)> {
        let (position, axis, quaternion, matrix) =
            (given(self.position), given(self.axis), given(self.quaternion), given(self.matrix));
        let named =
            [("axis", axis.is_some()), ("quaternion", quaternion.is_some()), ("matrix", matrix.is_some())];
        let orientations: Vec<String> =
            named.iter().filter(|(_, g)| *g).map(|(n, _)| format!("`{prefix}{n}`")).collect();
        if orientations.len() > 1 {
            return Err(PyValueError::new_err(format!(
                "give one orientation, not {}: an axis, a quaternion (w, x, y, z) or a 4 × 4 matrix",
                orientations.join(" and ")
            )));
        }
        if let Some(m) = matrix {
            if position.is_some() {
                return Err(PyValueError::new_err(format!(
                    "`{prefix}position` and `{prefix}matrix` were both given: the matrix holds the position \
                     (its last column); give one of them"
                )));
            }
            let (p, a) = matrix_pose(&m, &format!("{prefix}matrix"))?;
            return Ok((p, Some(a)));
        }
        let position = position.ok_or_else(|| {
            PyValueError::new_err(format!("`{prefix}position` is missing (or give a `{prefix}matrix`)"))
        })?;
        let p = self::position(&position, &format!("{prefix}position"))?;
        let a = match (axis, quaternion) {
            (Some(a), _) => Some(direction(&a, &format!("{prefix}axis"))?),
            (None, Some(q)) => Some(quaternion_axis(&q, &format!("{prefix}quaternion"))?),
            (None, None) => None,
        };
        Ok((p, a))
    }
}

impl Pose {
    /// Reads a pose, refusing what the engine cannot follow: non-finite numbers, a zero axis or
    /// quaternion, a matrix that is no rigid pose, a position beyond ±[`MAX_COORD`] m.
    pub fn read(args: &PoseArgs<'_, '_>) -> PyResult<Pose> {
        let (position, axis) = args.read("")?;
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

/// One waypoint from a dict (keys among [`WAYPOINT_KEYS`]: `time`, a position and an
/// orientation, optionally `spray`) or a `(time, position, axis[, spray])` tuple.
fn waypoint(item: &Bound<'_, PyAny>, i: usize) -> PyResult<Waypoint> {
    let at = |k: &str| format!("waypoints[{i}].{k}");
    let accepted = WAYPOINT_KEYS.join(", ");
    let missing = |k: &str| PyValueError::new_err(format!("`{}` is missing", at(k)));
    let (time, pose, spray) = if let Ok(d) = item.cast::<PyDict>() {
        for k in d.keys() {
            let known = k.extract::<String>().is_ok_and(|k| WAYPOINT_KEYS.contains(&k.as_str()));
            if !known {
                return Err(PyValueError::new_err(format!(
                    "`waypoints[{i}]` has an unknown key {}: a waypoint's keys are {accepted}",
                    short_repr(&k)
                )));
            }
        }
        let get = |k: &str| d.get_item(k);
        let (position, axis, quaternion, matrix) =
            (get("position")?, get("axis")?, get("quaternion")?, get("matrix")?);
        if axis.is_none() && quaternion.is_none() && matrix.is_none() {
            return Err(PyValueError::new_err(format!(
                "`waypoints[{i}]` needs an orientation: `axis`, `quaternion` (w, x, y, z) or `matrix` (4 × 4)"
            )));
        }
        let args = PoseArgs {
            position: position.as_ref(),
            axis: axis.as_ref(),
            quaternion: quaternion.as_ref(),
            matrix: matrix.as_ref(),
        };
        let pose = args.read(&format!("waypoints[{i}]."))?;
        (get("time")?, pose, get("spray")?)
    } else {
        let shape = || {
            format!(
                "`waypoints[{i}]` must be a dict (keys {accepted}) or a (time, position, axis[, spray]) tuple"
            )
        };
        let seq: Vec<Bound<'_, PyAny>> = item.extract().map_err(|_| PyValueError::new_err(shape()))?;
        if seq.len() > 4 {
            return Err(PyValueError::new_err(format!("{}, got {} items", shape(), seq.len())));
        }
        let position = position(seq.get(1).ok_or_else(|| missing("position"))?, &at("position"))?;
        let axis = direction(seq.get(2).ok_or_else(|| missing("axis"))?, &at("axis"))?;
        (seq.first().cloned(), (position, Some(axis)), seq.get(3).cloned())
    };
    let time: f64 = time
        .ok_or_else(|| missing("time"))?
        .extract()
        .map_err(|_| PyValueError::new_err(format!("`{}` must be a number of seconds", at("time"))))?;
    if !time.is_finite() {
        return Err(PyValueError::new_err(format!("`{}` must be finite, got {time}", at("time"))));
    }
    let (position, axis) = pose;
    let axis = axis.ok_or_else(|| missing("axis"))?;
    let spray = match spray {
        Some(s) => s.is_truthy()?,
        None => true,
    };
    Ok(Waypoint { time, position, axis, spray })
}

/// A roll angle from `roll_deg` (degrees) or the deprecated `roll` (radians), in radians; None
/// when neither is given. Both at once, or a non-finite one, raise `ValueError`.
pub fn roll(py: Python<'_>, roll_deg: Option<f64>, roll_rad: Option<f64>) -> PyResult<Option<f64>> {
    let r = match (roll_deg, roll_rad) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err(
                "`roll_deg` and `roll` were both given: give `roll_deg` (degrees) only",
            ));
        }
        (Some(d), None) => {
            if !d.is_finite() {
                return Err(PyValueError::new_err(format!("`roll_deg` must be finite, got {d}")));
            }
            Some(d.to_radians())
        }
        (None, Some(r)) => {
            PyErr::warn(
                py,
                &py.get_type::<pyo3::exceptions::PyDeprecationWarning>(),
                c"`roll` (radians) is deprecated: give `roll_deg` (degrees), as every angle of the package",
                1,
            )?;
            if !r.is_finite() {
                return Err(PyValueError::new_err(format!("`roll` must be finite, got {r}")));
            }
            Some(r)
        }
        (None, None) => None,
    };
    Ok(r)
}

/// Reads a nozzle path: `waypoints` in strictly increasing time, at least one.
pub fn read_path(waypoints: &Bound<'_, PyAny>) -> PyResult<Vec<Waypoint>> {
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
    Ok(list)
}

/// Replaces the nozzle's path with one through `list` (read by [`read_path`]), turned by
/// `roll` (radians, converted from the caller's degrees; the present roll when None).
pub fn set_path(sim: &mut Simulation, list: Vec<Waypoint>, roll: Option<f64>) -> PyResult<()> {
    let roll = roll.unwrap_or_else(|| sim.nozzle().roll());
    replace(sim, NozzlePath::through(list, roll))
}

/// One waypoint as a dict.
fn waypoint_dict<'py>(py: Python<'py>, w: &Waypoint) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("time", w.time)?;
    d.set_item("position", array(py, w.position))?;
    d.set_item("axis", array(py, w.axis))?;
    d.set_item("spray", w.spray)?;
    Ok(d)
}

/// The nozzle's path as flown, as waypoints: the path's own waypoints when no circle is
/// superposed; with one, the path sampled `samples_per_turn` times per revolution of the
/// circle (and at each of its own waypoints), from its first waypoint to its last or to the
/// configured duration, whichever is later, each sample's position with the circle's offset.
pub fn waypoints<'py>(
    py: Python<'py>,
    sim: &Simulation,
    samples_per_turn: u64,
) -> PyResult<Bound<'py, PyList>> {
    if !(3..=10_000).contains(&samples_per_turn) {
        return Err(PyValueError::new_err(format!(
            "`samples_per_turn` must be from 3 to 10000, got {samples_per_turn}"
        )));
    }
    let path = sim.nozzle();
    let out = PyList::empty(py);
    let own = path.waypoints();
    let circle = path.circle().filter(|c| c.radius > 0.0 && c.frequency > 0.0);
    let (Some(c), Some(first), Some(last)) = (circle, own.first(), own.last()) else {
        for w in own {
            out.append(waypoint_dict(py, w)?)?;
        }
        return Ok(out);
    };
    let (start, end) = (first.time, last.time.max(sim.config().duration));
    let step = 1.0 / (c.frequency * samples_per_turn as f64);
    let count = ((end - start) / step).ceil();
    if count + own.len() as f64 > MAX_SAMPLES {
        return Err(PyValueError::new_err(format!(
            "the path's circle would take {count} samples (at most {MAX_SAMPLES}): lower `samples_per_turn`"
        )));
    }
    let mut times: Vec<f64> = (0..=count as u64).map(|k| (start + k as f64 * step).min(end)).collect();
    times.extend(own.iter().map(|w| w.time));
    times.sort_by(f64::total_cmp);
    times.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    for t in times {
        let (frame, spray) = path.at(t);
        let w = Waypoint { time: t, position: frame.position, axis: frame.axis, spray };
        out.append(waypoint_dict(py, &w)?)?;
    }
    Ok(out)
}

/// The nozzle's whole path as a dict: `waypoints`, `roll_deg` and `circle` (None, or its
/// `radius` m, `frequency` Hz, `start` s and the unit vectors `first`, `second`, `axis`).
pub fn path<'py>(py: Python<'py>, sim: &Simulation) -> PyResult<Bound<'py, PyDict>> {
    let path = sim.nozzle();
    let list = PyList::empty(py);
    for w in path.waypoints() {
        list.append(waypoint_dict(py, w)?)?;
    }
    let d = PyDict::new(py);
    d.set_item("waypoints", list)?;
    d.set_item("roll_deg", path.roll().to_degrees())?;
    match path.circle() {
        Some(c) => {
            let circle = PyDict::new(py);
            circle.set_item("radius", c.radius)?;
            circle.set_item("frequency", c.frequency)?;
            circle.set_item("start", c.start)?;
            circle.set_item("first", array(py, c.first))?;
            circle.set_item("second", array(py, c.second))?;
            circle.set_item("axis", array(py, c.axis))?;
            d.set_item("circle", circle)?;
        }
        None => d.set_item("circle", py.None())?,
    }
    Ok(d)
}

/// The nozzle's pose at each of `times` (s), circle included: `position` (n, 3) m, `axis`
/// (n, 3) and `spraying` (n,).
pub fn sample<'py>(py: Python<'py>, sim: &Simulation, times: Vec<f64>) -> PyResult<Bound<'py, PyDict>> {
    if let Some(t) = times.iter().find(|t| !t.is_finite()) {
        return Err(PyValueError::new_err(format!("`times` must be finite, got {t}")));
    }
    let n = times.len();
    let (mut pos, mut axis, mut spraying) =
        (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n), Vec::with_capacity(n));
    for &t in &times {
        let (frame, spray) = sim.nozzle().at(t);
        pos.extend_from_slice(&frame.position.to_array());
        axis.extend_from_slice(&frame.axis.to_array());
        spraying.push(spray);
    }
    let d = PyDict::new(py);
    d.set_item("position", PyArray1::from_vec(py, pos).reshape([n, 3])?)?;
    d.set_item("axis", PyArray1::from_vec(py, axis).reshape([n, 3])?)?;
    d.set_item("spraying", PyArray1::from_vec(py, spraying))?;
    Ok(d)
}
