//! The keys every `[[target]]` and `[[obstacle]]` has, whatever its shape: `name` and `impact`.

use super::process::{ImpactDefaults, ImpactParams, read_impact};
use crate::reader::{Read, Section, bad};

/// Longest name of a target or obstacle, characters.
pub(crate) const MAX_NAME: usize = 64;

/// Reads and checks a surface's `name`: non-empty, file-name safe, at most [`MAX_NAME`]
/// characters, unique among `seen` (the names read so far, to which it is added).
pub(crate) fn name(s: &Section<'_>, seen: &mut Vec<String>) -> Read<String> {
    let n = s.string("name", None)?;
    let key = s.key("name");
    if n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_') {
        return bad(&key, format!("must be non-empty and use only letters, digits, '-' and '_', got {n:?}"));
    }
    if n.len() > MAX_NAME {
        // The name begins output file names (`NAME_thickness.npy`), which file systems cap at
        // 255 bytes: refused now rather than after the run.
        return bad(&key, format!("must be at most {MAX_NAME} characters, got {}", n.len()));
    }
    if seen.contains(&n) {
        return bad(&key, format!("{n:?} is used twice; names must be unique"));
    }
    seen.push(n.clone());
    Ok(n)
}

/// A surface's own impact table, laid over the process's, `process`.
pub(crate) fn impact_override(s: &Section<'_>, process: &ImpactParams) -> Read<Option<ImpactParams>> {
    s.table("impact")?.map(|t| read_impact(&t, &ImpactDefaults::over(process))).transpose()
}
