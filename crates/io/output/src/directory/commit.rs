//! Writing a set of files into a directory so that it holds the previous complete set or the
//! new one, never a mix, and removing only what spraysim wrote there.
//!
//! 1. **Check.** Every name is one of spraysim's [`OUTPUT_NAMES`], and nothing that cannot be
//!    replaced (a folder, a FIFO, a link on the way) stands where a file goes; otherwise the
//!    write is refused before anything changes.
//! 2. **Stage.** The files are written into a fresh staging folder inside the directory
//!    (created exclusively, under a random name), in `new/`.
//! 3. **Journal.** The staging folder's journal records the new files (name, size, SHA-256)
//!    and the names about to be moved aside, before anything moves.
//! 4. **Swap.** The previous set's files that this one replaces or no longer writes are moved
//!    aside into the staging folder's `old/`, the index (`metrics.json`, the set's first file)
//!    first; then the new files move in, the index last. A failure on the way moves everything
//!    back: the directory holds the previous set again. The caller's [`CommitHooks`] may refuse
//!    the swap before the first move, and hold it off from outside until the last.
//! 5. **List.** [`FILE_LIST`] records each file of the set with its size and SHA-256. A later
//!    set removes a file of an earlier one only if the list names it, its name is one of
//!    spraysim's, it is a regular file reached without following a link, and its size and
//!    hash are still those spraysim wrote: a file spraysim did not write is never touched.
//!
//! A writer killed during the swap leaves its staging folder; the next writer to lock the
//! directory (see [`super::lock`]) reads the journal and finishes the swap backwards (or, when
//! the new index is in place, forwards), with the same checks on every name.

use super::hooks::{CommitHooks, CommitPoint};
use super::paths::{
    Found, check_name, create_fresh, create_new, hash_bytes, hash_file, in_the_way, invalid, lookup,
    make_parents, read_small,
};
use crate::{OutputError, io_err};
use std::collections::BTreeSet;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The list of the files the last complete write put in a directory: one a line, as
/// `SHA-256 BYTES NAME`.
pub const FILE_LIST: &str = ".spraysim-files";
/// The prefix of staging folders.
pub const STAGING_PREFIX: &str = ".spraysim-staging-";
/// Inside a staging folder: what the swap is about to do.
const JOURNAL: &str = "journal";
/// Inside a staging folder: the new set's files.
const NEW: &str = "new";
/// Inside a staging folder: the previous set's files, moved aside.
const OLD: &str = "old";
/// Most bytes of a list or a journal read back: far beyond any real set's.
const LIST_CAP: u64 = 16 << 20;

/// Every name spraysim writes into an output directory, as patterns in which `*` stands for
/// any part of one file name: a run's results, its 3D views, the validation report and a
/// calibration's files. Only names of these forms are ever replaced or removed.
pub const OUTPUT_NAMES: &[&str] = &[
    "metrics.json",
    "scenario.resolved.toml",
    "impacts.csv",
    "particles.ply",
    "*_thickness.npy",
    "*_hits.npy",
    "*_erosion.npy",
    "*_coating.npy",
    "*_thickness.png",
    "*_hits.png",
    "*_erosion.png",
    "*_coating.png",
    "*_sag.png",
    "*_failure.png",
    "*.ply",
    "*.vtk",
    "*.glb",
    "view_*.png",
    "frames/frame_*.png",
    "animation.gif",
    "animation.mp4",
    "validation.md",
    "validation/*.png",
    "calibrated.toml",
    "calibration.json",
    "profile.csv",
    "profile.png",
];

/// Whether `name` has the form of one of spraysim's [`OUTPUT_NAMES`].
pub fn is_output_name(name: &str) -> bool {
    let options = glob::MatchOptions { require_literal_separator: true, ..glob::MatchOptions::new() };
    check_name(name).is_ok()
        && OUTPUT_NAMES
            .iter()
            .filter_map(|p| glob::Pattern::new(p).ok())
            .any(|p| p.matches_with(name, options))
}

/// One file of a set: its name, size and SHA-256.
#[derive(Clone, Debug, PartialEq)]
struct Entry {
    name: String,
    bytes: u64,
    sha256: String,
}

