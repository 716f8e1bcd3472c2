//! Reading a TOML table key by key. Every value is converted and checked as it is read, so a
//! section comes out either whole and valid or as an error that names its key; keys nobody
//! read are refused at the end.

use std::borrow::Cow;
use std::cell::RefCell;
use toml::Spanned;
use toml::de::{DeInteger, DeTable, DeValue};

/// A parsed TOML table: every key and value with its byte span in the text it came from.
pub(crate) type Table<'a> = DeTable<'a>;
/// A parsed TOML value.
pub(crate) type Value<'a> = DeValue<'a>;

/// A value a scenario may not have: the dotted key (0-based indices) and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{key}` {message}")]
pub struct Invalid {
    /// Dotted path of the key, e.g. `simulation.dt` or `target[0].up`.
    pub key: String,
    /// What is wrong with it.
    pub message: String,
}

/// The result of reading one value.
pub(crate) type Read<T> = Result<T, Invalid>;

/// An [`Invalid`] for `key`.
pub(crate) fn bad<T>(key: &str, message: impl Into<String>) -> Read<T> {
    Err(Invalid { key: key.to_string(), message: message.into() })
}

/// Largest coordinate magnitude accepted anywhere, m: beyond any construction site (the
/// engine's own bound, which it checks again on the nozzle's path and on checkpoints).
pub use spraysim_engine::config::MAX_COORD;

/// How a number is checked.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Check {
    /// Within `[lo, hi]`.
    Within(f64, f64),
    /// Within `(0, hi]`.
    Positive(f64),
}

/// A word a key takes, mapped to a value: the variants of a setting.
pub(crate) trait Choice: Sized + Copy + 'static {
    /// Every variant with its name in files.
    const NAMES: &'static [(&'static str, Self)];

    /// The name of this variant.
    fn name(self) -> &'static str
    where
        Self: PartialEq,
    {
        Self::NAMES.iter().find(|(_, v)| *v == self).map_or("?", |(n, _)| n)
    }
}

/// The kind of a TOML value, for messages; a long string is cut short.
fn kind(v: &Value<'_>) -> String {
    match v {
        Value::String(s) if s.chars().count() > 60 => {
            format!(
                "the string {:?}… ({} characters)",
                s.chars().take(40).collect::<String>(),
                s.chars().count()
            )
        }
        Value::String(s) => format!("the string {s:?}"),
        Value::Integer(i) => format!("the integer {i}"),
        Value::Float(f) => match float(f) {
            Ok(x) => format!("the number {}", Num(x)),
            Err(_) => format!("the number {f}"),
        },
        Value::Boolean(b) => format!("the boolean {b}"),
        Value::Datetime(d) => format!("the date {d}"),
        Value::Array(a) => format!("an array of {} values", a.len()),
        Value::Table(_) => "a table".into(),
    }
}

/// A value as TOML text on one line, numbers as written (`"wall"`, `2e4`, `[1, 2]`,
/// `{target = "wall"}`).
fn inline(v: &Value<'_>) -> String {
    match v {
        Value::String(s) => toml_edit::Value::from(s.as_ref()).to_string().trim().to_string(),
        Value::Integer(i) => i.to_string(),
        Value::Float(f) => f.to_string(),
        Value::Boolean(b) => b.to_string(),
        Value::Datetime(d) => d.to_string(),
        Value::Array(items) => {
            format!("[{}]", items.iter().map(|i| inline(i.get_ref())).collect::<Vec<_>>().join(", "))
        }
        Value::Table(t) => {
            let entries = (t.iter())
                .map(|(k, v)| format!("{} = {}", key_text(k.get_ref()), inline(v.get_ref())))
                .collect::<Vec<_>>();
            format!("{{{}}}", entries.join(", "))
        }
    }
}

/// A number as messages print it: as written for everyday magnitudes (`0.001`, `2500`), in
/// scientific notation beyond them (`1e308`, `2.5e-9`), always with the fewest digits that
/// give it back exactly.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Num(pub f64);

