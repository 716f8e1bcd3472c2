//! `spraysim check`: validates a scenario without running it, and prints its size or the
//! scenario resolved.

use super::{load, warn_size, write_out};
use crate::cli::CheckArgs;
use anyhow::Result;

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
    say!(
        "{}: valid ({} targets, {} obstacles): {} steps, {:.4e} particles ({:.3e} in flight at most), \
         about {} of memory (limit {})",
        args.scenario.display(),
        sc.targets().len(),
        sc.obstacles().len(),
        b.steps,
        b.particles,
        b.in_flight,
        spraysim::scenario::bytes_text(b.memory),
        spraysim::scenario::bytes_text(b.limit)
    );
    warn_size(&sc);
    Ok(())
}
