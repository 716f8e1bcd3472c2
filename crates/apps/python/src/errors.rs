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
     `spraysim` command prints). The text is `key: message (location)`, e.g. `emitter.speed: must \
     be [min, max] with min ≤ max, got [30.0, 20.0] (Scenario.set('emitter.speed', [30, 20]))`; a \
     syntax or read error, which has no key, reads `location: message`."
);

/// A `ScenarioError` with its `key`, `location` and `message` attributes set.
pub fn scenario_error(py: Python<'_>, e: &spraysim::ScenarioError) -> PyErr {
    use spraysim::ScenarioError as E;
    // An override's location is the command line's `--set KEY=VALUE`; callers name the Python
    // call instead (`relocated`), and any left over is named without the command's syntax.
    let place = |l: &String| match l.strip_prefix("--set ") {
        Some(assignment) => format!("override {assignment}"),
        None => l.clone(),
    };
    let (key, location, message) = match e {
        E::Read { origin, source } => (None, Some(origin.clone()), source.to_string()),
        E::Syntax { location, message } => (None, Some(place(location)), message.clone()),
        E::Invalid { location, key, message } => (Some(key.clone()), Some(place(location)), message.clone()),
    };
    refusal(py, key, location, message)
}

/// The text of a refusal: `key: message (location)`, or `location: message` without a key.
pub fn refusal_text(key: Option<&str>, location: Option<&str>, message: &str) -> String {
    match (key, location) {
        (Some(k), Some(l)) => format!("{k}: {message} ({l})"),
        (Some(k), None) => format!("{k}: {message}"),
        (None, Some(l)) => format!("{l}: {message}"),
        (None, None) => message.to_string(),
    }
}

/// A `ScenarioError` about `key` (None for a syntax or read error), given at `location`.
pub fn refusal(py: Python<'_>, key: Option<String>, location: Option<String>, message: String) -> PyErr {
    let err = ScenarioError::new_err(refusal_text(key.as_deref(), location.as_deref(), &message));
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

/// A `ValueError` for an engine set-up error: `field: message` for a configuration the engine
/// cannot run.
pub fn setup_error(e: &spraysim::SetupError) -> PyErr {
    match e {
        spraysim::SetupError::Config(c) => PyValueError::new_err(format!("{}: {}", c.field, c.message)),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// An `OSError` for an output error.
pub fn output_error(e: &spraysim::output::OutputError) -> PyErr {
    PyOSError::new_err(e.to_string())
}
