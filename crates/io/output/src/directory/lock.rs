//! The exclusive lock on an output directory: one writer at a time.
//!
//! A writer holds an advisory lock (`flock`) on the file [`LOCK_FILE`] inside the directory for
//! as long as it may write there: a whole run with its checkpoints, a resume, one set written
//! from Python. The lock goes with the process: a killed writer holds nothing, so whatever it
//! left (a staging folder, a temporary checkpoint) belongs to no live writer once the lock is
//! taken. The file stays in the directory (removing it would let two writers lock two
//! different files); it names the holder, for the message a second writer gets.

use crate::{OutputError, io_err};
use std::fs::{File, OpenOptions, TryLockError};
use std::io::{Read, Seek, Write};
use std::path::Path;

/// The lock file inside an output directory.
pub const LOCK_FILE: &str = ".spraysim-lock";

/// Most bytes of the holder's description read back for a message.
const HOLDER_CAP: u64 = 4096;

/// Takes the lock on `dir` (which exists), or says who holds it.
pub(crate) fn acquire(dir: &Path) -> Result<File, OutputError> {
    let path = dir.join(LOCK_FILE);
    let mut options = OpenOptions::new();
    options.read(true).write(true).create(true).truncate(false);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK | libc::O_CLOEXEC);
    }
    let mut file = options.open(&path).map_err(|e| match std::fs::symlink_metadata(&path) {
        Ok(m) if !m.file_type().is_file() => super::paths::in_the_way(&path),
        _ => io_err(&path)(e),
    })?;
    if !file.metadata().map_err(io_err(&path))?.is_file() {
        return Err(super::paths::in_the_way(&path));
    }
    match file.try_lock() {
        Ok(()) => {}
        Err(TryLockError::WouldBlock) => {
            return Err(OutputError::Busy { path: dir.to_path_buf(), holder: holder(&mut file) });
        }
        Err(TryLockError::Error(e)) => return Err(io_err(&path)(e)),
    }
    let mut describe = || -> std::io::Result<()> {
        file.set_len(0)?;
        file.rewind()?;
        let since =
            std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_secs());
        let command: Vec<String> = std::env::args().collect();
        write!(file, "{}\n{since}\n{}\n", std::process::id(), command.join(" "))
    };
    describe().map_err(io_err(&path))?;
    Ok(file)
}

/// Who holds the lock, from what the holder wrote into the file: its process id, how long it
/// has held it and its command line.
fn holder(file: &mut File) -> String {
    let mut text = String::new();
    let _ = file.rewind();
    let _ = file.take(HOLDER_CAP).read_to_string(&mut text);
    let mut lines = text.lines();
    let (Some(pid), Some(since)) = (lines.next(), lines.next().and_then(|s| s.parse::<u64>().ok())) else {
        return "another process".into();
    };
    let now =
        std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(since, |d| d.as_secs());
    let command: String = lines.next().unwrap_or("").chars().filter(|c| !c.is_control()).take(200).collect();
    format!("process {pid} (`{command}`), for {} s", now.saturating_sub(since))
}