impl Entry {
    fn line(&self) -> String {
        format!("{} {} {}\n", self.sha256, self.bytes, self.name)
    }

    /// Reads a line written by [`Entry::line`].
    fn parse(line: &str) -> Option<Entry> {
        let mut parts = line.splitn(3, ' ');
        let sha256 = parts.next()?.to_string();
        let bytes = parts.next()?.parse().ok()?;
        let name = parts.next()?.to_string();
        (sha256.len() == 64 && sha256.bytes().all(|b| b.is_ascii_hexdigit())).then_some(Entry {
            name,
            bytes,
            sha256,
        })
    }

    /// Whether `dir` still holds this file as written: a regular file reached without a link,
    /// of this size and hash.
    fn still_in(&self, dir: &Path) -> bool {
        matches!(lookup(dir, &self.name), Ok(Found::File(n)) if n == self.bytes)
            && hash_file(&dir.join(&self.name)).is_ok_and(|(_, h)| h == self.sha256)
    }
}

/// A name a set may hold, or the list itself.
fn movable(name: &str) -> bool {
    name == FILE_LIST || is_output_name(name)
}

/// Writes `files` (name, contents) into `dir` as one set, the first (the set's index) moved in
/// last, removing the files of the previous set that this one does not write, and telling
/// `hooks` on the way. Returns the paths written. The caller holds the directory's lock.
pub(crate) fn write_set(
    dir: &Path,
    files: &[(String, Vec<u8>)],
    hooks: &dyn CommitHooks,
) -> Result<Vec<PathBuf>, OutputError> {
    let mut names = BTreeSet::new();
    for (name, _) in files {
        check_name(name)?;
        if !is_output_name(name) {
            return Err(invalid(name, "is not one of spraysim's output names (OUTPUT_NAMES)"));
        }
        if !names.insert(name.as_str()) {
            return Err(invalid(name, "is written twice in one set"));
        }
    }
    let Some(((index, _), _)) = files.split_first() else { return Ok(Vec::new()) };
    for name in names.iter().copied().chain([FILE_LIST]) {
        match lookup(dir, name).map_err(io_err(&dir.join(name)))? {
            Found::Missing | Found::File(_) | Found::Link => {}
            Found::Folder | Found::Special => return Err(in_the_way(&dir.join(name))),
            Found::Blocked(at) => return Err(in_the_way(&at)),
        }
    }
    let entries: Vec<Entry> = files
        .iter()
        .map(|(name, bytes)| Entry {
            name: name.clone(),
            bytes: bytes.len() as u64,
            sha256: hash_bytes(bytes),
        })
        .collect();
    let list: String = entries.iter().map(Entry::line).collect();
    let stale: Vec<String> = previous_list(dir)
        .into_iter()
        .filter(|e| !names.contains(e.name.as_str()) && is_output_name(&e.name) && e.still_in(dir))
        .map(|e| e.name)
        .collect();
    let (_, staging) = create_fresh(dir, STAGING_PREFIX, "", |p| std::fs::create_dir(p))?;
    let plan = Plan { dir, staging: &staging, index, entries, list, stale, hooks };
    let result = plan.stage(files).and_then(|()| plan.swap());
    match &result {
        Err(Failed { restored: false, .. }) => {} // the journal stays, for the next writer
        _ => {
            let _ = std::fs::remove_dir_all(&staging);
        }
    }
    result.map_err(|f| f.error)?;
    plan.remove_empty_folders();
    Ok(files.iter().map(|(n, _)| dir.join(n)).collect())
}

/// The previous set's list in `dir` (empty when there is none or it cannot be read).
fn previous_list(dir: &Path) -> Vec<Entry> {
    let bytes = read_small(&dir.join(FILE_LIST), LIST_CAP).unwrap_or_default();
    String::from_utf8_lossy(&bytes).lines().filter_map(Entry::parse).collect()
}

/// A swap that failed: the error, and whether the previous set is back in place.
struct Failed {
    error: OutputError,
    restored: bool,
}

impl From<OutputError> for Failed {
    fn from(error: OutputError) -> Failed {
        Failed { error, restored: true }
    }
}

