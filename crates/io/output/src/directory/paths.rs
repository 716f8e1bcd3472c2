//! Paths inside an output directory, looked up and created without following symbolic links
//! below the directory itself, and files created exclusively.
//!
//! The directory a user names may itself be a link (an `out` pointing at a larger disk): that
//! is the user's choice. Below it, every folder on the way to a file must be a real folder and
//! a file spraysim reads, replaces or removes must be a regular file; a link planted there (in
//! an unpacked archive, say) is never followed.

use crate::{OutputError, io_err};
use std::fs::{File, OpenOptions};
use std::io::{ErrorKind, Read};
use std::path::{Component, Path, PathBuf};

/// The prefix of every name the writer keeps for itself (its list, lock, staging folders).
pub const RESERVED_PREFIX: &str = ".spraysim-";

/// What is at a name inside a directory.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Found {
    /// Nothing (a folder on the way may be missing too).
    Missing,
    /// A regular file of this many bytes.
    File(u64),
    /// A symbolic link, not followed.
    Link,
    /// A real folder (not a link to one).
    Folder,
    /// A FIFO, a device or a socket.
    Special,
    /// A part of the way that is not a real folder (a link, a file), which is not followed.
    Blocked(PathBuf),
}

/// Refuses a name that is not a plain relative path of plain components (no root, `.`, `..`),
/// or that starts with the writer's [`RESERVED_PREFIX`].
pub(crate) fn check_name(name: &str) -> Result<(), OutputError> {
    let path = Path::new(name);
    let plain = path.components().all(|c| matches!(c, Component::Normal(_)));
    if name.is_empty() || !plain || name.starts_with(RESERVED_PREFIX) {
        return Err(invalid(name, "not a file name inside the directory"));
    }
    Ok(())
}

/// An error about `path` with `message`.
pub(crate) fn invalid(path: impl Into<PathBuf>, message: &str) -> OutputError {
    OutputError::Io { path: path.into(), source: std::io::Error::new(ErrorKind::InvalidInput, message) }
}

/// What is at `dir/name` (`name` checked by [`check_name`]), found without following a link at
/// any component below `dir`.
pub(crate) fn lookup(dir: &Path, name: &str) -> std::io::Result<Found> {
    let mut at = dir.to_path_buf();
    let parts: Vec<_> = Path::new(name).components().collect();
    for (k, part) in parts.iter().enumerate() {
        at.push(part);
        let meta = match std::fs::symlink_metadata(&at) {
            Ok(m) => m,
            Err(e) if e.kind() == ErrorKind::NotFound => return Ok(Found::Missing),
            Err(e) => return Err(e),
        };
        let kind = meta.file_type();
        let last = k + 1 == parts.len();
        if !last {
            if !kind.is_dir() {
                return Ok(Found::Blocked(at));
            }
            continue;
        }
        return Ok(if kind.is_symlink() {
            Found::Link
        } else if kind.is_file() {
            Found::File(meta.len())
        } else if kind.is_dir() {
            Found::Folder
        } else {
            Found::Special
        });
    }
    Ok(Found::Folder)
}

/// Creates the folders on the way to `dir/name`, one at a time, refusing a part of the way
/// that is a link or not a folder.
pub(crate) fn make_parents(dir: &Path, name: &str) -> Result<(), OutputError> {
    let Some(parent) = Path::new(name).parent() else { return Ok(()) };
    let mut at = dir.to_path_buf();
    for part in parent.components() {
        at.push(part);
        match std::fs::symlink_metadata(&at) {
            Ok(m) if m.file_type().is_dir() => {}
            Ok(_) => return Err(in_the_way(&at)),
            Err(e) if e.kind() == ErrorKind::NotFound => match std::fs::create_dir(&at) {
                Ok(()) => {}
                // Made meanwhile: fine if it is a real folder.
                Err(e) if e.kind() == ErrorKind::AlreadyExists => {
                    if !std::fs::symlink_metadata(&at).is_ok_and(|m| m.file_type().is_dir()) {
                        return Err(in_the_way(&at));
                    }
                }
                Err(e) => return Err(io_err(&at)(e)),
            },
            Err(e) => return Err(io_err(&at)(e)),
        }
    }
    Ok(())
}

/// The error for something that stands where the writer needs a folder or a file of its own.
pub(crate) fn in_the_way(at: &Path) -> OutputError {
    let what = match std::fs::symlink_metadata(at) {
        Ok(m) if m.file_type().is_symlink() => "a symbolic link, which spraysim does not follow",
        Ok(m) if m.file_type().is_dir() => "a folder, where an output file goes",
        Ok(m) if m.file_type().is_file() => "a file, where spraysim needs a folder",
        _ => "something spraysim cannot replace",
    };
    invalid(at, &format!("is {what}: move it away and run again"))
}

/// Options that open without following a final link and without blocking on a FIFO.
fn no_follow(options: &mut OpenOptions) -> &mut OpenOptions {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC);
    }
    options
}

/// Creates `path` for writing, failing if anything (a file, a link, a folder) is there already.
pub(crate) fn create_new(path: &Path) -> std::io::Result<File> {
    no_follow(OpenOptions::new().write(true).create_new(true)).open(path)
}

/// Opens `path` for reading if it is a regular file (a final link is refused, a FIFO does not
/// block), with its length.
fn open_regular(path: &Path) -> std::io::Result<(File, u64)> {
    let file = no_follow(OpenOptions::new().read(true)).open(path)?;
    let meta = file.metadata()?;
    if !meta.is_file() {
        return Err(std::io::Error::new(ErrorKind::InvalidInput, "not a regular file"));
    }
    Ok((file, meta.len()))
}

