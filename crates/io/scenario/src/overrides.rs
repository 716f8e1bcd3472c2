//! Overrides by dotted key (`emitter.spawn_rate`, `target[0].resolution`), applied to the
//! scenario's text before it is read, so that an overridden value is checked exactly as if the
//! file had given it.

use crate::error::ScenarioError;
use toml_edit::{DocumentMut, Item, TableLike};

/// A value to set: a number, a boolean, a string, a list of numbers, or TOML text.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number.
    Number(f64),
    /// A whole number.
    Integer(i64),
    /// True or false.
    Bool(bool),
    /// A string.
    Text(String),
    /// An array of numbers.
    Numbers(Vec<f64>),
    /// Any TOML value, as text (`[1, 2]`, `"painting"`, `{ a = 1 }`).
    Toml(String),
}

impl Value {
    /// The value as TOML text.
    pub fn to_toml(&self) -> String {
        let float = |x: f64| toml_edit::Value::from(x).to_string().trim().to_string();
        match self {
            Value::Number(x) => float(*x),
            Value::Integer(i) => i.to_string(),
            Value::Bool(b) => b.to_string(),
            Value::Text(s) => toml_edit::Value::from(s.as_str()).to_string().trim().to_string(),
            Value::Numbers(v) => format!("[{}]", v.iter().map(|&x| float(x)).collect::<Vec<_>>().join(", ")),
            Value::Toml(t) => t.clone(),
        }
    }
}

impl From<f64> for Value {
    fn from(x: f64) -> Self {
        Value::Number(x)
    }
}

impl From<i64> for Value {
    fn from(x: i64) -> Self {
        Value::Integer(x)
    }
}

impl From<i32> for Value {
    fn from(x: i32) -> Self {
        Value::Integer(i64::from(x))
    }
}

impl From<u32> for Value {
    fn from(x: u32) -> Self {
        Value::Integer(i64::from(x))
    }
}

impl From<bool> for Value {
    fn from(b: bool) -> Self {
        Value::Bool(b)
    }
}

impl From<&str> for Value {
    fn from(s: &str) -> Self {
        Value::Text(s.to_string())
    }
}

impl From<String> for Value {
    fn from(s: String) -> Self {
        Value::Text(s)
    }
}

impl From<Vec<f64>> for Value {
    fn from(v: Vec<f64>) -> Self {
        Value::Numbers(v)
    }
}

impl<const N: usize> From<[f64; N]> for Value {
    fn from(v: [f64; N]) -> Self {
        Value::Numbers(v.to_vec())
    }
}

/// Splits `KEY=VALUE`: the value is TOML when it parses as a TOML value, else a bare string.
pub(crate) fn split(assignment: &str) -> Result<(String, Value), ScenarioError> {
    let Some((key, value)) = assignment.split_once('=') else {
        return Err(ScenarioError::Syntax {
            location: format!("--set {assignment}"),
            message: "must be KEY=VALUE, e.g. simulation.seed=3".into(),
        });
    };
    let (key, value) = (key.trim(), value.trim());
    let value = match value.parse::<toml_edit::Value>() {
        Ok(_) => Value::Toml(value.to_string()),
        Err(_) => Value::Text(value.to_string()),
    };
    Ok((key.to_string(), value))
}

/// `text` (named `origin` in errors) with `overrides` (dotted key, TOML value) applied in order.
pub(crate) fn apply(
    text: &str,
    origin: &str,
    overrides: &[(String, String)],
) -> Result<String, ScenarioError> {
    if overrides.is_empty() {
        return Ok(text.to_string());
    }
    let mut doc = text.parse::<DocumentMut>().map_err(|e| ScenarioError::Syntax {
        location: origin.to_string(),
        message: e.message().trim().to_string(),
    })?;
    for (key, value) in overrides {
        let refuse = |message: String| ScenarioError::Invalid {
            location: format!("--set {key}={value}"),
            key: key.clone(),
            message,
        };
        let value =
            value.parse::<toml_edit::Value>().map_err(|e| refuse(format!("is not a TOML value: {e}")))?;
        set(doc.as_table_mut(), key, value).map_err(refuse)?;
    }
    Ok(doc.to_string())
}

/// Sets the dotted `key` of `table` to `value`, creating the tables on the way.
fn set(table: &mut dyn TableLike, key: &str, value: toml_edit::Value) -> Result<(), String> {
    let (head, rest) = match key.split_once('.') {
        Some((h, r)) => (h, Some(r)),
        None => (key, None),
    };
    let (name, index) = match head.split_once('[') {
        Some((n, i)) => {
            let i = i.strip_suffix(']').and_then(|i| i.parse::<usize>().ok());
            (n, Some(i.ok_or_else(|| format!("has a bad index in {head:?}"))?))
        }
        None => (head, None),
    };
    if name.is_empty() {
        return Err("is not a key: a part of it is empty".into());
    }
    let Some(rest) = rest else {
        if index.is_some() {
            return Err("must end with a key, not an index".into());
        }
        table.insert(name, Item::Value(value));
        return Ok(());
    };
    let item = table.entry(name).or_insert_with(|| Item::Table(toml_edit::Table::new()));
    let inner: &mut dyn TableLike = match index {
        Some(i) => {
            let Some(array) = item.as_array_of_tables_mut() else {
                return Err(format!("indexes `{name}`, which is not a list of tables"));
            };
            let len = array.len();
            array.get_mut(i).ok_or_else(|| format!("indexes entry {i} of `{name}`, which has {len}"))?
        }
        None => {
            item.as_table_like_mut().ok_or_else(|| format!("goes into `{name}`, which is not a table"))?
        }
    };
    set(inner, rest, value)
}
