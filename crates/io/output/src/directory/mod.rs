//! The output directory's contract.
//!
//! - **One writer at a time.** A writer locks the directory ([`OutputDir::lock`]) before it
//!   writes anything there and holds the lock until it is done; a second one is refused with a
//!   message naming the holder ([`crate::OutputError::Busy`]).
//! - **Whole sets.** A set of files (a run's results, a report) replaces the previous set as a
//!   whole: the directory holds the previous complete set or the new one, never a mix, even when
//!   a write fails part-way or the writer is killed (see `commit.rs`). A caller that must know
//!   when files move (to hold off an abort) passes [`CommitHooks`] ([`hooks`]).
//! - **Nothing that spraysim did not write.** Only names of spraysim's [`OUTPUT_NAMES`] are
//!   replaced or removed, a file is removed only while it is still byte for byte what spraysim
//!   wrote, no symbolic link below the directory is followed, and temporary files are created
//!   exclusively under random names (see `paths.rs`).
//!
//! Besides a set, a directory holds the writer's bookkeeping, every name of it beginning with
//! `.spraysim-`: the list of the set's files, the lock file, the record of the run, and while
//! a write is under way a staging folder.

mod commit;
pub mod hooks;
mod lock;
mod paths;

pub use commit::{FILE_LIST, OUTPUT_NAMES, STAGING_PREFIX, is_output_name};
pub use hooks::{CommitHooks, CommitPoint, MovingGuard, NoHooks};
pub use lock::LOCK_FILE;
pub use paths::RESERVED_PREFIX;
pub(crate) use paths::hash_bytes;

use crate::{OutputError, io_err};
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The record of the run a directory holds: the SHA-256 of its resolved scenario.
pub const RUN_RECORD: &str = ".spraysim-run";
/// The prefix of a new record of the run, before it is renamed into place.
const RUN_RECORD_PREFIX: &str = ".spraysim-run-";
/// The prefix of the empty file that shows a directory can be written in.
const PROBE_PREFIX: &str = ".spraysim-probe-";

/// A locked output directory. The lock is released when this is dropped (or the process ends).
#[derive(Debug)]
pub struct OutputDir {
    path: PathBuf,
    /// Holds the lock while open.
    _lock: File,
}

impl OutputDir {
    /// Creates `path` (and the folders above it) if needed, checks that files can be created in
    /// it, takes its lock and finishes what killed writers left there. Refused when `path` is
    /// not a folder, cannot be written or is locked by another writer; on a refusal, the folders
    /// this call created are removed again.
    pub fn lock(path: &Path) -> Result<OutputDir, OutputError> {
        let created = create_folders(path)?;
        let opened = (|| {
            let lock = lock::acquire(path)?;
            let (probe, probe_path) = paths::create_fresh(path, PROBE_PREFIX, "", paths::create_new)?;
            drop(probe);
            let _ = std::fs::remove_file(&probe_path);
            Ok(lock)
        })();
        let lock = match opened {
            Ok(lock) => lock,
            Err(e) => {
                remove_created(path, &created);
                return Err(e);
            }
        };
        commit::recover(path);
        remove_temporaries(path);
        Ok(OutputDir { path: path.to_path_buf(), _lock: lock })
    }

    /// The directory's path, as given to [`OutputDir::lock`].
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Writes `files` (relative name, contents; every name one of [`OUTPUT_NAMES`]) as one set
    /// replacing the previous one, the first file (the set's index) moved in last; returns the
    /// paths written. See the module's contract.
    pub fn write_set(&self, files: &[(String, Vec<u8>)]) -> Result<Vec<PathBuf>, OutputError> {
        self.write_set_with(files, &NoHooks)
    }

