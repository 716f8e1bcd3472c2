//! Checks of Python arguments before they reach the engine: each refusal is a Python exception
//! that names the argument, says why and what is allowed.

use pyo3::exceptions::{PyOverflowError, PyTypeError, PyValueError};
use pyo3::prelude::*;

/// A `threads=` argument: worker threads, 0 for one per core, at most
/// [`spraysim::max_threads`]. Negative counts and counts above the cap are refused with a
/// `ValueError` before any thread starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Threads(pub usize);

impl Threads {
    /// One worker thread per core (`threads=0`).
    pub const PER_CORE: Threads = Threads(0);
}

impl<'a, 'py> FromPyObject<'a, 'py> for Threads {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        threads(&obj).map(Threads)
    }
}

/// The worker thread count `value` stands for (a whole number; 0: one per core).
pub fn threads(value: &Bound<'_, PyAny>) -> PyResult<usize> {
    let py = value.py();
    let too_many = |count: &dyn std::fmt::Display| {
        PyValueError::new_err(format!(
            "`threads` = {count} is too many: at most {} worker threads are allowed on this machine \
             ({} per core; 0 uses one per core)",
            spraysim::max_threads(),
            spraysim::pipeline::THREADS_PER_CORE,
        ))
    };
    let negative = |count: &dyn std::fmt::Display| {
        PyValueError::new_err(format!(
            "`threads` must be 0 (one worker thread per core) or a positive count, got {count}"
        ))
    };
    match value.extract::<i64>() {
        Ok(n) if n < 0 => Err(negative(&n)),
        Ok(n) => {
            let n = usize::try_from(n).map_err(|_| too_many(&n))?;
            spraysim::check_threads(n).map_err(|_| too_many(&n))?;
            Ok(n)
        }
        // A whole number beyond 64 bits.
        Err(e) if e.is_instance_of::<PyOverflowError>(py) => {
            if value.lt(0)? {
                Err(negative(value))
            } else {
                Err(too_many(value))
            }
        }
        Err(_) => Err(PyTypeError::new_err(format!(
            "`threads` must be a whole number (0: one worker thread per core), got {}",
            type_name(value)
        ))),
    }
}

/// The name of a value's type, for messages (`float`, `NoneType`).
pub fn type_name(value: &Bound<'_, PyAny>) -> String {
    value.get_type().name().map_or_else(|_| "?".to_string(), |n| n.to_string())
}

/// A short `repr` of `value` for messages: at most a few levels and items deep (through
/// `reprlib`), so that a huge or deeply nested value gives a line, not a page or an error.
pub fn short_repr(value: &Bound<'_, PyAny>) -> String {
    let py = value.py();
    py.import("reprlib")
        .and_then(|m| m.call_method1("repr", (value,)))
        .and_then(|r| r.extract::<String>())
        .unwrap_or_else(|_| format!("<{}>", type_name(value)))
}

/// A count `value` given as the argument `name` (of `unit`, for messages): a whole number ≥ 0.
/// A negative or too large one raises `ValueError` (not `OverflowError`), anything else
/// `TypeError`.
pub fn count(value: &Bound<'_, PyAny>, name: &str, unit: &str) -> PyResult<u64> {
    if value.is_instance_of::<pyo3::types::PyBool>() || !value.hasattr("__index__")? {
        return Err(PyTypeError::new_err(format!(
            "`{name}` must be a whole number of {unit}, got {}",
            type_name(value)
        )));
    }
    if value.lt(0_i64)? {
        return Err(PyValueError::new_err(format!("`{name}` must be a number of {unit} ≥ 0, got {value}")));
    }
    value.extract::<u64>().map_err(|_| {
        PyValueError::new_err(format!("`{name}` must be at most {} {unit}, got {value}", u64::MAX))
    })
}
