//! numpy arrays of a simulation's particles and targets.
//!
//! A target's maps are handed out without a copy when asked: the array views the engine's own
//! storage, which a deposit surface allocates once and writes in place (see
//! `DepositSurface::thickness`), and its base object keeps the simulation alive.
//! `Simulation.restore` swaps the engine's state for another; the old one is kept for as long
//! as an array still views it.

use crate::simulation::PySimulation;
use numpy::ndarray::{ArrayViewD, IxDyn};
use numpy::{Element, PyArray1, PyArrayDyn, PyArrayMethods, ToPyArray};
use pyo3::exceptions::{PyIndexError, PyKeyError, PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use spraysim::Simulation;
use spraysim::deposit::{Chart, DepositSurface, Layout, Surface};
use spraysim::world::{Role, Target};
use std::sync::Arc;

/// The base object of a zero-copy array: keeps the simulation, and the state viewed, alive.
#[pyclass(module = "spraysim._core", frozen)]
pub struct ViewOwner {
    _owner: Py<PySimulation>,
    _views: Arc<()>,
}

/// Index of the target named by `target`: a name (`str`), or an index from 0 (any integer,
/// numpy's included). An unknown name raises `KeyError`, a negative or too large index
/// `IndexError`, anything else `TypeError`; each lists the targets.
pub fn target_index(sim: &Simulation, target: &Bound<'_, PyAny>) -> PyResult<usize> {
    let count = sim.targets().len();
    let names = || sim.targets().iter().map(|t| t.name.as_str()).collect::<Vec<_>>().join(", ");
    let choices = || format!("give an index from 0 to {} or a name ({})", count.saturating_sub(1), names());
    if target.is_instance_of::<PyString>() {
        let name: String = target.extract()?;
        return sim.targets().iter().position(|t| t.name == name).ok_or_else(|| {
            PyKeyError::new_err(format!("no target named {name:?}: the targets are {}", names()))
        });
    }
    match target.extract::<i64>() {
        Ok(i) if i < 0 => Err(PyIndexError::new_err(format!(
            "target index {i} is negative (indices count from 0): {}",
            choices()
        ))),
        Ok(i) => match usize::try_from(i) {
            Ok(i) if i < count => Ok(i),
            _ => Err(PyIndexError::new_err(format!("no target {i}: there are {count}; {}", choices()))),
        },
        Err(e) if e.is_instance_of::<PyOverflowError>(target.py()) => {
            Err(PyIndexError::new_err(format!("no target {target}: there are {count}; {}", choices())))
        }
        Err(_) => Err(PyTypeError::new_err(format!(
            "`target` must be a target's name (str) or index (int), got {}: {}",
            crate::args::type_name(target),
            choices()
        ))),
    }
}

/// The shape of a target's maps: `[rows, cols]` on a grid (a rectangle, a shell unrolled),
/// `[triangles]` on a mesh.
pub fn shape(t: &Target) -> IxDyn {
    match t.surface.layout() {
        Layout::Grid { rows, cols, .. } => IxDyn(&[rows, cols]),
        Layout::Cells { count } => IxDyn(&[count]),
    }
}

/// A map of the target `target` (see [`shape`]), viewed (or copied when `copy`).
pub fn grid<'py, T: Element + Copy>(
    slf: &Bound<'py, PySimulation>,
    target: &Bound<'py, PyAny>,
    copy: bool,
    data: impl Fn(&Target) -> &[T],
) -> PyResult<Bound<'py, PyAny>> {
    let py = slf.py();
    let this = slf.get();
    // Waits while another thread's call runs this simulation; refused (RuntimeError) from a
    // callback of its own call.
    let state = this.lock(py)?;
    let t = &state.held.sim.targets()[target_index(&state.held.sim, target)?];
    let view = ArrayViewD::from_shape(shape(t), data(t))
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("target {}: {e}", t.name)))?;
    if copy {
        return Ok(view.to_pyarray(py).into_any());
    }
    let owner = Bound::new(py, ViewOwner { _owner: slf.clone().unbind(), _views: state.held.views.clone() })?;
    // SAFETY: the storage viewed belongs to the engine state in `state.held`, which lives until
    // the simulation does (the owner keeps it alive) or, once replaced by `restore`, for as
    // long as the token cloned into the owner is counted; deposit surfaces allocate their maps
    // once and write them in place, so the pointer stays valid.
    let array = unsafe { PyArrayDyn::borrow_from_array(&view, owner.into_any()) };
    array.readwrite().make_nonwriteable();
    Ok(array.into_any())
}