    /// [`OutputDir::write_set`], telling `hooks` when the set is staged and as each file moves
    /// in, and asking them before the first file moves (see [`CommitHooks`]).
    pub fn write_set_with(
        &self,
        files: &[(String, Vec<u8>)],
        hooks: &dyn CommitHooks,
    ) -> Result<Vec<PathBuf>, OutputError> {
        commit::write_set(&self.path, files, hooks)
    }

    /// Creates a new file for writing under a fresh random name `{prefix}{pid}-{random}{suffix}`
    /// in the directory, failing rather than opening anything that is there already.
    pub fn create_temporary(&self, prefix: &str, suffix: &str) -> Result<(File, PathBuf), OutputError> {
        paths::create_fresh(&self.path, prefix, suffix, paths::create_new)
    }

    /// Records that the directory holds the run of the resolved scenario `scenario` (TOML):
    /// a checkpoint of another run is then refused here (see [`OutputDir::recorded_run`]).
    pub fn record_run(&self, scenario: &str) -> Result<(), OutputError> {
        let (mut file, temp) = self.create_temporary(RUN_RECORD_PREFIX, ".tmp")?;
        let written = file.write_all(run_hash(scenario).as_bytes()).map_err(io_err(&temp));
        let target = self.path.join(RUN_RECORD);
        let result = written.and_then(|()| std::fs::rename(&temp, &target).map_err(io_err(&target)));
        if result.is_err() {
            let _ = std::fs::remove_file(&temp);
        }
        result
    }

    /// The recorded run's hash ([`run_hash`] of its scenario), if the directory has a record.
    pub fn recorded_run(&self) -> Option<String> {
        let bytes = paths::read_small(&self.path.join(RUN_RECORD), 1024)?;
        Some(String::from_utf8_lossy(&bytes).trim().to_string())
    }
}