/// One set on its way into a directory.
struct Plan<'a> {
    dir: &'a Path,
    staging: &'a Path,
    index: &'a str,
    entries: Vec<Entry>,
    /// The new [`FILE_LIST`]'s contents.
    list: String,
    /// Files of the previous set that this one does not write, checked still to be spraysim's.
    stale: Vec<String>,
    /// The caller's hooks: told when the set is staged and as each file moves in, and asked
    /// before the first file moves.
    hooks: &'a dyn CommitHooks,
}

impl Plan<'_> {
    /// Writes every file into the staging folder's `new/`.
    fn stage(&self, files: &[(String, Vec<u8>)]) -> Result<(), Failed> {
        let new = self.staging.join(NEW);
        std::fs::create_dir(&new).map_err(io_err(&new))?;
        for (name, bytes) in
            files.iter().map(|(n, b)| (n.as_str(), b.as_slice())).chain([(FILE_LIST, self.list.as_bytes())])
        {
            make_parents(&new, name)?;
            let path = new.join(name);
            create_new(&path).and_then(|mut f| f.write_all(bytes)).map_err(io_err(&path))?;
        }
        self.hooks.reached(CommitPoint::Staged);
        Ok(())
    }

    /// The names to move aside, the index first: every name of the new set (and the list)
    /// that is in the directory now, and the stale files.
    fn aside(&self) -> Vec<String> {
        let present = |n: &str| matches!(lookup(self.dir, n), Ok(Found::File(_) | Found::Link));
        let new = self.entries.iter().map(|e| e.name.as_str());
        new.chain([FILE_LIST])
            .filter(|n| present(n))
            .map(str::to_string)
            .chain(self.stale.iter().cloned())
            .collect()
    }

    /// Records the swap in the journal, then moves the previous files aside and the new ones
    /// in; on a failure, moves everything back.
    fn swap(&self) -> Result<(), Failed> {
        let aside = self.aside();
        let mut journal = format!("index {}\n", self.index);
        let list = Entry {
            name: FILE_LIST.into(),
            bytes: self.list.len() as u64,
            sha256: hash_bytes(self.list.as_bytes()),
        };
        for e in self.entries.iter().chain([&list]) {
            journal.push_str(&format!("new {}", e.line()));
        }
        for name in &aside {
            journal.push_str(&format!("old {name}\n"));
        }
        let path = self.staging.join(JOURNAL);
        create_new(&path).and_then(|mut f| f.write_all(journal.as_bytes())).map_err(io_err(&path))?;
        let Some(_moving) = self.hooks.begin_moving() else {
            let source = std::io::Error::new(
                std::io::ErrorKind::Interrupted,
                "aborted before moving files into place",
            );
            return Err(OutputError::Io { path: self.dir.to_path_buf(), source }.into());
        };
        let mut moves = Moves::default();
        let result = self.moves(&aside, &mut moves);
        match result {
            Ok(()) => Ok(()),
            Err(error) => Err(Failed { error, restored: moves.undo(self) }),
        }
    }

    fn moves(&self, aside: &[String], done: &mut Moves) -> Result<(), OutputError> {
        let (new, old) = (self.staging.join(NEW), self.staging.join(OLD));
        std::fs::create_dir(&old).map_err(io_err(&old))?;
        for name in aside {
            make_parents(&old, name)?;
            rename(&self.dir.join(name), &old.join(name))?;
            done.aside.push(name.clone());
        }
        let rest = self.entries.iter().skip(1).map(|e| e.name.as_str()).chain([FILE_LIST]);
        for (k, name) in rest.enumerate() {
            make_parents(self.dir, name)?;
            rename(&new.join(name), &self.dir.join(name))?;
            done.moved_in.push(name.to_string());
            if name != FILE_LIST {
                self.hooks.reached(CommitPoint::MovedIn(k + 1));
            }
        }
        rename(&new.join(self.index), &self.dir.join(self.index))?;
        Ok(())
    }

    /// Removes the folders the stale files were in, where they are now empty.
    fn remove_empty_folders(&self) {
        for name in &self.stale {
            let mut at = Path::new(name).parent();
            while let Some(parent) = at.filter(|p| !p.as_os_str().is_empty()) {
                let path = self.dir.join(parent);
                if !std::fs::symlink_metadata(&path).is_ok_and(|m| m.is_dir())
                    || std::fs::remove_dir(&path).is_err()
                {
                    break;
                }
                at = parent.parent();
            }
        }
    }
}

