//! The subcommands, one file each, and what several of them share: reading a scenario with its
//! overrides, locking an output directory, and the warning before a very long run.

pub mod bench;
pub mod calibrate;
pub mod check;
pub mod render;
pub mod run;
pub mod validate;

use anyhow::{Context, Result};
use spraysim::Scenario;
use spraysim::output::OutputDir;
use spraysim::scenario::sanity::Warning;
use std::io::Write;
use std::path::Path;

/// `spraysim presets`: prints each process preset as TOML.
pub fn presets() -> Result<()> {
    write_out(&spraysim::scenario::presets_toml())
}

/// Writes `text` to stdout as it is.
pub fn write_out(text: &str) -> Result<()> {
    std::io::stdout().lock().write_all(text.as_bytes())?;
    Ok(())
}

/// The scenario at `path` (the default scene without one), with the `--set` overrides applied
/// together and checked once (their order does not matter); its warnings go to stderr.
pub fn load(path: Option<&Path>, set: &[String]) -> Result<Scenario> {
    let sc = match path {
        Some(p) => Scenario::from_path(p)?,
        None => Scenario::default_scene(),
    };
    let sc = if set.is_empty() { sc } else { sc.with_assignments(set)? };
    for w in sc.warnings() {
        eprintln!("warning: {w}");
    }
    Ok(sc)
}

/// Creates (if needed) and locks the output directory `dir`, refusing one that cannot be
/// written or that another writer holds.
pub fn lock(dir: &Path) -> Result<OutputDir> {
    OutputDir::lock(dir).with_context(|| format!("output directory {}", dir.display()))
}

/// The error `--strict` makes of `warnings` (`None` when there are none).
pub fn strict_refusal(warnings: &[Warning]) -> Option<anyhow::Error> {
    if warnings.is_empty() {
        return None;
    }
    let listed: Vec<String> = warnings.iter().map(|w| format!("{} (change `{}`)", w.code, w.key)).collect();
    let count =
        if warnings.len() == 1 { "1 warning".to_string() } else { format!("{} warnings", warnings.len()) };
    Some(anyhow::anyhow!("--strict: {count}: {}", listed.join(", ")))
}

/// Prints `warnings` to stderr, one a line.
pub fn print_warnings(warnings: &[Warning]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Steps beyond which a run is worth a word before it starts.
const LONG_STEPS: u64 = 10_000_000;
/// Particles emitted beyond which a run is worth a word before it starts.
const MANY_PARTICLES: f64 = 1e9;

/// Warns of a run whose step or particle count is far beyond the usual.
pub fn warn_size(sc: &Scenario) {
    let b = sc.budget();
    if b.steps > LONG_STEPS || b.particles > MANY_PARTICLES {
        eprintln!(
            "warning: this run takes {} steps (simulation.duration / simulation.dt) and emits {:.3e} particles \
             (emitter.spawn_rate × simulation.duration): it may take a very long time",
            b.steps, b.particles
        );
    }
}