impl std::fmt::Display for Num {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || !a.is_finite() || (1e-4..1e15).contains(&a) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// The most a TOML integer may be: integers are 64-bit, signed.
const INTEGER_RANGE: &str = "TOML integers are 64-bit, from -9223372036854775808 to 9223372036854775807";

/// An integer's value; `None` beyond 64 bits.
fn whole(i: &DeInteger<'_>) -> Option<i64> {
    i64::from_str_radix(i.as_str(), i.radix()).ok()
}

/// A float's value, or why it has none (too large for 64 bits).
fn float(f: &toml::de::DeFloat<'_>) -> Result<f64, String> {
    match f.as_str().parse::<f64>() {
        Ok(x) if x.is_infinite() && !f.as_str().contains("inf") => {
            Err(format!("{f}, beyond the largest 64-bit float (about 1.8e308)"))
        }
        Ok(x) => Ok(x),
        Err(_) => Err(format!("{f}, not a number")),
    }
}

/// A number (an integer or a float) as f64; `None` for other kinds; an error for a number
/// beyond 64 bits, saying so.
fn as_number(v: &Value<'_>) -> Option<Result<f64, String>> {
    match v {
        Value::Float(f) => Some(float(f)),
        Value::Integer(i) => {
            Some(whole(i).map(|x| x as f64).ok_or_else(|| format!("the integer {i}: {INTEGER_RANGE}")))
        }
        _ => None,
    }
}

/// A key as a dotted path prints it: bare when it can be, quoted otherwise (`"a.b"`).
pub(crate) fn key_text(k: &str) -> Cow<'_, str> {
    let bare = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    if !k.is_empty() && k.chars().all(bare) {
        Cow::Borrowed(k)
    } else {
        Cow::Owned(toml_edit::Key::new(k).display_repr().into_owned())
    }
}

/// An item of a list that takes numbers and words (`[0.5, 2.0, "end"]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum NumberOrWord {
    /// A number, as given.
    Number(f64),
    /// One of the words the list takes.
    Word(&'static str),
}

/// One table of a scenario, being read.
pub(crate) struct Section<'a> {
    path: String,
    table: &'a Table<'a>,
    used: RefCell<Vec<&'a str>>,
}

/// A table of one string, for reading a section built in code (e.g. a preset's name alone).
pub(crate) fn table_of(key: &'static str, value: &'static str) -> Table<'static> {
    let mut t = Table::new();
    t.insert(Spanned::new(0..0, Cow::Borrowed(key)), Spanned::new(0..0, Value::String(Cow::Borrowed(value))));
    t
}

impl<'a> Section<'a> {
    /// The document's top level.
    pub fn root(table: &'a Table<'a>) -> Self {
        Section { path: String::new(), table, used: RefCell::new(Vec::new()) }
    }

    /// An empty section at `path` (a table the file leaves out).
    pub fn empty<'b>(path: &str) -> Section<'b> {
        static EMPTY: std::sync::OnceLock<Table<'static>> = std::sync::OnceLock::new();
        Section {
            path: path.to_string(),
            table: EMPTY.get_or_init(Table::new),
            used: RefCell::new(Vec::new()),
        }
    }

    /// The dotted key of `k` in this section (`k` quoted if it is not a bare key).
    pub fn key(&self, k: &str) -> String {
        let k = key_text(k);
        if self.path.is_empty() { k.into_owned() } else { format!("{}.{k}", self.path) }
    }

    /// True if the file gives `k` here.
    pub fn has(&self, k: &str) -> bool {
        self.table.contains_key(k)
    }

    /// True if an override (`--set`, [`crate::Scenario::with`]) set `k` here, or made the
    /// table `k` on its way to a key inside it; false for a key of the file, or one inside a
    /// table that an override set whole.
    pub fn set_by_override(&self, k: &str) -> bool {
        self.table
            .get_key_value(k)
            .is_some_and(|(key, _)| crate::overrides::override_of(&key.span()).is_some())
    }

