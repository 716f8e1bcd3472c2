//! Conversions between Python values and TOML or JSON: dictionaries and override values go to
//! TOML (and from there through the scenario reader, with its checks), results come back as
//! JSON read by Python's own `json` module, so that a dictionary equals the file's contents.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// Deepest nesting of dicts and lists (inside one another) that a scenario value may have: a
/// scenario file needs three levels (`target[0].opening[1].size`), so 32 leaves room for any
/// value without letting a runaway (or self-referring) structure exhaust the stack.
pub const MAX_DEPTH: usize = 32;

/// A Python value that has no TOML form, at the dotted key `key`.
pub struct Refused {
    /// Dotted key of the value, e.g. `target[0].size`.
    pub key: String,
    /// What is wrong with it.
    pub message: String,
}

/// `value`, found at the dotted key `key`, as a TOML value: `bool`, `int`, `float`, `str`, a
/// `dict` with string keys, a `list` or `tuple`, anything with `tolist()` (numpy arrays and
/// scalars) and paths (`os.PathLike`, as strings); nested at most [`MAX_DEPTH`] levels deep,
/// and holding no dict or list inside itself.
pub fn to_toml(value: &Bound<'_, PyAny>, key: &str) -> Result<toml::Value, Refused> {
    Walk::default().value(value, key, 0)
}

/// A dictionary with string keys, found at the dotted key `key` (empty at the top), as a TOML
/// table (see [`to_toml`]).
pub fn dict_to_toml(dict: &Bound<'_, PyDict>, key: &str) -> Result<toml::Table, Refused> {
    Walk::default().dict(dict, key, 0)
}

/// A walk through nested dicts and lists, which knows the containers it is inside.
#[derive(Default)]
struct Walk {
    /// The dicts and lists being read, outermost first: their address and dotted key.
    open: Vec<(usize, String)>,
}

impl Walk {
    /// `value` at `key`, `depth` levels inside the walk's first value.
    fn value(&mut self, value: &Bound<'_, PyAny>, key: &str, depth: usize) -> Result<toml::Value, Refused> {
        let refuse = |message: String| Refused { key: key.to_string(), message };
        let py_err = |e: PyErr| refuse(format!("cannot be read: {e}"));
        if value.is_instance_of::<PyBool>() {
            return Ok(toml::Value::Boolean(value.is_truthy().map_err(py_err)?));
        }
        if value.is_instance_of::<PyInt>() {
            let i =
                value.extract::<i64>().map_err(|_| refuse("is an integer beyond TOML's 64 bits".into()))?;
            return Ok(toml::Value::Integer(i));
        }
        if value.is_instance_of::<PyFloat>() {
            return Ok(toml::Value::Float(value.extract::<f64>().map_err(py_err)?));
        }
        if value.is_instance_of::<PyString>() {
            return Ok(toml::Value::String(value.extract::<String>().map_err(py_err)?));
        }
        if value.is_none() {
            return Err(refuse("is None, which a scenario cannot hold (leave the key out instead)".into()));
        }
        let is_dict = value.cast::<PyDict>().is_ok();
        let is_list = value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>();
        // Containers, and the values numpy or a path stand for, go one level deeper.
        if depth >= MAX_DEPTH {
            return Err(refuse(format!(
                "is nested more than {MAX_DEPTH} levels deep (dicts and lists inside one another), \
                 deeper than any scenario value"
            )));
        }
        if is_dict || is_list {
            return self.container(value, key, depth);
        }
        if value.hasattr("tolist").unwrap_or(false) {
            // numpy arrays and scalars become plain lists and numbers.
            return self.value(&value.call_method0("tolist").map_err(py_err)?, key, depth + 1);
        }
        if value.hasattr("__fspath__").unwrap_or(false) {
            let path = value.call_method0("__fspath__").map_err(py_err)?;
            return self.value(&path, key, depth + 1);
        }
        Err(refuse(format!(
            "is a {}, which has no TOML form (give a number, bool, string, list or dict)",
            crate::args::type_name(value)
        )))
    }

    /// A dict or a list at `key`: refused when it is one of the containers it sits in.
    fn container(
        &mut self,
        value: &Bound<'_, PyAny>,
        key: &str,
        depth: usize,
    ) -> Result<toml::Value, Refused> {
        let address = value.as_ptr() as usize;
        if let Some((_, outer)) = self.open.iter().find(|(a, _)| *a == address) {
            let outer = if outer.is_empty() { "the whole dict".to_string() } else { format!("`{outer}`") };
            return Err(Refused {
                key: key.to_string(),
                message: format!(
                    "refers back to {outer}, which holds it: a scenario value cannot contain itself"
                ),
            });
        }
        if let Ok(dict) = value.cast::<PyDict>() {
            return self.dict(dict, key, depth).map(toml::Value::Table);
        }
        self.open.push((address, key.to_string()));
        let items = value
            .try_iter()
            .map_err(|e| Refused { key: key.into(), message: format!("cannot be read: {e}") });
        let mut out = Vec::new();
        let result = items.and_then(|items| {
            for (i, item) in items.enumerate() {
                let at = format!("{key}[{i}]");
                let item =
                    item.map_err(|e| Refused { key: at.clone(), message: format!("cannot be read: {e}") })?;
                out.push(self.value(&item, &at, depth + 1)?);
            }
            Ok(())
        });
        self.open.pop();
        result.map(|()| toml::Value::Array(out))
    }

    /// A dictionary at `key` (empty at the top), `depth` levels inside the walk's first value.
    fn dict(&mut self, dict: &Bound<'_, PyDict>, key: &str, depth: usize) -> Result<toml::Table, Refused> {
        self.open.push((dict.as_ptr() as usize, key.to_string()));
        let result = self.entries(dict, key, depth);
        self.open.pop();
        result
    }

    fn entries(&mut self, dict: &Bound<'_, PyDict>, key: &str, depth: usize) -> Result<toml::Table, Refused> {
        let mut table = toml::Table::new();
        for (k, v) in dict.iter() {
            let Ok(name) = k.extract::<String>() else {
                return Err(Refused {
                    key: key.to_string(),
                    message: format!("has a key that is not a string: {}", crate::args::short_repr(&k)),
                });
            };
            let path = if key.is_empty() { name.clone() } else { format!("{key}.{name}") };
            let value = self.value(&v, &path, depth + 1)?;
            table.insert(name, value);
        }
        Ok(table)
    }
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

/// `metrics.json` text as a Python dict, with its `targets` list turned into a dict keyed by
/// target name (in scenario order), so that a target is found by its name.
pub fn metrics_to_py<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    let metrics = json_to_py(py, text)?;
    if let Ok(d) = metrics.cast::<PyDict>()
        && let Some(targets) = d.get_item("targets")?
        && let Ok(list) = targets.cast::<PyList>()
    {
        let by_name = PyDict::new(py);
        for t in list.iter() {
            by_name.set_item(t.get_item("name")?, &t)?;
        }
        d.set_item("targets", by_name)?;
    }
    Ok(metrics)
}