fn rename(from: &Path, to: &Path) -> Result<(), OutputError> {
    std::fs::rename(from, to).map_err(io_err(to))
}

/// What a swap has moved so far.
#[derive(Default)]
struct Moves {
    /// Names of the previous set moved into `old/`.
    aside: Vec<String>,
    /// Names of the new set moved into the directory.
    moved_in: Vec<String>,
}

impl Moves {
    /// Moves everything back, the last move first; true when all of it went back.
    fn undo(&self, plan: &Plan<'_>) -> bool {
        let (new, old) = (plan.staging.join(NEW), plan.staging.join(OLD));
        let mut restored = true;
        for name in self.moved_in.iter().rev() {
            restored &= std::fs::rename(plan.dir.join(name), new.join(name)).is_ok();
        }
        for name in self.aside.iter().rev() {
            restored &= std::fs::rename(old.join(name), plan.dir.join(name)).is_ok();
        }
        restored
    }
}

/// Finishes the swaps of writers that were killed in `dir` (whose staging folders remain):
/// forwards when the new index is in place, else backwards; then removes their staging
/// folders. Only the lock's holder calls it, so every staging folder is a dead writer's.
pub(crate) fn recover(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        if !name.to_string_lossy().starts_with(STAGING_PREFIX) {
            continue;
        }
        let path = entry.path();
        match std::fs::symlink_metadata(&path) {
            Ok(m) if m.is_dir() => {
                if let Some(bytes) = read_small(&path.join(JOURNAL), LIST_CAP) {
                    finish_dead_swap(dir, &path, &String::from_utf8_lossy(&bytes));
                }
                let _ = std::fs::remove_dir_all(&path);
            }
            // A link or a file under a staging name: removed itself, its target untouched.
            Ok(_) => {
                let _ = std::fs::remove_file(&path);
            }
            Err(_) => {}
        }
    }
}

/// Rolls back (or accepts) the swap a dead writer's `journal` describes.
fn finish_dead_swap(dir: &Path, staging: &Path, journal: &str) {
    let mut index = None;
    let (mut new, mut aside) = (Vec::new(), Vec::new());
    for line in journal.lines() {
        if let Some(n) = line.strip_prefix("index ") {
            index = Some(n);
        } else if let Some(e) = line.strip_prefix("new ").and_then(Entry::parse) {
            new.push(e);
        } else if let Some(n) = line.strip_prefix("old ") {
            aside.push(n);
        }
    }
    let Some(index) = index else { return };
    let completed = new.iter().any(|e| e.name == index && e.still_in(dir));
    if completed {
        return;
    }
    for e in new.iter().filter(|e| movable(&e.name) && e.still_in(dir)) {
        let _ = std::fs::remove_file(dir.join(&e.name));
    }
    let old = staging.join(OLD);
    for name in aside.into_iter().filter(|n| movable(n)) {
        let back = matches!(lookup(&old, name), Ok(Found::File(_) | Found::Link))
            && matches!(lookup(dir, name), Ok(Found::Missing))
            && make_parents(dir, name).is_ok();
        if back {
            let _ = std::fs::rename(old.join(name), dir.join(name));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_output_of_a_run_and_the_tools_has_an_output_name() {
        for name in [
            "metrics.json",
            "wall_thickness.npy",
            "floor_hits.png",
            "panel.glb",
            "view_1.500s.png",
            "frames/frame_0001.png",
            "validation/rebound.png",
            "profile.csv",
        ] {
            assert!(is_output_name(name), "{name}");
        }
        for name in
            ["notes.txt", "link/keep.txt", "frames/sub/frame_1.png", "../metrics.json", ".spraysim-files"]
        {
            assert!(!is_output_name(name), "{name}");
        }
    }

    #[test]
    fn a_list_line_reads_back_and_a_bare_name_is_not_an_entry() {
        let e = Entry { name: "wall thickness.npy".into(), bytes: 12, sha256: hash_bytes(b"x") };
        assert_eq!(Entry::parse(e.line().trim_end()), Some(e));
        assert_eq!(Entry::parse("link/keep.txt"), None);
    }
}