    /// The dotted path of this section (`nozzle`, `target[1]`; empty for the top level).
    pub fn path(&self) -> &str {
        &self.path
    }

    /// This section's keys but those of `left_out`, as one TOML inline table with the values
    /// as given (`{roll = 30, raster = {target = "wall"}}`).
    pub fn inline_without(&self, left_out: &[&str]) -> String {
        let entries = (self.table.iter())
            .filter(|(k, _)| !left_out.contains(&k.get_ref().as_ref()))
            .map(|(k, v)| format!("{} = {}", key_text(k.get_ref()), inline(v.get_ref())))
            .collect::<Vec<_>>();
        format!("{{{}}}", entries.join(", "))
    }

    fn raw(&self, k: &str) -> Option<&'a Value<'a>> {
        let (key, value) = self.table.get_key_value(k)?;
        self.used.borrow_mut().push(key.get_ref().as_ref());
        Some(value.get_ref())
    }

    /// A number (integers are accepted), or `default` when absent; checked finite and in range.
    pub fn number(&self, k: &str, default: Option<f64>, check: Check, unit: &str) -> Read<f64> {
        let key = self.key(k);
        let x = match self.raw(k) {
            None => default.map_or_else(|| bad(&key, "is required"), Ok)?,
            Some(v) => match as_number(v) {
                Some(Ok(x)) => x,
                Some(Err(why)) => return bad(&key, format!("must be a number ({unit}), got {why}")),
                None => return bad(&key, format!("must be a number ({unit}), got {}", kind(v))),
            },
        };
        number_in(&key, x, check, unit)?;
        Ok(x)
    }

    /// A fixed number of numbers, each checked.
    pub fn numbers<const N: usize>(
        &self,
        k: &str,
        default: Option<[f64; N]>,
        check: Check,
        unit: &str,
    ) -> Read<[f64; N]> {
        let key = self.key(k);
        let Some(v) = self.raw(k) else {
            return default.map_or_else(|| bad(&key, "is required"), Ok);
        };
        let what = || format!("must be an array of {N} numbers ({unit})");
        let Value::Array(items) = v else { return bad(&key, format!("{}, got {}", what(), kind(v))) };
        if items.len() != N {
            return bad(&key, format!("{}, got {} values", what(), items.len()));
        }
        let mut out = [0.0; N];
        for (o, item) in out.iter_mut().zip(items.iter()) {
            *o = match as_number(item.get_ref()) {
                Some(Ok(x)) => x,
                Some(Err(why)) => return bad(&key, format!("{}, got {why} in it", what())),
                None => return bad(&key, format!("{}, got {} in it", what(), kind(item.get_ref()))),
            };
            number_in(&key, *o, check, unit)?;
        }
        Ok(out)
    }

    /// A list of numbers of any length in `1..=max`, each checked.
    pub fn list(&self, k: &str, default: Option<Vec<f64>>, max: usize, check: Check) -> Read<Vec<f64>> {
        let key = self.key(k);
        let Some(v) = self.raw(k) else {
            return default.map_or_else(|| bad(&key, "is required"), Ok);
        };
        let Value::Array(items) = v else {
            return bad(&key, format!("must be an array of numbers, got {}", kind(v)));
        };
        if items.is_empty() || items.len() > max {
            return bad(&key, format!("must have between 1 and {max} numbers, got {}", items.len()));
        }
        items
            .iter()
            .map(|item| {
                let x = match as_number(item.get_ref()) {
                    Some(Ok(x)) => x,
                    Some(Err(why)) => {
                        return bad(&key, format!("must be an array of numbers, got {why} in it"));
                    }
                    None => {
                        let other = kind(item.get_ref());
                        return bad(&key, format!("must be an array of numbers, got {other} in it"));
                    }
                };
                number_in(&key, x, check, "")?;
                Ok(x)
            })
            .collect()
    }