/// The SHA-256 of the regular file at `path` (a link is refused), with its length.
pub(crate) fn hash_file(path: &Path) -> std::io::Result<(u64, String)> {
    use sha2::{Digest, Sha256};
    let (mut file, len) = open_regular(path)?;
    let mut hasher = Sha256::new();
    let mut buffer = vec![0u8; 1 << 16];
    loop {
        let n = file.read(&mut buffer)?;
        if n == 0 {
            break;
        }
        hasher.update(&buffer[..n]);
    }
    Ok((len, hex(&hasher.finalize())))
}

/// The SHA-256 of `bytes`, as lower-case hex.
pub(crate) fn hash_bytes(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    hex(&Sha256::digest(bytes))
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Reads the regular file at `path` (a link is refused, a FIFO does not block) if it holds at
/// most `cap` bytes; None when it is missing, special, a link or larger.
pub(crate) fn read_small(path: &Path, cap: u64) -> Option<Vec<u8>> {
    let (file, len) = open_regular(path).ok()?;
    if len > cap {
        return None;
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(cap + 1).read_to_end(&mut bytes).ok()?;
    (bytes.len() as u64 <= cap).then_some(bytes)
}

/// A fresh name `{prefix}{pid}-{16 random hex digits}{suffix}`: with exclusive creation, a name
/// planted in advance only costs another draw.
pub(crate) fn temporary_name(prefix: &str, suffix: &str) -> String {
    format!("{prefix}{}-{:016x}{suffix}", std::process::id(), rand::random::<u64>())
}

/// Tries [`temporary_name`]s in `dir` until `create` makes one (it must fail with
/// `AlreadyExists` when the name is taken); returns what it made and its path.
pub(crate) fn create_fresh<T>(
    dir: &Path,
    prefix: &str,
    suffix: &str,
    mut create: impl FnMut(&Path) -> std::io::Result<T>,
) -> Result<(T, PathBuf), OutputError> {
    let mut last = None;
    for _ in 0..16 {
        let path = dir.join(temporary_name(prefix, suffix));
        match create(&path) {
            Ok(made) => return Ok((made, path)),
            Err(e) if e.kind() == ErrorKind::AlreadyExists => last = Some((path, e)),
            Err(e) => return Err(io_err(&path)(e)),
        }
    }
    let (path, e) = last.unwrap_or_else(|| (dir.to_path_buf(), ErrorKind::AlreadyExists.into()));
    Err(io_err(&path)(e))
}

#[cfg(test)]
mod tests {

    /// Says in the test output that a test cannot run here, and why. Written straight to the
    /// standard error, which the test harness does not capture (it captures `eprintln!`), so that
    /// the note shows without `--nocapture`.
    fn skip(reason: &str) {
        use std::io::Write;
        let _ = writeln!(std::io::stderr(), "skipped: {reason}");
    }
    use super::*;

    #[test]
    fn names_outside_the_directory_or_reserved_are_refused() {
        for bad in ["", "/etc/passwd", "../x", "a/../b", "./a", ".spraysim-files", ".spraysim-lock"] {
            assert!(check_name(bad).is_err(), "{bad:?}");
        }
        for good in ["metrics.json", "frames/frame_0001.png", ".hidden"] {
            assert!(check_name(good).is_ok(), "{good:?}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn lookup_does_not_follow_links_on_the_way_or_at_the_end() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let (dir, outside) = (tmp.path().join("out"), tmp.path().join("outside"));
        std::fs::create_dir_all(&dir).expect("mkdir");
        std::fs::create_dir_all(&outside).expect("mkdir");
        std::fs::write(outside.join("keep.txt"), b"precious").expect("write");
        std::os::unix::fs::symlink(&outside, dir.join("link")).expect("symlink");
        std::os::unix::fs::symlink(outside.join("keep.txt"), dir.join("file.png")).expect("symlink");
        assert_eq!(lookup(&dir, "link/keep.txt").expect("lookup"), Found::Blocked(dir.join("link")));
        assert_eq!(lookup(&dir, "file.png").expect("lookup"), Found::Link);
        assert_eq!(lookup(&dir, "none/x.png").expect("lookup"), Found::Missing);
        assert!(make_parents(&dir, "link/x.png").is_err(), "a link on the way is refused");
        assert!(hash_file(&dir.join("file.png")).is_err(), "a final link is not read");
        assert!(create_new(&dir.join("file.png")).is_err(), "nor written through");
        assert_eq!(std::fs::read(outside.join("keep.txt")).expect("read"), b"precious");
    }

    #[cfg(unix)]
    #[test]
    fn a_name_planted_in_advance_only_costs_another_draw() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let victim = tmp.path().join("keep.txt");
        std::fs::write(&victim, "precious").expect("write");
        let mut planted = 0;
        // Each of the first two names drawn has a link to the victim planted at it just before
        // the writer creates it.
        let (mut file, path) = create_fresh(tmp.path(), ".spraysim-test-", ".tmp", |p| {
            if planted < 2 {
                std::os::unix::fs::symlink(&victim, p).expect("plant");
                planted += 1;
            }
            create_new(p)
        })
        .expect("a third name");
        std::io::Write::write_all(&mut file, b"mine").expect("write");
        assert_eq!(std::fs::read_to_string(&path).expect("read"), "mine");
        assert_eq!(std::fs::read_to_string(&victim).expect("read"), "precious");
        assert!(std::fs::symlink_metadata(&path).expect("meta").is_file());
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_neither_read_nor_waited_on() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let fifo = tmp.path().join("list");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            skip("mkfifo is not available");
            return;
        }
        assert_eq!(read_small(&fifo, 1024), None);
        assert_eq!(lookup(tmp.path(), "list").expect("lookup"), Found::Special);
    }
}
