//! The paper-equivalent implementation, built and timed beside spraysim.
//!
//! `baseline/paper_baseline.cpp` is a plain single-threaded C++ implementation of the paper's
//! algorithm (an array of particle structs stepped every Δt = 1 ms, every obstacle tested at
//! every step, no broad phase). Its scene is the reference scene in outline, in its own frame
//! and with the paper's own parameters: a 2 m × 2 m wall with a 1024² heightfield 1 m from a
//! static nozzle, a floor, 13 + 13 rebars of 8 mm radius at 150 mm spacing 50 mm in front of
//! the wall; its spray cone (9° half angle), rebound law and restitution are its own, so its
//! particles rebound less than spraysim's shotcrete preset and reach their fates sooner (at
//! 10⁶ particles/s for 0.5 s it retires 83 % of them, spraysim 69 %).
//!
//! Timing it in the same bench run as spraysim makes the "× paper baseline" column a ratio of
//! two figures taken on the same machine at the same moment: this machine's speed drifts by up
//! to a fifth within a session, and a ratio against a figure recorded on another day carries
//! that drift. Where it cannot be built or run (no C++ compiler, say), the bench divides by
//! [`PAPER_BASELINE_PARTICLES_PER_SECOND`](crate::PAPER_BASELINE_PARTICLES_PER_SECOND), the
//! figure recorded on the development machine, and says why.

use std::path::Path;
use std::process::Command;

/// The implementation's source, compiled at bench time.
pub const SOURCE: &str = include_str!("../baseline/paper_baseline.cpp");

/// Flags the implementation is built with (those of its recorded figure); where the compiler
/// refuses them (`-march=native` on some targets), it is built with [`PORTABLE_FLAGS`].
pub const FLAGS: [&str; 2] = ["-O3", "-march=native"];

/// Flags of the second attempt at a build.
pub const PORTABLE_FLAGS: [&str; 1] = ["-O3"];

/// Why the paper-equivalent implementation could not be timed.
#[derive(Debug, thiserror::Error)]
pub enum BaselineError {
    /// No C++ compiler could be started.
    #[error("no C++ compiler found (tried {tried}); set CXX to one")]
    NoCompiler {
        /// The commands tried, comma-separated.
        tried: String,
    },
    /// The compiler could not be started or refused the source.
    #[error("`{compiler}` could not build the paper-equivalent implementation: {message}")]
    Build {
        /// The compiler command.
        compiler: String,
        /// Its first error line, or why it could not be started.
        message: String,
    },
    /// The built program could not be started, failed or printed something unexpected.
    #[error("the paper-equivalent implementation {0}")]
    Run(String),
    /// The source could not be written for the compiler.
    #[error("writing the paper-equivalent implementation's source: {0}")]
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
    /// inconsistent. A run that retired no particle is refused: it gives no rate to divide by.
    pub fn parse(out: &str) -> Result<BaselineRun, BaselineError> {
        let text = |key: &str| {
            out.lines().filter_map(|l| l.split_once(' ')).find(|(k, _)| *k == key).map(|(_, v)| v.trim())
        };
        let invalid = |key: &str| BaselineError::Run(format!("printed no valid `{key}`"));
        let count = |key: &str| text(key).and_then(|v| v.parse::<u64>().ok()).ok_or_else(|| invalid(key));
        let emitted = count("emitted")?;
        let in_flight = count("in_flight")?;
        let mut retired = 0u64;
        for key in ["adhered_wall", "adhered_floor", "rebar", "lost"] {
            retired = retired.checked_add(count(key)?).ok_or_else(|| invalid(key))?;
        }
        if retired.checked_add(in_flight) != Some(emitted) {
            return Err(BaselineError::Run(format!(
                "accounted for {retired} retired + {in_flight} in flight of {emitted} emitted particles"
            )));
        }
        if retired == 0 {
            return Err(BaselineError::Run(
                "brought no particle to its fate: run it longer (--duration) to time it".into(),
            ));
        }
        let seconds = text("seconds")
            .and_then(|v| v.parse::<f64>().ok())
            .filter(|v| v.is_finite() && *v > 0.0)
            .ok_or_else(|| invalid("seconds"))?;
        Ok(BaselineRun { emitted, in_flight, retired, seconds })
    }

