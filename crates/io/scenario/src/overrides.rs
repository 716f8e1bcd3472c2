//! Overrides by dotted key (`emitter.spawn_rate`, `target[0].resolution`), applied to the
//! scenario's text before it is read, so that an overridden value is checked exactly as if the
//! file had given it.

use crate::error::ScenarioError;
use std::borrow::Cow;
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// A value to set: a number, a boolean, a string, a list of numbers, or TOML text.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A number, written as a TOML float.
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
/// The key is split at the first `=` outside quotes, so a quoted key may hold one.
pub(crate) fn split(assignment: &str) -> Result<(String, Value), ScenarioError> {
    let Some((key, value)) =
        find_outside_quotes(assignment, '=').map(|i| (&assignment[..i], &assignment[i + 1..]))
    else {
        let quote =
            if split_outside_quotes(assignment, '=').is_none() { "; a quote is not closed" } else { "" };
        return Err(ScenarioError::Syntax {
            location: format!("--set {assignment}"),
            message: format!("must be KEY=VALUE, e.g. simulation.seed=3{quote}"),
        });
    };
    let (key, value) = (key.trim(), value.trim());
    let value = match DeValue::parse(value) {
        Ok(_) => Value::Toml(value.to_string()),
        Err(_) => Value::Text(value.to_string()),
    };
    Ok((key.to_string(), value))
}

/// Where spans of what overrides set start: the span of a key or table an override set or
/// made is `OVERRIDE + i` (its index), far past the end of any text, so that an error in it is
/// put on the override rather than on a line of the file.
pub(crate) const OVERRIDE: usize = usize::MAX / 2;

/// The index of the override that set a key or value with `span`, if one did.
pub(crate) fn override_of(span: &std::ops::Range<usize>) -> Option<usize> {
    span.start.checked_sub(OVERRIDE)
}

/// One step of an override's key: a key of a table, and the entry of the array of tables
/// under it when the step is indexed (`target[1]`).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Step {
    /// The key, unquoted.
    pub name: String,
    /// The 0-based entry of the array of tables, if indexed.
    pub index: Option<usize>,
}

/// Parses an override's key: TOML's dotted-key syntax (bare or quoted parts:
/// `nozzle.raster.speed`, `simulation."dt"`, `"a.b"`), each part optionally indexed (`[1]`) to
/// go into an entry of an array of tables.
pub(crate) fn parse_key(key: &str) -> Result<Vec<Step>, String> {
    let parts = split_outside_quotes(key, '.').ok_or("is not a key: a quote is not closed")?;
    parts.into_iter().map(|part| step(part.trim())).collect()
}

/// One part of an override's key: a TOML key, optionally followed by `[i]`.
fn step(part: &str) -> Result<Step, String> {
    let (name, index) = match part.strip_suffix(']').and_then(|p| p.rsplit_once('[')) {
        // The `[` is outside the name's quotes when the name's quotes are all closed.
        Some((name, i)) if split_outside_quotes(name, '[').is_some_and(|p| p.len() == 1) => {
            let i = i.trim().parse::<usize>().map_err(|_| format!("has a bad index in {part:?}"))?;
            (name.trim(), Some(i))
        }
        _ => (part, None),
    };
    if name.is_empty() {
        return Err("is not a key: a part of it is empty".into());
    }
    match toml_edit::Key::parse(name) {
        Ok(keys) if keys.len() == 1 => Ok(Step { name: keys[0].get().to_string(), index }),
        _ => Err(format!("is not a key: {name} is neither a bare nor a quoted TOML key")),
    }
}

/// Where a scan of TOML text is: outside quotes, or inside `"…"` (with `\` escapes) or `'…'`.
#[derive(Default)]
struct Quotes {
    open: Option<char>,
    escaped: bool,
}

impl Quotes {
    /// Takes the next character; true if it is outside quotes (and not a quote itself).
    fn outside(&mut self, c: char) -> bool {
        match self.open {
            Some('"') if self.escaped => self.escaped = false,
            Some('"') if c == '\\' => self.escaped = true,
            Some(q) if c == q => self.open = None,
            Some(_) => {}
            None if c == '"' || c == '\'' => self.open = Some(c),
            None => return true,
        }
        false
    }
}

/// Byte offset of the first `sep` outside TOML quotes in `text`.
fn find_outside_quotes(text: &str, sep: char) -> Option<usize> {
    let mut quotes = Quotes::default();
    text.char_indices().find(|&(_, c)| quotes.outside(c) && c == sep).map(|(i, _)| i)
}

