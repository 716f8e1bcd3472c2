//! Python exceptions for the library's errors.

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    spraysim,
    ScenarioError,
    PyValueError,
    "A scenario was refused: unknown key, wrong type, impossible value. `key` is the dotted key \
     (`emitter.speed`, `target[0].resolution`) or None for a syntax or read error, `location` \
     where it was given (`file:line`, `<dict>`, or the Python call that set it, e.g. \
     `Scenario.set('emitter.speed', [30, 20])`), `message` what is wrong (the words the \
     `spraysim` command prints). The text is `location: `key` message` (without the key for a \
     syntax or read error)."
);

/// A `ScenarioError` with its `key`, `location` and `message` attributes set.
pub fn scenario_error(py: Python<'_>, e: &spraysim::ScenarioError) -> PyErr {
    use spraysim::ScenarioError as E;
    let (key, location, message) = match e {
        E::Read { origin, source } => (None, Some(origin.clone()), source.to_string()),
        E::Syntax { location, message } => (None, Some(location.clone()), message.clone()),
        E::Invalid { location, key, message } => (Some(key.clone()), Some(location.clone()), message.clone()),
    };
    refusal(py, e.to_string(), key, location, message)
}

/// A `ScenarioError` with text `text` about `key`.
pub fn refusal(
    py: Python<'_>,
    text: String,
    key: Option<String>,
    location: Option<String>,
    message: String,
) -> PyErr {
    let err = ScenarioError::new_err(text);
    let value = err.value(py);
    // Setting attributes on a fresh exception instance cannot fail in practice; if it did,
    // the exception would still carry its text.
    let _ = value.setattr("key", key);
    let _ = value.setattr("location", location);
    let _ = value.setattr("message", message);
    err
}

/// `e` with the location of an override, which the scenario crate gives as the command line's
/// `--set KEY=VALUE`, replaced by the Python call that made it: `called("KEY=VALUE")` names
/// that call (`Scenario.set('emitter.speed', [30, 20])`). Other locations are kept.
pub fn relocated(e: spraysim::ScenarioError, called: impl Fn(&str) -> String) -> spraysim::ScenarioError {
    use spraysim::ScenarioError as E;
    let place = |location: String| match location.strip_prefix("--set ") {
        Some(assignment) => called(assignment),
        None => location,
    };
    match e {
        E::Invalid { location, key, message } => E::Invalid { location: place(location), key, message },
        E::Syntax { location, message } => E::Syntax { location: place(location), message },
        read @ E::Read { .. } => read,
    }
}

/// A `ValueError` for an engine set-up error.
pub fn setup_error(e: &spraysim::SetupError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// An `OSError` for an output error.
pub fn output_error(e: &spraysim::output::OutputError) -> PyErr {
    PyOSError::new_err(e.to_string())
}
