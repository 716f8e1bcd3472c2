//! `spraysim calibrate`: fits emitter parameters to a measured profile, writes the calibrated
//! scenario with its report, and prints the fit.

use super::lock;
use crate::cli::{CalibrateArgs, Fit, Shape};
use crate::control::RunControl;
use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use spraysim::Scenario;
use spraysim_calibrate::{Calibration, CalibrationSettings, FitParam, MeasuredProfile, ProfileShape};
use std::path::PathBuf;

impl From<Fit> for FitParam {
    fn from(f: Fit) -> FitParam {
        match f {
            Fit::Mu => FitParam::Mu,
            Fit::Sigma => FitParam::Sigma,
            Fit::ConeAngle => FitParam::ConeAngle,
            Fit::SpeedMin => FitParam::SpeedMin,
            Fit::SpeedMax => FitParam::SpeedMax,
        }
    }
}

impl From<Shape> for ProfileShape {
    fn from(s: Shape) -> ProfileShape {
        match s {
            Shape::Radial => ProfileShape::Radial,
            Shape::Right => ProfileShape::Right,
            Shape::Up => ProfileShape::Up,
        }
    }
}

/// The fit's settings `args` give; refuses a `--center` that is not two numbers.
fn settings(args: &CalibrateArgs) -> Result<CalibrationSettings> {
    let center = match args.center.as_deref() {
        None => None,
        Some(&[u, v]) => Some([u, v]),
        Some(other) => anyhow::bail!("--center takes two numbers, U,V in m; got {}", other.len()),
    };
    Ok(CalibrationSettings {
        fit: args.fit.iter().copied().map(FitParam::from).collect(),
        target: args.target.clone(),
        shape: args.shape.into(),
        center,
        band: args.band,
        shape_only: args.shape_only,
        max_iterations: args.max_iterations,
        tolerance: args.tolerance,
        threads: args.threads,
    })
}

/// Fits the emitter to a measured profile and writes the results.
pub fn calibrate(args: &CalibrateArgs) -> Result<()> {
    let settings = settings(args)?;
    let quiet = args.quiet;
    let scenario = Scenario::from_path(&args.scenario)?;
    // `-o DIR`, else where the scenario's runs write.
    let output = &args.output.clone().unwrap_or_else(|| PathBuf::from(&scenario.output().directory));
    let measured = MeasuredProfile::from_path(&args.profile)?;
    spraysim::check_threads(settings.threads)?;
    // Nelder–Mead's evaluation count is not known in advance: a spinner with the best error.
    let bar = if quiet { ProgressBar::hidden() } else { ProgressBar::new_spinner() };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let names: Vec<&str> = settings.fit.iter().map(|p| p.name()).collect();
    let cal = spraysim_calibrate::calibrate(&scenario, &measured, &settings, |e| {
        let values: Vec<String> = names.iter().zip(&e.values).map(|(n, v)| format!("{n} = {v:.4}")).collect();
        bar.set_message(format!(
            "evaluation {}: {} → RMS {:.2} % (best {:.2} %)",
            e.index,
            values.join(", "),
            100.0 * e.rms,
            100.0 * e.best_rms
        ));
        bar.tick();
    })?;
    bar.finish_and_clear();
    // Locked once the fit is done: the fit's refusals (a target it does not have, say) then
    // leave no folder behind.
    let dir = lock(output)?;
    let files = spraysim_calibrate::files::files(&cal, &measured)
        .and_then(|f| dir.write_set_with(&f, &RunControl))
        .with_context(|| format!("writing outputs to {}", output.display()))?;
    if !quiet {
        print_fit(&cal, settings.shape_only)?;
        say!("wrote {} files to {}", files.len(), output.display());
    }
    Ok(())
}

/// The fit's tables: each parameter at the start and fitted, then the errors; `shape_only`
/// adds the scale the simulated profile was given.
fn print_fit(cal: &Calibration, shape_only: bool) -> Result<()> {
    say!("{} evaluations, {} iterations ({})", cal.evaluations, cal.iterations, cal.termination);
    say!("{:<12}{:>14}{:>14}  unit", "parameter", "start", "fitted");
    for ((p, a), b) in cal.params.iter().zip(&cal.initial).zip(&cal.fitted) {
        say!("{:<12}{a:>14.6}{b:>14.6}  {}", p.name(), p.unit());
    }
    say!("{:<22}{:>10}{:>10}", "error, % of peak", "start", "fitted");
    let (i, f) = (&cal.initial_errors, &cal.errors);
    for (name, a, b) in [
        ("max absolute", i.max_abs, f.max_abs),
        ("RMS", i.rms, f.rms),
        ("mean absolute", i.mean_abs, f.mean_abs),
    ] {
        say!("{name:<22}{:>10.2}{:>10.2}", 100.0 * a, 100.0 * b);
    }
    if shape_only {
        say!("simulated profile scaled by {:.4} (shape only)", cal.scale);
    }
    Ok(())
}
