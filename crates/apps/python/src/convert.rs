//! Conversions between Python values and TOML or JSON: dictionaries and override values go to
//! TOML (and from there through the scenario reader, with its checks), results come back as
//! JSON read by Python's own `json` module, so that a dictionary equals the file's contents.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// A Python value that has no TOML form, at the dotted key `key`.
pub struct Refused {
    /// Dotted key of the value, e.g. `target[0].size`.
    pub key: String,
    /// What is wrong with it.
    pub message: String,
}

/// `value`, found at the dotted key `key`, as a TOML value: `bool`, `int`, `float`, `str`, a
/// `dict` with string keys, a `list` or `tuple`, anything with `tolist()` (numpy arrays and
/// scalars) and paths (`os.PathLike`, as strings).
pub fn to_toml(value: &Bound<'_, PyAny>, key: &str) -> Result<toml::Value, Refused> {
    let refuse = |message: String| Refused { key: key.to_string(), message };
    let py_err = |e: PyErr| refuse(format!("cannot be read: {e}"));
    if value.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(value.is_truthy().map_err(py_err)?));
    }
    if value.is_instance_of::<PyInt>() {
        let i = value.extract::<i64>().map_err(|_| refuse("is an integer beyond TOML's 64 bits".into()))?;
        return Ok(toml::Value::Integer(i));
    }
    if value.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(value.extract::<f64>().map_err(py_err)?));
    }
    if value.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(value.extract::<String>().map_err(py_err)?));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        return dict_to_toml(dict, key).map(toml::Value::Table);
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items = value.try_iter().map_err(py_err)?;
        let mut out = Vec::new();
        for (i, item) in items.enumerate() {
            out.push(to_toml(&item.map_err(py_err)?, &format!("{key}[{i}]"))?);
        }
        return Ok(toml::Value::Array(out));
    }
    if value.is_none() {
        return Err(refuse("is None, which a scenario cannot hold (leave the key out instead)".into()));
    }
    if value.hasattr("tolist").unwrap_or(false) {
        // numpy arrays and scalars become plain lists and numbers.
        return to_toml(&value.call_method0("tolist").map_err(py_err)?, key);
    }
    if value.hasattr("__fspath__").unwrap_or(false) {
        let path = value.call_method0("__fspath__").map_err(py_err)?;
        return to_toml(&path, key);
    }
    let kind = value.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
    Err(refuse(format!("is a {kind}, which has no TOML form (give a number, bool, string, list or dict)")))
}

/// A dictionary with string keys, found at the dotted key `key` (empty at the top), as a TOML
/// table.
pub fn dict_to_toml(dict: &Bound<'_, PyDict>, key: &str) -> Result<toml::Table, Refused> {
    let mut table = toml::Table::new();
    for (k, v) in dict.iter() {
        let Ok(name) = k.extract::<String>() else {
            return Err(Refused {
                key: key.to_string(),
                message: format!("has a key that is not a string: {k}"),
            });
        };
        let path = if key.is_empty() { name.clone() } else { format!("{key}.{name}") };
        table.insert(name, to_toml(&v, &path)?);
    }
    Ok(table)
}

/// JSON text as a Python value, read by the `json` module (so that it equals what
/// `json.load` gives for the same text).
pub fn json_to_py<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// Any serialisable value as a Python value, through JSON.
pub fn to_py<'py, T: serde::Serialize>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(format!("cannot convert to Python: {e}")))?;
    json_to_py(py, &text)
}
