//! Reading the files a user names, bounded: only regular files, and never more bytes than the
//! kind of file may have.
//!
//! Every file spraysim reads on a user's word (a scenario, a tool path, a mesh, a checkpoint, a
//! measured profile) goes through [`read_input`]. It refuses what is not a regular file (a
//! directory, a FIFO, a device such as `/dev/zero`, a socket) before opening it, so that neither
//! a pipe nobody writes to nor an endless device can stall or exhaust the program, and it reads
//! at most the cap of the file's [`InputKind`] plus one byte, so that a file larger than its cap,
//! or one that grows while it is read, is refused rather than read whole.
//!
//! Each cap has a default and an environment variable that raises (or lowers) it, read once
//! per process: a whole number of bytes, optionally with a binary suffix (`KiB`, `MiB`, `GiB`,
//! `TiB`), e.g. `SPRAYSIM_MAX_MESH_BYTES=4GiB`.
//!
//! ```
//! use spraysim_scenario::{InputKind, read_input};
//!
//! let err = read_input(std::path::Path::new("/nonexistent.stl"), InputKind::Mesh).expect_err("missing");
//! assert!(err.to_string().starts_with("/nonexistent.stl: "));
//! assert_eq!(InputKind::Mesh.default_cap(), 2 << 30);
//! ```

use std::fs::{File, Metadata};
use std::io::Read;
use std::path::Path;
use std::sync::OnceLock;

/// Bytes in a mebibyte.
const MIB: u64 = 1 << 20;
/// Bytes in a gibibyte.
const GIB: u64 = 1 << 30;

/// What a file holds, which sets the most bytes it may have.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum InputKind {
    /// A scenario, TOML: 16 MiB by default. A hand-written scene is a few kB; the largest
    /// generated ones list waypoints, about 100 bytes each, so 16 MiB holds some 150 000 of
    /// them; longer paths belong in a tool-path CSV.
    Scenario,
    /// A robot tool path, CSV (`nozzle.path_csv`): 256 MiB by default, some 3 million poses
    /// of about 80 bytes, hours of a robot program sampled at 100 Hz and more.
    ToolPath,
    /// A triangle mesh, STL or OBJ: 2 GiB by default. A binary STL of the most triangles a
    /// mesh may have (10⁷) is 500 MB, an ASCII STL of as many about 2.5 GB, so the default
    /// takes any binary STL and the ASCII or OBJ meshes of up to about 8 million triangles.
    Mesh,
    /// A checkpoint of a run: 16 GiB by default, a run of some 100 million particles with its
    /// deposits; a checkpoint can only be as large as the run that wrote it, so raise it for a
    /// run that needed more memory.
    Checkpoint,
    /// A measured thickness profile, CSV, read by the calibration: 64 MiB by default, about a
    /// million points, far more than any scan of a sprayed panel is sampled at.
    Profile,
}

impl InputKind {
    /// Every kind, in the order of the documentation.
    pub const ALL: [InputKind; 5] = [
        InputKind::Scenario,
        InputKind::ToolPath,
        InputKind::Mesh,
        InputKind::Checkpoint,
        InputKind::Profile,
    ];

    /// The cap when its environment variable is not set, bytes.
    pub const fn default_cap(self) -> u64 {
        match self {
            InputKind::Scenario => 16 * MIB,
            InputKind::ToolPath => 256 * MIB,
            InputKind::Mesh => 2 * GIB,
            InputKind::Checkpoint => 16 * GIB,
            InputKind::Profile => 64 * MIB,
        }
    }

    /// The environment variable that sets the cap, e.g. `SPRAYSIM_MAX_MESH_BYTES`.
    pub const fn env_var(self) -> &'static str {
        match self {
            InputKind::Scenario => "SPRAYSIM_MAX_SCENARIO_BYTES",
            InputKind::ToolPath => "SPRAYSIM_MAX_TOOL_PATH_BYTES",
            InputKind::Mesh => "SPRAYSIM_MAX_MESH_BYTES",
            InputKind::Checkpoint => "SPRAYSIM_MAX_CHECKPOINT_BYTES",
            InputKind::Profile => "SPRAYSIM_MAX_PROFILE_BYTES",
        }
    }

    /// What the file is, for messages: `a scenario`, `a mesh`, ….
    pub const fn what(self) -> &'static str {
        match self {
            InputKind::Scenario => "a scenario",
            InputKind::ToolPath => "a tool path",
            InputKind::Mesh => "a mesh",
            InputKind::Checkpoint => "a checkpoint",
            InputKind::Profile => "a measured profile",
        }
    }

    /// The cap in force, bytes: the environment variable's value if it is set, else
    /// [`InputKind::default_cap`]. The variable is read once, the first time any cap is asked
    /// for; a value that is not a size is an error (naming the variable) on every read.
    pub fn cap(self) -> Result<u64, InputProblem> {
        static CAPS: OnceLock<[Result<u64, String>; 5]> = OnceLock::new();
        let caps = CAPS.get_or_init(|| {
            InputKind::ALL.map(|k| match std::env::var_os(k.env_var()) {
                None => Ok(k.default_cap()),
                Some(v) => v.to_str().and_then(parse_size).ok_or_else(|| v.to_string_lossy().into_owned()),
            })
        });
        // `ALL` lists the kinds in declaration order, so a kind's number is its place in it.
        caps[self as usize].clone().map_err(|value| InputProblem::BadCap { variable: self.env_var(), value })
    }
}