    /// Particles brought from emission to a final fate per second.
    pub fn particles_per_second(&self) -> f64 {
        self.retired as f64 / self.seconds
    }

    /// The run of median time of `runs` (the later of the middle two of an even count); `None`
    /// for none.
    pub fn median(runs: Vec<BaselineRun>) -> Option<BaselineRun> {
        crate::median_by(runs, |r| r.seconds)
    }
}

/// A built paper-equivalent implementation, in a directory removed when this is dropped.
#[derive(Debug)]
pub struct Baseline {
    dir: tempfile::TempDir,
    /// The compiler command and flags that built it.
    pub build: String,
}

impl Baseline {
    /// Builds the implementation with `$CXX` if set (a command, possibly with arguments, as
    /// `ccache g++`), else the first of `c++`, `g++` and `clang++` found.
    pub fn build() -> Result<Baseline, BaselineError> {
        let candidates: Vec<String> = match std::env::var("CXX") {
            Ok(cxx) if !cxx.trim().is_empty() => vec![cxx],
            _ => ["c++", "g++", "clang++"].map(String::from).to_vec(),
        };
        Baseline::build_with(&candidates)
    }

    /// Builds the implementation with the first of `compilers` (each a command, its words
    /// split at white space) that is found; it fails if that one cannot build it.
    pub fn build_with(compilers: &[String]) -> Result<Baseline, BaselineError> {
        let dir = tempfile::Builder::new().prefix("spraysim-baseline-").tempdir()?;
        let source = dir.path().join("paper_baseline.cpp");
        std::fs::write(&source, SOURCE)?;
        let program = program(dir.path());
        for compiler in compilers {
            let mut words = compiler.split_whitespace();
            let Some(command) = words.next() else { continue };
            let prefix: Vec<&str> = words.collect();
            let mut message = String::new();
            for flags in [&FLAGS[..], &PORTABLE_FLAGS[..]] {
                let built = Command::new(command)
                    .args(&prefix)
                    .args(flags)
                    .arg("-o")
                    .arg(&program)
                    .arg(&source)
                    .output();
                let built = match built {
                    Ok(b) => b,
                    Err(e) if e.kind() == std::io::ErrorKind::NotFound => break,
                    Err(e) => {
                        return Err(BaselineError::Build {
                            compiler: compiler.clone(),
                            message: e.to_string(),
                        });
                    }
                };
                if built.status.success() {
                    return Ok(Baseline { dir, build: format!("{compiler} {}", flags.join(" ")) });
                }
                message = first_error(&String::from_utf8_lossy(&built.stderr));
            }
            if !message.is_empty() {
                return Err(BaselineError::Build { compiler: compiler.clone(), message });
            }
        }
        Err(BaselineError::NoCompiler { tried: compilers.join(", ") })
    }

    /// Runs the reference scene at `spawn_rate` particles/s for `duration` s (seed 1).
    pub fn run(&self, spawn_rate: f64, duration: f64) -> Result<BaselineRun, BaselineError> {
        // Rust prints floats exactly enough for C's `atof` to read back the same value.
        let args = [spawn_rate.to_string(), duration.to_string(), "1".into()];
        let out = Command::new(program(self.dir.path()))
            .args(args)
            .output()
            .map_err(|e| BaselineError::Run(format!("could not be started: {e}")))?;
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
        let runs =
            (0..repeats.max(1)).map(|_| self.run(spawn_rate, duration)).collect::<Result<Vec<_>, _>>()?;
        BaselineRun::median(runs).ok_or_else(|| BaselineError::Run("was not run".into()))
    }
}

