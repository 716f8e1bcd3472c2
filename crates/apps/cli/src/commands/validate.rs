//! `spraysim validate`: runs every check against a closed form and writes the report.

use super::lock;
use crate::cli::ValidateArgs;
use crate::control::RunControl;
use anyhow::{Context, Result};
use std::time::Instant;

/// Runs the closed-form checks and writes their report; fails if any check fails.
pub fn validate(args: &ValidateArgs) -> Result<()> {
    let (output, size, threads) = (&args.output, args.size, args.threads);
    if !(size.is_finite() && (0.01..=1000.0).contains(&size)) {
        anyhow::bail!("--size must be between 0.01 and 1000, got {size}");
    }
    spraysim::check_threads(threads)?;
    let dir = lock(output)?;
    let start = Instant::now();
    let report = spraysim_validate::report(spraysim_validate::Size::times(size), threads, |name| {
        eprintln!("[{:>6.1} s] {name}", start.elapsed().as_secs_f64());
    });
    let files = report
        .files()
        .and_then(|f| dir.write_set_with(&f, &RunControl))
        .with_context(|| format!("writing the report to {}", output.display()))?;
    for v in &report.verdicts {
        say!("{:<6} {}: {} ({})", if v.passed { "pass" } else { "FAIL" }, v.name, v.statistic, v.criterion);
    }
    say!("wrote {} files to {} in {:.1} s", files.len(), output.display(), start.elapsed().as_secs_f64());
    let failed = report.verdicts.iter().filter(|v| !v.passed).count();
    if failed > 0 {
        anyhow::bail!("{failed} of {} checks failed", report.verdicts.len());
    }
    Ok(())
}
