//! `spraysim check`: validates a scenario without running it, and prints its size or the
//! scenario resolved.

use super::{load, strict_refusal, warn_size, write_out};
use crate::cli::CheckArgs;
use anyhow::Result;
use spraysim::scenario::sanity;

/// Validates a scenario and prints its size, or the scenario resolved.
pub fn check(args: &CheckArgs) -> Result<()> {
    let sc = load(Some(&args.scenario), &args.set)?;
    if args.resolved {
        let duration = sc.simulation().duration;
        let ends = match sc.spraying_ends() {
            Some(t) if t < duration => {
                format!("# Spraying ends at {t:.3} s, before the end of the run at {duration} s.\n")
            }
            Some(t) => {
                format!("# Spraying would end at {t:.3} s, after the end of the run at {duration} s.\n")
            }
            None => format!("# Spraying goes on until the end of the run at {duration} s.\n"),
        };
        return write_out(&format!("{ends}{}", sc.to_toml()));
    }
    let b = sc.budget();
    let counted = |n: usize, what: &str| if n == 1 { format!("1 {what}") } else { format!("{n} {what}s") };
    say!(
        "{}: valid ({}, {}): {} steps, {:.4e} particles sprayed ({:.3e} in flight at most), \
         about {} of memory (limit {})",
        args.scenario.display(),
        counted(sc.targets().len(), "target"),
        counted(sc.obstacles().len(), "obstacle"),
        b.steps,
        sanity::sprayed_particles(&sc),
        b.in_flight,
        spraysim::scenario::bytes_text(b.memory),
        spraysim::scenario::bytes_text(b.limit)
    );
    warn_size(&sc);
    let warnings = sanity::before_run(&sc);
    for w in &warnings {
        say!("warning: {w}");
    }
    match strict_refusal(&warnings).filter(|_| args.strict) {
        Some(e) => Err(e),
        None => Ok(()),
    }
}