/// Which cells of a target carry its surface: false for the cells cut away by openings.
pub fn solid(t: &Target) -> Vec<bool> {
    let cells = t.surface.thickness().len();
    (0..cells).map(|c| u32::try_from(c).is_ok_and(|c| t.surface.cell_area(c) > 0.0)).collect()
}

/// `values` with NaN in the cells of `t` cut away by openings, as the `.npy` files hold them.
pub fn with_nan(t: &Target, values: &[f64]) -> Vec<f64> {
    values.iter().zip(solid(t)).map(|(&v, s)| if s { v } else { f64::NAN }).collect()
}

/// A float map of the target `target` (see [`shape`]) with NaN in openings: viewed when the
/// target has none and `copy` is false, else copied.
pub fn float_map<'py>(
    slf: &Bound<'py, PySimulation>,
    target: &Bound<'py, PyAny>,
    copy: bool,
    data: impl Fn(&Target) -> &[f64],
) -> PyResult<Bound<'py, PyAny>> {
    let py = slf.py();
    {
        let state = slf.get().lock(py)?;
        let t = &state.held.sim.targets()[target_index(&state.held.sim, target)?];
        if solid(t).iter().any(|s| !s) {
            let values = with_nan(t, data(t));
            let view = ArrayViewD::from_shape(shape(t), values.as_slice())
                .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("target {}: {e}", t.name)))?;
            return Ok(view.to_pyarray(py).into_any());
        }
    }
    grid(slf, target, copy, data)
}

/// Where a target's surface is (false in openings), laid out as its maps.
pub fn mask<'py>(
    py: Python<'py>,
    sim: &Simulation,
    target: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let t = &sim.targets()[target_index(sim, target)?];
    let solid = solid(t);
    let view = ArrayViewD::from_shape(shape(t), solid.as_slice())
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok(view.to_pyarray(py).into_any())
}

/// The surface of a rectangle or shell at unrolled `(u, v)` raised by `height`, as a dict.
pub fn surface_frame<'py>(
    py: Python<'py>,
    sim: &Simulation,
    target: &Bound<'py, PyAny>,
    [u, v, height]: [f64; 3],
) -> PyResult<Bound<'py, PyDict>> {
    let t = &sim.targets()[target_index(sim, target)?];
    if let Some(bad) = [("u", u), ("v", v), ("height", height)].iter().find(|(_, x)| !x.is_finite()) {
        return Err(PyValueError::new_err(format!("`{}` must be finite, got {}", bad.0, bad.1)));
    }
    let (position, (normal, right, up)) = match &t.surface {
        Surface::Rectangle(r) => (r.chart.point(u, v, height), r.chart.frame(u, v)),
        Surface::Cylinder(c) => (c.chart.point(u, v, height), c.chart.frame(u, v)),
        Surface::Mesh(_) => {
            return Err(PyValueError::new_err(format!(
                "target {:?} is a mesh, which has no unrolled (u, v) coordinates",
                t.name
            )));
        }
    };
    let d = PyDict::new(py);
    d.set_item("position", vec3(py, position))?;
    d.set_item("normal", vec3(py, normal))?;
    d.set_item("right", vec3(py, right))?;
    d.set_item("up", vec3(py, up))?;
    Ok(d)
}

/// The depth eroded per cell of a target, coating and substrate together, a copy (NaN in
/// openings), or None.
pub fn erosion<'py>(
    py: Python<'py>,
    sim: &Simulation,
    target: &Bound<'py, PyAny>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    optional_map(py, sim, target, |t| {
        let e = t.erosion.as_ref()?;
        Some((0..e.coating.len()).map(|c| e.eroded(c)).collect())
    })
}

/// The coating left per cell of a target, m, a copy (NaN in openings), or None when the
/// process erodes nothing.
pub fn coating<'py>(
    py: Python<'py>,
    sim: &Simulation,
    target: &Bound<'py, PyAny>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    optional_map(py, sim, target, |t| Some(t.erosion.as_ref()?.coating.clone()))
}

/// The dry film per cell of a target, m: the wet thickness times the material's volume
/// solids, a copy (NaN in openings), or None without volume solids.
pub fn dry_thickness<'py>(
    py: Python<'py>,
    sim: &Simulation,
    target: &Bound<'py, PyAny>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let solids = sim.config().material.volume_solids;
    optional_map(py, sim, target, |t| {
        let solids = solids?;
        Some(t.surface.thickness().iter().map(|x| x * solids).collect())
    })
}