    /// A list of `[a, b]` pairs of finite numbers, at most `max` of them.
    pub fn pairs(&self, k: &str, default: Option<Vec<[f64; 2]>>, max: usize) -> Read<Vec<[f64; 2]>> {
        let key = self.key(k);
        let Some(v) = self.raw(k) else {
            return default.map_or_else(|| bad(&key, "is required"), Ok);
        };
        let what = "must be an array of [a, b] pairs of numbers";
        let Value::Array(items) = v else { return bad(&key, format!("{what}, got {}", kind(v))) };
        if items.len() > max {
            return bad(&key, format!("must have at most {max} pairs, got {}", items.len()));
        }
        items
            .iter()
            .map(|item| {
                let Value::Array(pair) = item.get_ref() else {
                    return bad(&key, format!("{what}, got {} in it", kind(item.get_ref())));
                };
                let num = |v: &Spanned<Value<'_>>| as_number(v.get_ref()).and_then(Result::ok);
                match &pair[..] {
                    [a, b] => match (num(a), num(b)) {
                        (Some(a), Some(b)) if a.is_finite() && b.is_finite() => Ok([a, b]),
                        _ => bad(&key, format!("{what}: every value a finite number")),
                    },
                    _ => bad(&key, format!("{what}, got a list of {} values in it", pair.len())),
                }
            })
            .collect()
    }

    /// A point, m: three finite numbers within [`MAX_COORD`] of the origin.
    pub fn point(&self, k: &str, default: Option<[f64; 3]>) -> Read<[f64; 3]> {
        self.numbers(k, default, Check::Within(-MAX_COORD, MAX_COORD), "m")
    }

    /// A direction: three finite numbers, not all (nearly) zero.
    pub fn direction(&self, k: &str, default: Option<[f64; 3]>) -> Read<[f64; 3]> {
        let d = self.numbers(k, default, Check::Within(-1e9, 1e9), "a direction")?;
        if glam::DVec3::from_array(d).length() < 1e-9 {
            return bad(&self.key(k), "must not be a zero-length vector");
        }
        Ok(d)
    }

    /// A whole number within `lo..=hi`.
    pub fn integer(&self, k: &str, default: Option<i64>, lo: i64, hi: i64) -> Read<i64> {
        let key = self.key(k);
        let x = match self.raw(k) {
            None => default.map_or_else(|| bad(&key, "is required"), Ok)?,
            Some(Value::Integer(i)) => match whole(i) {
                Some(x) => x,
                None => {
                    return bad(
                        &key,
                        format!("must be a whole number between {lo} and {hi}, got {i}: {INTEGER_RANGE}"),
                    );
                }
            },
            Some(v) => return bad(&key, format!("must be a whole number, got {}", kind(v))),
        };
        if !(lo..=hi).contains(&x) {
            return bad(&key, format!("must be between {lo} and {hi}, got {x}"));
        }
        Ok(x)
    }

    /// A true or false.
    pub fn boolean(&self, k: &str, default: bool) -> Read<bool> {
        match self.raw(k) {
            None => Ok(default),
            Some(Value::Boolean(b)) => Ok(*b),
            Some(v) => bad(&self.key(k), format!("must be true or false, got {}", kind(v))),
        }
    }

    /// A string of any content, or `default` when absent.
    pub fn string(&self, k: &str, default: Option<&str>) -> Read<String> {
        let key = self.key(k);
        match self.raw(k) {
            None => default.map(str::to_string).map_or_else(|| bad(&key, "is required"), Ok),
            Some(Value::String(s)) => Ok(s.to_string()),
            Some(v) => bad(&key, format!("must be a string, got {}", kind(v))),
        }
    }