/// Why a file was not read: the file as given, and what is wrong.
#[derive(Debug, thiserror::Error)]
#[error("{path}: {problem}")]
pub struct InputError {
    /// The file, as given.
    pub path: String,
    /// What is wrong.
    pub problem: InputProblem,
}

/// What is wrong with a file that was not read.
#[derive(Debug, thiserror::Error)]
pub enum InputProblem {
    /// Not a regular file once symbolic links are followed.
    #[error("it is {what}, not a regular file; only regular files are read")]
    NotAFile {
        /// What it is instead: `a directory`, `a FIFO (named pipe)`, `a character device`, ….
        what: &'static str,
    },
    /// Larger than the cap of its kind.
    #[error(
        "the file is {}, more than the {} allowed for {}; set {variable} to raise the limit (bytes, or e.g. `4GiB`)",
        size_text(*.size, *.exact), size_text(*.cap, true), .kind.what()
    )]
    TooLarge {
        /// The kind of file.
        kind: InputKind,
        /// Its size, bytes: exact when `exact`, else the bytes read before it passed the cap.
        size: u64,
        /// Whether `size` is the file's size rather than a lower bound.
        exact: bool,
        /// The cap, bytes.
        cap: u64,
        /// The environment variable that sets the cap.
        variable: &'static str,
    },
    /// The environment variable that sets a cap holds something that is not a size.
    #[error(
        "{variable}={value:?} is not a size: give a whole number of bytes above 0, optionally with KiB, MiB, GiB or TiB"
    )]
    BadCap {
        /// The environment variable's name (`SPRAYSIM_MAX_…`).
        variable: &'static str,
        /// What it holds, as given.
        value: String,
    },
    /// The file could not be opened or read.
    #[error(transparent)]
    Io(#[from] std::io::Error),
}

impl InputProblem {
    /// The problem as an I/O error (its kind kept for an I/O error, `InvalidInput` otherwise).
    pub fn into_io_error(self) -> std::io::Error {
        match self {
            InputProblem::Io(e) => e,
            other => std::io::Error::new(std::io::ErrorKind::InvalidInput, other),
        }
    }
}

/// Reads the whole of `path`, a file of `kind` named by a user: refused if it is not a regular
/// file (after following symbolic links; checked before it is opened and again on the opened
/// file) or if it has more bytes than the kind's cap ([`InputKind::cap`]), checked before it is
/// read and while it is read.
pub fn read_input(path: &Path, kind: InputKind) -> Result<Vec<u8>, InputError> {
    let cap = kind.cap().map_err(|problem| InputError { path: path.display().to_string(), problem })?;
    read_capped(path, kind, cap)
}

/// [`read_input`] with the cap given, bytes.
pub(crate) fn read_capped(path: &Path, kind: InputKind, cap: u64) -> Result<Vec<u8>, InputError> {
    let fail = |problem: InputProblem| InputError { path: path.display().to_string(), problem };
    // Stat first: opening a FIFO blocks until someone writes to it, and a device may never end.
    let meta = std::fs::metadata(path).map_err(|e| fail(e.into()))?;
    regular(&meta).map_err(fail)?;
    let file = File::open(path).map_err(|e| fail(e.into()))?;
    // The path may have been replaced between the two calls: check what was opened.
    let meta = file.metadata().map_err(|e| fail(e.into()))?;
    regular(&meta).map_err(fail)?;
    let too_large = |size: u64, exact: bool| {
        fail(InputProblem::TooLarge { kind, size, exact, cap, variable: kind.env_var() })
    };
    if meta.len() > cap {
        return Err(too_large(meta.len(), true));
    }
    // The size is a hint: the file may grow while it is read, so the read itself is bounded.
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(cap.saturating_add(1)).read_to_end(&mut bytes).map_err(|e| fail(e.into()))?;
    if bytes.len() as u64 > cap {
        return Err(too_large(bytes.len() as u64, false));
    }
    Ok(bytes)
}