/// The per-cell values `values` gives for a target (name or index) as a new array in its map
/// shape, NaN in openings, or None where the target has no such map.
fn optional_map<'py>(
    py: Python<'py>,
    sim: &Simulation,
    target: &Bound<'py, PyAny>,
    values: impl FnOnce(&Target) -> Option<Vec<f64>>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let t = &sim.targets()[target_index(sim, target)?];
    values(t).map(|v| map_copy(py, t, &v)).transpose()
}

/// Per-cell `values` of target `t` as a new array in the target's map shape, NaN in openings.
fn map_copy<'py>(py: Python<'py>, t: &Target, values: &[f64]) -> PyResult<Bound<'py, PyAny>> {
    let values = with_nan(t, values);
    let view = ArrayViewD::from_shape(shape(t), values.as_slice())
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok(view.to_pyarray(py).into_any())
}

fn vec3<'py>(py: Python<'py>, v: glam::DVec3) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_slice(py, &v.to_array())
}

/// A target's geometry as a dictionary.
pub fn target_info<'py>(
    py: Python<'py>,
    sim: &Simulation,
    target: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyDict>> {
    let t = &sim.targets()[target_index(sim, target)?];
    let d = PyDict::new(py);
    d.set_item("name", &t.name)?;
    d.set_item("role", if t.role == Role::Substrate { "substrate" } else { "collector" })?;
    d.set_item("cells", t.surface.thickness().len())?;
    d.set_item("solid_cells", solid(t).iter().filter(|s| **s).count())?;
    if let Layout::Grid { rows, cols, cell, .. } = t.surface.layout() {
        d.set_item("rows", rows)?;
        d.set_item("cols", cols)?;
        d.set_item("cell_size", cell)?;
    }
    match &t.surface {
        Surface::Rectangle(r) => {
            let f = &r.chart;
            d.set_item("shape", "rectangle")?;
            d.set_item("size", (2.0 * f.half_width, 2.0 * f.half_height))?;
            d.set_item("center", vec3(py, f.center))?;
            d.set_item("normal", vec3(py, f.normal))?;
            d.set_item("up", vec3(py, f.up))?;
            d.set_item("right", vec3(py, f.right))?;
        }
        Surface::Cylinder(c) => {
            let s = &c.chart.shell;
            d.set_item("shape", "cylinder")?;
            d.set_item("size", (s.radius * (s.angles[1] - s.angles[0]), 2.0 * s.half_length))?;
            d.set_item("center", vec3(py, s.center))?;
            d.set_item("axis", vec3(py, s.axis))?;
            d.set_item("radius", s.radius)?;
            d.set_item("angles_deg", (s.angles[0].to_degrees(), s.angles[1].to_degrees()))?;
            d.set_item("side", if c.chart.inside { "inside" } else { "outside" })?;
        }
        Surface::Mesh(_) => d.set_item("shape", "mesh")?,
    }
    Ok(d)
}

/// The particles in flight, at the present time, as numpy arrays.
pub fn particles<'py>(py: Python<'py>, sim: &Simulation) -> PyResult<Bound<'py, PyDict>> {
    let s = &sim.swarm().particles;
    let alive: Vec<usize> = (0..s.len()).filter(|&i| s[i].is_alive()).collect();
    let n = alive.len();
    let (mut pos, mut vel, mut age) =
        (Vec::with_capacity(3 * n), Vec::with_capacity(3 * n), Vec::with_capacity(n));
    for &i in &alive {
        let (x, v, a) = sim.particle_now(i);
        pos.extend_from_slice(&x.to_array());
        vel.extend_from_slice(&v.to_array());
        age.push(a);
    }
    let d = PyDict::new(py);
    d.set_item("position", PyArray1::from_vec(py, pos).reshape([n, 3])?)?;
    d.set_item("velocity", PyArray1::from_vec(py, vel).reshape([n, 3])?)?;
    d.set_item("age", PyArray1::from_vec(py, age))?;
    d.set_item("id", PyArray1::from_vec(py, alive.iter().map(|&i| s[i].id).collect::<Vec<u32>>()))?;
    d.set_item(
        "impacts",
        PyArray1::from_vec(py, alive.iter().map(|&i| s[i].impacts()).collect::<Vec<u16>>()),
    )?;
    d.set_item("state", PyArray1::from_vec(py, alive.iter().map(|&i| s[i].flags()).collect::<Vec<u8>>()))?;
    Ok(d)
}