    /// One of the words of `E`.
    pub fn choice<E: Choice>(&self, k: &str, default: Option<E>) -> Read<E> {
        let key = self.key(k);
        let names = || E::NAMES.iter().map(|(n, _)| format!("\"{n}\"")).collect::<Vec<_>>().join(", ");
        match self.raw(k) {
            None => default.map_or_else(|| bad(&key, format!("is required: one of {}", names())), Ok),
            Some(Value::String(s)) => E::NAMES
                .iter()
                .find(|(n, _)| *n == s.as_ref())
                .map(|(_, v)| *v)
                .map_or_else(|| bad(&key, format!("must be one of {}, got {s:?}", names())), Ok),
            Some(v) => bad(&key, format!("must be one of {}, got {}", names(), kind(v))),
        }
    }

    /// A list of words of `E`, each at most once (an empty list when the file gives none).
    pub fn choice_list<E: Choice + PartialEq>(&self, k: &str) -> Read<Vec<E>> {
        let key = self.key(k);
        let names = || E::NAMES.iter().map(|(n, _)| format!("\"{n}\"")).collect::<Vec<_>>().join(", ");
        let items = match self.raw(k) {
            None => return Ok(Vec::new()),
            Some(Value::Array(items)) => items,
            Some(v) => return bad(&key, format!("must be a list of {}, got {}", names(), kind(v))),
        };
        let mut out = Vec::new();
        for (i, item) in items.iter().enumerate() {
            let found = match item.get_ref() {
                Value::String(s) => E::NAMES.iter().find(|(n, _)| *n == s.as_ref()).map(|(_, v)| *v),
                _ => None,
            };
            match found {
                Some(v) if out.contains(&v) => return bad(&format!("{key}[{i}]"), "is listed twice"),
                Some(v) => out.push(v),
                None => return bad(&format!("{key}[{i}]"), format!("must be one of {}", names())),
            }
        }
        Ok(out)
    }

    /// True if the file gives `k` here as a table (the other forms of a key that takes either
    /// a switch or a table are read with [`Section::boolean`]).
    pub fn is_table(&self, k: &str) -> bool {
        matches!(self.table.get(k).map(Spanned::get_ref), Some(Value::Table(_)))
    }

    /// A list of `1..=max` items, each a number or one of `words`; `None` when absent.
    pub fn numbers_or_words(
        &self,
        k: &str,
        words: &[&'static str],
        max: usize,
    ) -> Read<Option<Vec<NumberOrWord>>> {
        let key = self.key(k);
        let Some(v) = self.raw(k) else { return Ok(None) };
        let names = words.iter().map(|w| format!("\"{w}\"")).collect::<Vec<_>>().join(", ");
        let what = format!("must be an array of numbers or {names}");
        let Value::Array(items) = v else { return bad(&key, format!("{what}, got {}", kind(v))) };
        if items.is_empty() || items.len() > max {
            return bad(&key, format!("must have between 1 and {max} items, got {}", items.len()));
        }
        let item = |v: &Spanned<Value<'_>>| match (v.get_ref(), as_number(v.get_ref())) {
            (_, Some(Ok(x))) => {
                number_in(&key, x, Check::Within(-1e300, 1e300), "").map(|()| NumberOrWord::Number(x))
            }
            (_, Some(Err(why))) => bad(&key, format!("{what}, got {why} in it")),
            (Value::String(s), None) => match words.iter().find(|w| **w == s.as_ref()) {
                Some(w) => Ok(NumberOrWord::Word(w)),
                None => bad(&key, format!("{what}, got {} in it", kind(v.get_ref()))),
            },
            (other, None) => bad(&key, format!("{what}, got {} in it", kind(other))),
        };
        items.iter().map(item).collect::<Read<Vec<_>>>().map(Some)
    }