/// The first line of a compiler's output that reports an error, else its first line.
fn first_error(stderr: &str) -> String {
    let lines = || stderr.lines().map(str::trim).filter(|l| !l.is_empty());
    lines().find(|l| l.contains("error")).or_else(|| lines().next()).unwrap_or("no message").to_string()
}

/// The built program's path in `dir`.
fn program(dir: &Path) -> std::path::PathBuf {
    dir.join("paper_baseline")
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
    fn a_run_that_retires_nothing_gives_no_rate() {
        let early =
            "emitted 200\nadhered_wall 0\nadhered_floor 0\nrebar 0\nlost 0\nin_flight 200\nseconds 0.01\n";
        let e = BaselineRun::parse(early).expect_err("nothing retired");
        assert!(e.to_string().contains("no particle"), "{e}");
    }

    #[test]
    fn the_median_run_is_the_middle_one_by_time() {
        let run = |seconds| BaselineRun { emitted: 2, in_flight: 1, retired: 1, seconds };
        let median =
            |times: &[f64]| BaselineRun::median(times.iter().map(|&t| run(t)).collect()).map(|r| r.seconds);
        assert_eq!(median(&[3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&[9.0, 1.0, 2.0, 3.0]), Some(3.0));
        assert_eq!(median(&[4.0]), Some(4.0));
        assert_eq!(median(&[]), None);
    }

    #[test]
    fn without_a_compiler_the_error_names_what_was_tried() {
        let e = Baseline::build_with(&["no-such-compiler-xyz".into(), " ".into()]).expect_err("no compiler");
        assert!(matches!(e, BaselineError::NoCompiler { .. }), "{e}");
        assert!(e.to_string().contains("no-such-compiler-xyz"), "{e}");
    }

    #[test]
    fn a_compiler_that_fails_is_reported_not_skipped() {
        // `false` starts and fails without a word, as a broken compiler would.
        let e = Baseline::build_with(&["false".into(), "c++".into()]).expect_err("a failing compiler");
        assert!(matches!(&e, BaselineError::Build { compiler, .. } if compiler == "false"), "{e}");
    }

    #[test]
    fn compiler_errors_are_quoted_by_their_error_line() {
        let clang = "paper_baseline.cpp:1:2: error: unknown target CPU 'native'\n1 error generated.\n";
        assert_eq!(first_error(clang), "paper_baseline.cpp:1:2: error: unknown target CPU 'native'");
        assert_eq!(first_error("\n  odd output\n"), "odd output");
        assert_eq!(first_error(""), "no message");
    }

    /// Builds and runs the implementation where a C++ compiler is present (also through a
    /// command with arguments, as `CXX=\"ccache g++\"` would be): every emitted particle is
    /// accounted for, the rate is honoured, and a run too short for any particle to reach the
    /// wall 1 m away (at 20–30 m/s: 33–50 ms) is refused rather than divided by.
    #[test]
    fn the_built_implementation_accounts_for_every_particle() {
        let baseline = match Baseline::build() {
            Ok(b) => b,
            Err(BaselineError::NoCompiler { tried }) => {
                skip(&format!("no C++ compiler ({tried})"));
                return;
            }
            Err(e) => panic!("{e}"),
        };
        let e = baseline.run(1e4, 0.02).expect_err("20 ms: nothing has arrived");
        assert!(e.to_string().contains("no particle"), "{e}");
        // Over 0.2 s at 10⁴/s: 2000 particles, the first ones at the wall and rebar.
        let r = baseline.run(1e4, 0.2).expect("a run");
        assert_eq!(r.emitted, 2000);
        assert!(r.retired > 500 && r.in_flight > 0, "{r:?}");
        let compiler = baseline.build.split_whitespace().next().unwrap_or_default();
        let wrapped = Baseline::build_with(&[format!("env {compiler}")]).expect("a build through `env`");
        assert_eq!(wrapped.run(1e4, 0.2).expect("a run").emitted, 2000);
    }
}
