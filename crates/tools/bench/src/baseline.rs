//! The paper-equivalent implementation, built and timed beside spraysim.
//!
//! `baseline/paper_baseline.cpp` is a plain single-threaded C++ implementation of the paper's
//! algorithm on the reference scene (forward Euler, every obstacle tested at every step, no
//! broad phase). Timing it in the same bench run as spraysim makes the "× paper baseline"
//! column a ratio of two figures taken on the same machine at the same moment: this machine's
//! speed drifts by up to a fifth within a session, and a ratio against a figure recorded on
//! another day carries that drift. Without a C++ compiler the bench divides by
//! [`PAPER_BASELINE_PARTICLES_PER_SECOND`](crate::PAPER_BASELINE_PARTICLES_PER_SECOND), the
//! figure recorded on the development machine, and says so.

use std::ffi::OsString;
use std::path::Path;
use std::process::Command;

/// The implementation's source, compiled at bench time.
pub const SOURCE: &str = include_str!("../baseline/paper_baseline.cpp");

/// Flags the implementation is built with (those of its recorded figure).
pub const FLAGS: [&str; 2] = ["-O3", "-march=native"];

/// Why the paper-equivalent implementation could not be timed.
#[derive(Debug, thiserror::Error)]
pub enum BaselineError {
    /// No C++ compiler could be started.
    #[error("no C++ compiler found (tried {tried}); set CXX to one")]
    NoCompiler {
        /// The commands tried, comma-separated.
        tried: String,
    },
    /// The compiler refused the source.
    #[error("`{compiler}` could not build the paper-equivalent implementation: {stderr}")]
    Build {
        /// The compiler command.
        compiler: String,
        /// The last line of what it printed.
        stderr: String,
    },
    /// The built program failed or printed something unexpected.
    #[error("the paper-equivalent implementation {0}")]
    Run(String),
    /// A file of the build could not be written or run.
    #[error("building the paper-equivalent implementation: {0}")]
    Io(#[from] std::io::Error),
}

/// What one run of the paper-equivalent implementation printed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaselineRun {
    /// Particles emitted.
    pub emitted: u64,
    /// Particles still in flight at the end.
    pub in_flight: u64,
    /// Particles stuck to the wall, the floor or the rebar, or lost (left the domain or
    /// expired).
    pub retired: u64,
    /// Time of the simulation loop, s (its own clock, without process start).
    pub seconds: f64,
}

impl BaselineRun {
    /// Parses the `key value` lines the program prints; an error names what is missing or
    /// inconsistent.
    pub fn parse(out: &str) -> Result<BaselineRun, BaselineError> {
        let value = |key: &str| -> Result<f64, BaselineError> {
            out.lines()
                .filter_map(|l| l.split_once(' '))
                .find(|(k, _)| *k == key)
                .and_then(|(_, v)| v.trim().parse::<f64>().ok())
                .filter(|v| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| BaselineError::Run(format!("printed no valid `{key}`")))
        };
        // Counts are printed as integers far below 2⁵³: exact as f64.
        let count = |key: &str| value(key).map(|v| v as u64);
        let emitted = count("emitted")?;
        let in_flight = count("in_flight")?;
        let retired = count("adhered_wall")? + count("adhered_floor")? + count("rebar")? + count("lost")?;
        if retired + in_flight != emitted {
            return Err(BaselineError::Run(format!(
                "accounted for {retired} retired + {in_flight} in flight of {emitted} emitted particles"
            )));
        }
        let seconds = value("seconds")?;
        if seconds <= 0.0 {
            return Err(BaselineError::Run("printed a run time of 0 s".into()));
        }
        Ok(BaselineRun { emitted, in_flight, retired, seconds })
    }

    /// Particles brought from emission to a final fate per second.
    pub fn particles_per_second(&self) -> f64 {
        self.retired as f64 / self.seconds
    }
}

/// A built paper-equivalent implementation, in a directory removed when this is dropped.
#[derive(Debug)]
pub struct Baseline {
    dir: tempfile::TempDir,
    /// The compiler command that built it.
    pub compiler: String,
}

impl Baseline {
    /// Builds the implementation with `$CXX` if set, else the first of `c++`, `g++` and
    /// `clang++` that starts.
    pub fn build() -> Result<Baseline, BaselineError> {
        let candidates: Vec<OsString> = match std::env::var_os("CXX") {
            Some(cxx) if !cxx.is_empty() => vec![cxx],
            _ => ["c++", "g++", "clang++"].map(OsString::from).to_vec(),
        };
        Baseline::build_with(&candidates)
    }