    /// The sub-table `k`, if the file gives it.
    pub fn table(&self, k: &str) -> Read<Option<Section<'a>>> {
        match self.raw(k) {
            None => Ok(None),
            Some(Value::Table(t)) => {
                Ok(Some(Section { path: self.key(k), table: t, used: RefCell::new(Vec::new()) }))
            }
            Some(v) => bad(&self.key(k), format!("must be a table, got {}", kind(v))),
        }
    }

    /// The sub-table `k`, or an empty one.
    pub fn table_or_empty(&self, k: &str) -> Read<Section<'a>> {
        Ok(self.table(k)?.unwrap_or_else(|| Section::empty(&self.key(k))))
    }

    /// The array of tables `k` (`[[k]]`), each at `k[i]`.
    pub fn tables(&self, k: &str) -> Read<Vec<Section<'a>>> {
        let key = self.key(k);
        match self.raw(k) {
            None => Ok(Vec::new()),
            Some(Value::Array(items)) => items
                .iter()
                .enumerate()
                .map(|(i, item)| match item.get_ref() {
                    Value::Table(t) => {
                        Ok(Section { path: format!("{key}[{i}]"), table: t, used: RefCell::new(Vec::new()) })
                    }
                    other => bad(&format!("{key}[{i}]"), format!("must be a table, got {}", kind(other))),
                })
                .collect(),
            Some(v) => bad(&key, format!("must be an array of tables ([[{k}]]), got {}", kind(v))),
        }
    }

    /// Refuses every key of this section that nothing read; `context` says what the section
    /// holds (e.g. `a circle emitter`), for the message.
    pub fn finish(&self, context: &str) -> Read<()> {
        let used = self.used.borrow();
        match self.table.keys().map(|k| k.get_ref().as_ref()).find(|k| !used.contains(k)) {
            None => Ok(()),
            // A quoted key with a dot in it is one key, not a path: say so.
            Some(k) if k.contains('.') && !k.starts_with('.') && !k.ends_with('.') => bad(
                &self.key(k),
                format!(
                    "is not a key of {context} (see docs/scenario.md); a quoted key is one key, dots and all: \
                     for the path, write {} without quotes",
                    k
                ),
            ),
            Some(k) => bad(&self.key(k), format!("is not a key of {context} (see docs/scenario.md)")),
        }
    }
}

/// Checks that the directions `a` (read from `key`) and `b` (read from the key named `what`)
/// are not parallel: the sine of their angle above 1e-6.
pub(crate) fn not_parallel(key: &str, a: [f64; 3], b: [f64; 3], what: &str) -> Read<()> {
    let (a, b) = (glam::DVec3::from_array(a).normalize(), glam::DVec3::from_array(b).normalize());
    if a.cross(b).length() < 1e-6 {
        return bad(key, format!("must not be parallel to {what}"));
    }
    Ok(())
}

/// Checks a number read from `key`.
pub(crate) fn number_in(key: &str, x: f64, check: Check, unit: &str) -> Read<()> {
    let (lo, hi, x) = match check {
        Check::Within(lo, hi) => (Num(lo), Num(hi), Num(x)),
        Check::Positive(hi) => (Num(0.0), Num(hi), Num(x)),
    };
    if !x.0.is_finite() {
        return bad(key, format!("must be a finite number, got {x}"));
    }
    let unit = if unit.is_empty() { String::new() } else { format!(" {unit}") };
    match check {
        Check::Within(..) if x.0 < lo.0 || x.0 > hi.0 => {
            bad(key, format!("must be between {lo} and {hi}{unit}, got {x}"))
        }
        Check::Positive(_) if x.0 <= 0.0 => bad(key, format!("must be greater than 0{unit}, got {x}")),
        Check::Positive(_) if x.0 > hi.0 => bad(key, format!("must be between 0 and {hi}{unit}, got {x}")),
        _ => Ok(()),
    }
}

/// Declares the words of a setting: `impl Choice` and a `Serialize` that writes the word.
macro_rules! choices {
    ($ty:ty { $( $name:literal => $variant:expr ),* $(,)? }) => {
        impl $crate::reader::Choice for $ty {
            const NAMES: &'static [(&'static str, Self)] = &[ $( ($name, $variant) ),* ];
        }
    };
}
pub(crate) use choices;
