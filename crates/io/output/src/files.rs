//! Writing a set of files into a directory so that it always holds one complete set.
//!
//! The files are staged in a folder inside the directory, then moved into place. The first
//! file of a set (a run's `metrics.json`) is its index: it is removed before anything moves
//! and moved in last, so while it is present the directory holds exactly the set it
//! describes. The names the last write put there are kept in [`FILE_LIST`]; a new set removes
//! those it does not write again (the maps of a target that no longer exists, an old impact
//! log), and nothing else. A staging folder records, before anything moves, every name that
//! may be in the directory once it does: a run killed while moving files leaves it behind, and
//! the next write into the directory removes it and what it names.

use crate::control::{Committing, pause_point};
use crate::{OutputError, io_err};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// The list of the files the last complete write put in a directory, one name a line.
pub const FILE_LIST: &str = ".spraysim-files";
/// The prefix of staging folders, followed by the writing process's id.
pub const STAGING_PREFIX: &str = ".spraysim-staging-";
/// Inside a staging folder: the names that may be in the directory once files move.
const JOURNAL: &str = ".journal";

/// Writes `files` (relative path, contents) into `dir`, created if needed, as one set: all or
/// none of them, the first (the set's index) last, and removing the files of the previous set
/// that this one does not write. Returns the paths written.
pub fn write_all(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Vec<PathBuf>, OutputError> {
    for (name, _) in files {
        check_name(name)?;
    }
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    let mut owned = read_list(&dir.join(FILE_LIST));
    owned.extend(clean_staging(dir));
    let staging = dir.join(format!("{STAGING_PREFIX}{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&staging);
    std::fs::create_dir(&staging).map_err(io_err(&staging))?;
    let result = stage(&staging, files).and_then(|()| commit(dir, &staging, files, &owned));
    let _ = std::fs::remove_dir_all(&staging);
    result
}

/// A name a set may hold: relative, inside the directory, not one of the writer's own.
fn check_name(name: &str) -> Result<(), OutputError> {
    let path = Path::new(name);
    let inside = path.components().all(|c| matches!(c, std::path::Component::Normal(_)));
    if name.is_empty() || !inside || name.starts_with(".spraysim") {
        let source =
            std::io::Error::new(std::io::ErrorKind::InvalidInput, "not a file name inside the directory");
        return Err(OutputError::Io { path: name.into(), source });
    }
    Ok(())
}

/// The names listed in `path`, one a line (none when it does not exist).
fn read_list(path: &Path) -> BTreeSet<String> {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    text.lines().filter(|l| check_name(l).is_ok()).map(str::to_string).collect()
}

/// Removes the staging folders of writers that are gone (killed, or stopped by a second
/// Ctrl-C); returns the names their journals list.
fn clean_staging(dir: &Path) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    let Ok(entries) = std::fs::read_dir(dir) else { return names };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        let Some(pid) = name.strip_prefix(STAGING_PREFIX) else { continue };
        if pid.parse::<u32>().is_ok_and(alive) {
            continue;
        }
        names.extend(read_list(&entry.path().join(JOURNAL)));
        let _ = std::fs::remove_dir_all(entry.path());
    }
    names
}

/// Whether process `pid` is running (another writer into the same directory): where that
/// cannot be told, only this process counts as running.
fn alive(pid: u32) -> bool {
    pid == std::process::id() || Path::new("/proc").join(pid.to_string()).exists()
}

/// Writes every file into `staging`, folders included.
fn stage(staging: &Path, files: &[(String, Vec<u8>)]) -> Result<(), OutputError> {
    for (name, bytes) in files {
        let path = staging.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        std::fs::write(&path, bytes).map_err(io_err(&path))?;
    }
    pause_point("staged");
    Ok(())
}

/// Moves the staged files into `dir`: the index out first and in last, the rest between,
/// then removes what the previous sets (`owned`) held that this one does not.
fn commit(
    dir: &Path,
    staging: &Path,
    files: &[(String, Vec<u8>)],
    owned: &BTreeSet<String>,
) -> Result<Vec<PathBuf>, OutputError> {
    let new: BTreeSet<String> = files.iter().map(|(n, _)| n.clone()).collect();
    let journal: Vec<&str> = owned.union(&new).map(String::as_str).collect();
    let path = staging.join(JOURNAL);
    std::fs::write(&path, journal.join("\n")).map_err(io_err(&path))?;
    let Some(((index, _), rest)) = files.split_first() else { return Ok(Vec::new()) };
    let Some(_guard) = Committing::start() else {
        let source =
            std::io::Error::new(std::io::ErrorKind::Interrupted, "aborted before moving files into place");
        return Err(OutputError::Io { path: dir.to_path_buf(), source });
    };
    match std::fs::remove_file(dir.join(index)) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(io_err(&dir.join(index))(e)),
        _ => {}
    }
    let mut written = Vec::new();
    for (k, (name, _)) in rest.iter().enumerate() {
        written.push(move_in(staging, dir, name)?);
        pause_point(&format!("commit:{}", k + 1));
    }
    for stale in owned.difference(&new) {
        let _ = std::fs::remove_file(dir.join(stale));
    }
    let list: Vec<&str> = new.iter().map(String::as_str).collect();
    let staged_list = staging.join(FILE_LIST);
    std::fs::write(&staged_list, list.join("\n")).map_err(io_err(&staged_list))?;
    std::fs::rename(&staged_list, dir.join(FILE_LIST)).map_err(io_err(&dir.join(FILE_LIST)))?;
    written.insert(0, move_in(staging, dir, index)?);
    Ok(written)
}

/// Moves `name` from `staging` into `dir`, creating its folders.
fn move_in(staging: &Path, dir: &Path, name: &str) -> Result<PathBuf, OutputError> {
    let to = dir.join(name);
    if let Some(parent) = to.parent() {
        std::fs::create_dir_all(parent).map_err(io_err(parent))?;
    }
    std::fs::rename(staging.join(name), &to).map_err(io_err(&to))?;
    Ok(to)
}
