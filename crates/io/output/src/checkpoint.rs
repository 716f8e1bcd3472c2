//! Checkpoint files: a run's whole state, to resume it after a stop or a crash.
//!
//! Layout (little-endian): the 16-byte magic `SPRAYSIM-CKPT\0\0\0`, the format version (u32),
//! the steps between checkpoints (u64), the resolved scenario (u64 length, UTF-8 TOML), the
//! engine's state ([`spraysim_engine::checkpoint`]; u64 length, bytes), and the SHA-256 of
//! everything before it. A checkpoint is written to a temporary file, flushed to disk and
//! renamed over the previous one, so the file is always a whole checkpoint. The checksum finds
//! damage, not tampering: what the state holds is checked again when it is restored
//! ([`spraysim_engine::Simulation::restore_state`]), and a checkpoint must belong to the run its
//! directory records ([`check_belongs`]).

use crate::directory::{OutputDir, RUN_RECORD, run_hash};
use crate::{OutputError, io_err};
use sha2::{Digest, Sha256};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of the checkpoint file in a run's output directory.
pub const CHECKPOINT_FILE: &str = "checkpoint.spraysim";
/// Version of the file layout.
pub const CHECKPOINT_VERSION: u32 = 1;
const MAGIC: &[u8; 16] = b"SPRAYSIM-CKPT\0\0\0";

/// What a checkpoint holds.
#[derive(Clone, Debug, PartialEq)]
pub struct Checkpoint {
    /// The resolved scenario being run, TOML.
    pub scenario: String,
    /// Steps between checkpoints (0: none but this one).
    pub every_steps: u64,
    /// The engine's state ([`spraysim_engine::Simulation::save_state`]).
    pub state: Vec<u8>,
}

fn invalid(path: &Path, message: &str) -> OutputError {
    let source = std::io::Error::new(std::io::ErrorKind::InvalidData, message.to_string());
    OutputError::Io { path: path.to_path_buf(), source }
}

impl Checkpoint {
    /// The checkpoint as file contents.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.state.len() + self.scenario.len() + 80);
        out.extend_from_slice(MAGIC);
        out.extend_from_slice(&CHECKPOINT_VERSION.to_le_bytes());
        out.extend_from_slice(&self.every_steps.to_le_bytes());
        out.extend_from_slice(&(self.scenario.len() as u64).to_le_bytes());
        out.extend_from_slice(self.scenario.as_bytes());
        out.extend_from_slice(&(self.state.len() as u64).to_le_bytes());
        out.extend_from_slice(&self.state);
        let hash = Sha256::digest(&out);
        out.extend_from_slice(&hash);
        out
    }

    /// Reads file contents written by [`Checkpoint::to_bytes`]; `path` names it in errors.
    pub fn from_bytes(bytes: &[u8], path: &Path) -> Result<Checkpoint, OutputError> {
        let bad = |m: &str| invalid(path, m);
        let (body, hash) =
            bytes.split_at_checked(bytes.len().saturating_sub(32)).ok_or_else(|| bad("empty"))?;
        if bytes.len() < MAGIC.len() + 32 || !body.starts_with(MAGIC) {
            return Err(bad("not a spraysim checkpoint"));
        }
        if Sha256::digest(body).as_slice() != hash {
            return Err(bad("the checkpoint is damaged (its checksum does not match)"));
        }
        let mut r = Fields { rest: &body[MAGIC.len()..], path };
        let version = u32::from_le_bytes(r.array()?);
        if version != CHECKPOINT_VERSION {
            return Err(bad(&format!(
                "checkpoint version {version}; this program reads {CHECKPOINT_VERSION}"
            )));
        }
        let every_steps = u64::from_le_bytes(r.array()?);
        let n = r.len()?;
        let scenario =
            String::from_utf8(r.take(n)?.to_vec()).map_err(|_| bad("the scenario is not UTF-8"))?;
        let n = r.len()?;
        let state = r.take(n)?.to_vec();
        Ok(Checkpoint { scenario, every_steps, state })
    }
}

/// The fields of a checkpoint being read.
struct Fields<'a> {
    rest: &'a [u8],
    path: &'a Path,
}

impl<'a> Fields<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], OutputError> {
        let (head, tail) =
            self.rest.split_at_checked(n).ok_or_else(|| invalid(self.path, "the checkpoint is truncated"))?;
        self.rest = tail;
        Ok(head)
    }
    fn array<const N: usize>(&mut self) -> Result<[u8; N], OutputError> {
        let bytes = self.take(N)?;
        bytes.try_into().map_err(|_| invalid(self.path, "the checkpoint is truncated"))
    }
    fn len(&mut self) -> Result<usize, OutputError> {
        usize::try_from(u64::from_le_bytes(self.array()?))
            .map_err(|_| invalid(self.path, "a length is too large"))
    }
}

/// The prefix of a checkpoint being written, before it is renamed into place.
pub(crate) const TEMPORARY_PREFIX: &str = ".spraysim-checkpoint-";

/// Writes `checkpoint` into `dir` atomically: into a temporary file created exclusively under
/// a random name, flushed to disk, then renamed over the previous checkpoint. Returns its path.
pub fn write_checkpoint(dir: &OutputDir, checkpoint: &Checkpoint) -> Result<PathBuf, OutputError> {
    let path = dir.path().join(CHECKPOINT_FILE);
    let (mut file, temp) = dir.create_temporary(TEMPORARY_PREFIX, ".tmp")?;
    let written = file.write_all(&checkpoint.to_bytes()).and_then(|()| file.sync_all());
    let result =
        written.map_err(io_err(&temp)).and_then(|()| std::fs::rename(&temp, &path).map_err(io_err(&path)));
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    result.map(|()| path)
}

/// Reads the checkpoint in `dir`: a regular file within the checkpoint size limit
/// ([`spraysim_scenario::read_input`]), whole and of this version.
pub fn read_checkpoint(dir: &Path) -> Result<Checkpoint, OutputError> {
    let path = dir.join(CHECKPOINT_FILE);
    let bytes = spraysim_scenario::read_input(&path, spraysim_scenario::InputKind::Checkpoint)
        .map_err(|e| OutputError::Io { path: path.clone(), source: e.problem.into_io_error() })?;
    Checkpoint::from_bytes(&bytes, &path)
}

/// Checks that `checkpoint`, read from `dir`, belongs to the run the directory records (see
/// [`OutputDir::record_run`]): a checkpoint copied in from another run's directory is refused,
/// naming both. Returns a warning when the directory has no record to compare with.
pub fn check_belongs(dir: &OutputDir, checkpoint: &Checkpoint) -> Result<Option<String>, OutputError> {
    let path = dir.path().join(CHECKPOINT_FILE);
    match dir.recorded_run() {
        Some(recorded) if recorded == run_hash(&checkpoint.scenario) => Ok(None),
        Some(_) => Err(invalid(
            &path,
            &format!(
                "belongs to another run than the one this directory holds (its scenario differs from the \
                 one recorded in {RUN_RECORD}): resume it in the directory it was written in, or start \
                 this run afresh with `spraysim run`"
            ),
        )),
        None => Ok(Some(format!(
            "{} has no record of the run it holds ({RUN_RECORD}): resuming the checkpoint's own scenario",
            dir.path().display()
        ))),
    }
}

/// Removes the checkpoint in `dir` (a run that completed needs none).
pub fn remove_checkpoint(dir: &OutputDir) {
    let _ = std::fs::remove_file(dir.path().join(CHECKPOINT_FILE));
}