    /// Builds the implementation with the first of `compilers` that starts.
    pub fn build_with(compilers: &[OsString]) -> Result<Baseline, BaselineError> {
        let dir = tempfile::Builder::new().prefix("spraysim-baseline-").tempdir()?;
        let source = dir.path().join("paper_baseline.cpp");
        std::fs::write(&source, SOURCE)?;
        let program = program(dir.path());
        for compiler in compilers {
            let built = Command::new(compiler).args(FLAGS).arg("-o").arg(&program).arg(&source).output();
            let Ok(built) = built else { continue };
            let compiler = compiler.to_string_lossy().into_owned();
            if !built.status.success() {
                let stderr = String::from_utf8_lossy(&built.stderr);
                let stderr =
                    stderr.lines().rfind(|l| !l.trim().is_empty()).unwrap_or("no message").to_string();
                return Err(BaselineError::Build { compiler, stderr });
            }
            return Ok(Baseline { dir, compiler });
        }
        let tried = compilers.iter().map(|c| c.to_string_lossy()).collect::<Vec<_>>().join(", ");
        Err(BaselineError::NoCompiler { tried })
    }

    /// Runs the reference scene at `spawn_rate` particles/s for `duration` s (seed 1).
    pub fn run(&self, spawn_rate: f64, duration: f64) -> Result<BaselineRun, BaselineError> {
        // Rust prints floats exactly enough for C's `atof` to read back the same value.
        let args = [spawn_rate.to_string(), duration.to_string(), "1".into()];
        let out = Command::new(program(self.dir.path())).args(args).output()?;
        if !out.status.success() {
            return Err(BaselineError::Run(format!("exited with {}", out.status)));
        }
        BaselineRun::parse(&String::from_utf8_lossy(&out.stdout))
    }

    /// [`Baseline::run`] `repeats` times (at least once); the run of median time.
    pub fn run_median(
        &self,
        spawn_rate: f64,
        duration: f64,
        repeats: usize,
    ) -> Result<BaselineRun, BaselineError> {
        let mut runs =
            (0..repeats.max(1)).map(|_| self.run(spawn_rate, duration)).collect::<Result<Vec<_>, _>>()?;
        runs.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
        Ok(runs.swap_remove(runs.len() / 2))
    }
}

/// The built program's path in `dir`.
fn program(dir: &Path) -> std::path::PathBuf {
    dir.join("paper_baseline")
}

#[cfg(test)]
mod tests {
    use super::*;

    const PRINTED: &str = "steps 500\nparticle_steps 30159707\nemitted 500000\nadhered_wall 293007\n\
        adhered_floor 12\nrebar 122757\nlost 0\nin_flight 84224\nseconds 9.2749\npsteps_per_s 3.2518e+06\n";

    #[test]
    fn a_run_is_read_as_its_fates_over_its_time() {
        let r = BaselineRun::parse(PRINTED).expect("a complete printout");
        assert_eq!((r.emitted, r.in_flight, r.retired), (500_000, 84_224, 415_776));
        assert!((r.particles_per_second() - 415_776.0 / 9.2749).abs() < 1e-9);
    }

    #[test]
    fn a_printout_that_loses_particles_or_a_key_is_refused() {
        let lossy = PRINTED.replace("rebar 122757", "rebar 122756");
        let e = BaselineRun::parse(&lossy).expect_err("one particle unaccounted for");
        assert!(e.to_string().contains("of 500000 emitted"), "{e}");
        let missing = PRINTED.replace("seconds 9.2749\n", "");
        let e = BaselineRun::parse(&missing).expect_err("no run time");
        assert!(e.to_string().contains("`seconds`"), "{e}");
        let nan = PRINTED.replace("seconds 9.2749", "seconds nan");
        assert!(BaselineRun::parse(&nan).is_err());
    }

    #[test]
    fn without_a_compiler_the_error_names_what_was_tried() {
        let e = Baseline::build_with(&[OsString::from("no-such-compiler-xyz")]).expect_err("no compiler");
        assert!(matches!(e, BaselineError::NoCompiler { .. }), "{e}");
        assert!(e.to_string().contains("no-such-compiler-xyz"), "{e}");
    }

    /// Builds and runs the implementation where a C++ compiler is present: every emitted
    /// particle is accounted for, and at a low rate over a short time they have all been
    /// emitted (the rate is honoured) and most are still on their way to the wall 1 m away.
    #[test]
    fn the_built_implementation_accounts_for_every_particle() {
        let baseline = match Baseline::build() {
            Ok(b) => b,
            Err(BaselineError::NoCompiler { tried }) => {
                eprintln!("skipped: no C++ compiler ({tried})");
                return;
            }
            Err(e) => panic!("{e}"),
        };
        // 20 steps of 1 ms at 10⁴/s: 200 particles, all emitted, none at the wall yet (it is
        // 1 m away at 20–30 m/s: 33–50 ms).
        let r = baseline.run(1e4, 0.02).expect("a run");
        assert_eq!(r.emitted, 200);
        assert_eq!(r.in_flight, 200);
        // Over 0.2 s the first particles have reached the wall and rebar.
        let r = baseline.run(1e4, 0.2).expect("a run");
        assert_eq!(r.emitted, 2000);
        assert!(r.retired > 500 && r.in_flight > 0, "{r:?}");
    }
}