/// Removes the temporary files that killed writers left in `dir` (probes, records and
/// checkpoints not yet renamed into place). Called by the lock's holder only, so none of them
/// is being written; a link under such a name is removed itself, never followed.
fn remove_temporaries(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    // Earlier versions named a temporary checkpoint `.checkpoint.spraysim.PID`.
    let old_checkpoint = format!(".{}.", crate::checkpoint::CHECKPOINT_FILE);
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        let temporary = [PROBE_PREFIX, RUN_RECORD_PREFIX, crate::checkpoint::TEMPORARY_PREFIX]
            .iter()
            .any(|p| name.starts_with(p))
            || name.strip_prefix(&old_checkpoint).is_some_and(|p| p.parse::<u32>().is_ok());
        if temporary && e.file_type().is_ok_and(|t| !t.is_dir()) {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

/// The identity of a run: the SHA-256 (hex) of its resolved scenario's TOML.
pub fn run_hash(scenario: &str) -> String {
    paths::hash_bytes(scenario.as_bytes())
}

/// The names of everything in `dir`, sorted, dot-files and the writer's bookkeeping (names
/// beginning with [`RESERVED_PREFIX`]) included: what a directory holds, to set beside the set
/// its `metrics.json` lists. A name that is not UTF-8 is given with U+FFFD for its bad bytes.
pub fn entries(dir: &Path) -> std::io::Result<Vec<String>> {
    let mut names = std::fs::read_dir(dir)?
        .map(|e| e.map(|e| e.file_name().to_string_lossy().into_owned()))
        .collect::<std::io::Result<Vec<String>>>()?;
    names.sort();
    Ok(names)
}

/// Creates `path` and the folders above it that are missing; returns those it created, the
/// outermost first. A part of the path that is a file is named in the error.
fn create_folders(path: &Path) -> Result<Vec<PathBuf>, OutputError> {
    let mut missing = Vec::new();
    let mut at = Some(path);
    while let Some(p) = at.filter(|p| !p.as_os_str().is_empty()) {
        match std::fs::metadata(p) {
            Ok(m) if m.is_dir() => break,
            Ok(_) => {
                return Err(paths::invalid(p, "is a file, not a folder: choose another output directory"));
            }
            Err(_) => missing.push(p.to_path_buf()),
        }
        at = p.parent();
    }
    missing.reverse();
    let mut created = Vec::new();
    for p in missing {
        match std::fs::create_dir(&p) {
            Ok(()) => created.push(p),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && p.is_dir() => {}
            Err(e) => {
                remove_created(path, &created);
                return Err(io_err(&p)(e));
            }
        }
    }
    Ok(created)
}

/// Removes the folders [`create_folders`] made (the innermost first), if they are still
/// empty but for the lock file this call made.
fn remove_created(path: &Path, created: &[PathBuf]) {
    if created.last().is_some_and(|p| p == path) {
        let _ = std::fs::remove_file(path.join(LOCK_FILE));
    }
    for p in created.iter().rev() {
        let _ = std::fs::remove_dir(p);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_a_directory_is_refused_naming_the_holder() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let first = OutputDir::lock(tmp.path()).expect("first");
        match OutputDir::lock(tmp.path()) {
            Err(OutputError::Busy { holder, .. }) => {
                assert!(holder.starts_with(&format!("process {}", std::process::id())), "{holder}");
            }
            other => panic!("a second writer got {other:?}"),
        }
        drop(first);
        OutputDir::lock(tmp.path()).expect("free again once the first is done");
    }

    #[test]
    fn a_directory_below_a_file_is_refused_naming_the_file_and_nothing_is_made() {
        let tmp = tempfile::tempdir().expect("tempdir");
        std::fs::write(tmp.path().join("file"), "").expect("write");
        let err = OutputDir::lock(&tmp.path().join("file/out/deeper")).expect_err("refused");
        assert!(err.to_string().contains("file: is a file, not a folder"), "{err}");
        let made = OutputDir::lock(&tmp.path().join("new/deeper")).expect("made");
        assert!(made.path().is_dir());
    }

    #[cfg(unix)]
    #[test]
    fn a_link_planted_as_the_lock_file_is_refused_and_its_target_untouched() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let (dir, victim) = (tmp.path().join("out"), tmp.path().join("keep.txt"));
        std::fs::create_dir(&dir).expect("mkdir");
        std::fs::write(&victim, "precious").expect("write");
        std::os::unix::fs::symlink(&victim, dir.join(LOCK_FILE)).expect("symlink");
        let err = OutputDir::lock(&dir).expect_err("refused");
        assert!(err.to_string().contains("symbolic link"), "{err}");
        assert_eq!(std::fs::read_to_string(&victim).expect("read"), "precious");
    }

    #[test]
    fn a_set_replaces_the_previous_one_and_removes_its_stale_files() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let dir = OutputDir::lock(tmp.path()).expect("lock");
        let set = |names: &[&str], tag: &str| -> Vec<(String, Vec<u8>)> {
            names.iter().map(|n| (n.to_string(), format!("{tag} {n}").into_bytes())).collect()
        };
        dir.write_set(&set(&["metrics.json", "a_hits.npy", "frames/frame_0001.png"], "first"))
            .expect("first");
        dir.write_set(&set(&["metrics.json", "b_hits.npy"], "second")).expect("second");
        let read = |n: &str| std::fs::read_to_string(tmp.path().join(n)).ok();
        assert_eq!(read("metrics.json").as_deref(), Some("second metrics.json"));
        assert_eq!(read("b_hits.npy").as_deref(), Some("second b_hits.npy"));
        assert_eq!(read("a_hits.npy"), None);
        assert!(!tmp.path().join("frames").exists(), "the emptied folder of a stale file goes too");
        let err =
            dir.write_set(&set(&["metrics.json", "notes.txt"], "third")).expect_err("not an output name");
        assert!(err.to_string().contains("not one of spraysim's output names"), "{err}");
        assert_eq!(
            read("metrics.json").as_deref(),
            Some("second metrics.json"),
            "a refused set changes nothing"
        );
    }
}