/// The pieces of `text` between the `sep`s outside TOML quotes; `None` when a quote is not
/// closed.
fn split_outside_quotes(text: &str, sep: char) -> Option<Vec<&str>> {
    let mut pieces = Vec::new();
    let mut start = 0;
    let mut quotes = Quotes::default();
    for (i, c) in text.char_indices() {
        if quotes.outside(c) && c == sep {
            pieces.push(&text[start..i]);
            start = i + c.len_utf8();
        }
    }
    if quotes.open.is_some() {
        return None;
    }
    pieces.push(&text[start..]);
    Some(pieces)
}

/// Applies `overrides` (dotted key, TOML value) to `doc` together, so that their order does not
/// matter: shallower keys first (a table replaced whole, `nozzle={raster={…}}`, before a key
/// set inside it, `nozzle.raster.speed=1`), and among keys of one depth in the order given (a
/// key set twice takes the later value). What each sets or makes is marked with the override's
/// span ([`OVERRIDE`] plus its index as given). A refusal names the override.
pub(crate) fn apply<'i>(
    doc: &mut DeTable<'i>,
    overrides: &'i [(String, String)],
) -> Result<(), ScenarioError> {
    let mut parsed = Vec::with_capacity(overrides.len());
    for (n, (key, value)) in overrides.iter().enumerate() {
        let steps = parse_key(key).map_err(refusal(key, value))?;
        let value = DeValue::parse(value)
            .map_err(|e| refusal(key, value)(format!("is not a TOML value: {}", e.message().trim())))?
            .into_inner();
        parsed.push((n, steps, value));
    }
    // A stable sort: keys of one depth keep the order given.
    parsed.sort_by_key(|(_, steps, _)| steps.len());
    for (n, steps, value) in parsed {
        let (key, text) = &overrides[n];
        set(doc, &steps, value, OVERRIDE + n).map_err(refusal(key, text))?;
    }
    Ok(())
}

/// The refusal of the override `key=value`, with what is wrong.
fn refusal<'a>(key: &'a str, value: &'a str) -> impl Fn(String) -> ScenarioError + 'a {
    move |message| ScenarioError::Invalid {
        location: format!("--set {key}={value}"),
        key: key.to_string(),
        message,
    }
}

/// How many leading parts the dotted keys `a` and `b` share (`nozzle.raster` and
/// `nozzle.axis` share 1); 0 when either is not a key.
pub(crate) fn shared_parts(a: &str, b: &str) -> usize {
    match (parse_key(a), parse_key(b)) {
        (Ok(a), Ok(b)) => a.iter().zip(&b).take_while(|(x, y)| x.name == y.name).count(),
        _ => 0,
    }
}

/// Sets the key `steps` of `table` to `value`, making the tables on the way; what it sets or
/// makes gets the span `at..at`.
fn set<'i>(table: &mut DeTable<'i>, steps: &[Step], value: DeValue<'i>, at: usize) -> Result<(), String> {
    let Some((step, rest)) = steps.split_first() else { return Err("is not a key: it is empty".into()) };
    let Step { name, index } = step;
    let key = || Spanned::new(at..at, Cow::Owned(name.clone()));
    if rest.is_empty() {
        if index.is_some() {
            return Err("must end with a key, not an index".into());
        }
        // Removed first, so that the key too is the override's, not the file's.
        table.remove(name.as_str());
        table.insert(key(), Spanned::new(at..at, value));
        return Ok(());
    }
    if !table.contains_key(name.as_str()) {
        table.insert(key(), Spanned::new(at..at, DeValue::Table(DeTable::new())));
    }
    let item = table.get_mut(name.as_str()).map(Spanned::get_mut);
    let inner = match (index, item) {
        (Some(i), Some(DeValue::Array(array))) => {
            let len = array.len();
            match array.get_mut(*i).map(Spanned::get_mut) {
                Some(DeValue::Table(t)) => t,
                Some(_) => return Err(format!("indexes `{name}`, which is not a list of tables")),
                None => return Err(format!("indexes entry {i} of `{name}`, which has {len}")),
            }
        }
        (Some(_), _) => return Err(format!("indexes `{name}`, which is not a list of tables")),
        (None, Some(DeValue::Table(t))) => t,
        (None, _) => return Err(format!("goes into `{name}`, which is not a table")),
    };
    set(inner, rest, value, at)
}