/// Refuses anything but a regular file, saying what it is.
fn regular(meta: &Metadata) -> Result<(), InputProblem> {
    let t = meta.file_type();
    if t.is_file() {
        return Ok(());
    }
    let what = if t.is_dir() { "a directory" } else { special(&t) };
    Err(InputProblem::NotAFile { what })
}

#[cfg(unix)]
fn special(t: &std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if t.is_fifo() {
        "a FIFO (named pipe)"
    } else if t.is_char_device() {
        "a character device"
    } else if t.is_block_device() {
        "a block device"
    } else if t.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn special(_: &std::fs::FileType) -> &'static str {
    "a special file"
}

/// A size in bytes: a whole number above 0, optionally followed by `KiB`, `MiB`, `GiB` or
/// `TiB` (spaces allowed between).
fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let digits = text.find(|c: char| !c.is_ascii_digit()).unwrap_or(text.len());
    let (number, unit) = text.split_at(digits);
    let scale: u64 = match unit.trim() {
        "" | "B" => 1,
        "KiB" => 1 << 10,
        "MiB" => MIB,
        "GiB" => GIB,
        "TiB" => 1 << 40,
        _ => return None,
    };
    number.parse::<u64>().ok().and_then(|n| n.checked_mul(scale)).filter(|&n| n > 0)
}

/// `bytes` in the largest binary unit that keeps it at or above 1 (`16 MiB`, `1.5 GiB`), with
/// the exact count; `at least` in front when `exact` is false.
fn size_text(bytes: u64, exact: bool) -> String {
    let units = [(1u64 << 40, "TiB"), (GIB, "GiB"), (MIB, "MiB"), (1 << 10, "KiB")];
    let short = match units.iter().find(|(u, _)| bytes >= *u) {
        Some((u, name)) if bytes.is_multiple_of(*u) => format!("{} {name}", bytes / u),
        Some((u, name)) => format!("{:.1} {name}", bytes as f64 / *u as f64),
        None => format!("{bytes} bytes"),
    };
    let exact_text = if bytes >= 1 << 10 { format!("{short} ({bytes} bytes)") } else { short };
    if exact { exact_text } else { format!("at least {exact_text}") }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_finds_its_own_cap() {
        for (i, kind) in InputKind::ALL.into_iter().enumerate() {
            assert_eq!(kind as usize, i, "{kind:?}");
        }
    }

    #[test]
    fn sizes_take_bytes_or_a_binary_unit_and_refuse_anything_else() {
        assert_eq!(parse_size("1000"), Some(1000));
        assert_eq!(parse_size(" 4GiB "), Some(4 << 30));
        assert_eq!(parse_size("16 MiB"), Some(16 << 20));
        for bad in ["", "0", "-1", "1.5GiB", "4GB", "lots", "99999999999999999999", "20000000TiB"] {
            assert_eq!(parse_size(bad), None, "{bad}");
        }
    }

    #[test]
    fn a_file_over_the_cap_is_refused_naming_the_size_the_cap_and_the_variable() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("scene.toml");
        std::fs::write(&path, vec![b'#'; 3000]).expect("written");
        let err = read_capped(&path, InputKind::Scenario, 2048).expect_err("over the cap");
        let text = err.to_string();
        assert!(matches!(err.problem, InputProblem::TooLarge { size: 3000, exact: true, cap: 2048, .. }));
        for part in [
            path.display().to_string(),
            "3000 bytes".into(),
            "2 KiB".into(),
            "SPRAYSIM_MAX_SCENARIO_BYTES".into(),
        ] {
            assert!(text.contains(&part), "{part} not in {text}");
        }
        // At the cap exactly, it is read.
        assert_eq!(read_capped(&path, InputKind::Scenario, 3000).expect("at the cap").len(), 3000);
    }

    #[test]
    fn a_device_that_never_ends_is_refused_before_it_is_read() {
        let path = Path::new("/dev/zero");
        if !path.exists() {
            return;
        }
        let err = read_capped(path, InputKind::Mesh, 16).expect_err("a device");
        assert!(matches!(err.problem, InputProblem::NotAFile { what: "a character device" }), "{err}");
    }
}
