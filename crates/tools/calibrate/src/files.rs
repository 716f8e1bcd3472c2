//! Files of a calibration: the fitted scenario, a JSON summary, the profiles as CSV and a plot
//! of measured against simulated.

use crate::{Calibration, MeasuredProfile, Quantity};
use spraysim_output::OutputError;
use spraysim_plot::{Chart, Mark, Series, png};
use std::fmt::Write;
use std::path::Path;

/// Display unit and factor from SI for a profile's values.
fn display_unit(q: Quantity) -> (&'static str, f64) {
    match q {
        Quantity::Thickness => ("mm", 1e3),
        Quantity::MassPerArea => ("kg/m²", 1.0),
    }
}

/// `calibrated.toml`, `calibration.json`, `profile.csv` and `profile.png`, as (name, bytes).
pub fn files(cal: &Calibration, measured: &MeasuredProfile) -> Result<Vec<(String, Vec<u8>)>, OutputError> {
    let mut toml = String::from("# Scenario calibrated by spraysim against ");
    let _ = writeln!(toml, "{}.", measured.origin);
    for ((p, a), b) in cal.params.iter().zip(&cal.initial).zip(&cal.fitted) {
        let _ = writeln!(toml, "# {} [{}]: {a:.6} -> {b:.6}", p.name(), p.unit());
    }
    let e = &cal.errors;
    let _ = writeln!(
        toml,
        "# errors, % of the measured peak: max abs {:.2}, RMS {:.2}, mean abs {:.2}\n",
        100.0 * e.max_abs,
        100.0 * e.rms,
        100.0 * e.mean_abs
    );
    toml.push_str(&cal.scenario.to_toml());

    let json = serde_json::to_string_pretty(cal)
        .map_err(|err| OutputError::Io { path: "calibration.json".into(), source: err.into() })?;

    let (unit, k) = display_unit(cal.quantity);
    let mut csv = format!("position [m],measured [{unit}],initial [{unit}],fitted [{unit}]\n");
    for i in 0..cal.positions.len() {
        let _ = writeln!(
            csv,
            "{},{},{},{}",
            cal.positions[i],
            cal.measured[i] * k,
            cal.initial_simulated[i] * k,
            cal.simulated[i] * k
        );
    }

    let series = |values: &[f64]| cal.positions.iter().zip(values).map(|(&p, &v)| (p * 1e3, v * k)).collect();
    let fitted = cal.params.iter().zip(&cal.fitted).map(|(p, v)| format!("{} = {v:.4}", p.name()));
    let chart = Chart {
        title: format!("calibration against {}", file_name(&measured.origin)),
        x_label: format!("{} [mm]", measured.position_name),
        y_label: format!("{} [{unit}]", measured.value_name),
        series: vec![
            Series::new("measured", series(&cal.measured), Mark::Points),
            Series::new(
                format!("fitted: {} (RMS {:.2} %)", fitted.collect::<Vec<_>>().join(", "), 100.0 * e.rms),
                series(&cal.simulated),
                Mark::Line,
            ),
            Series::new(
                format!("start (RMS {:.2} %)", 100.0 * cal.initial_errors.rms),
                series(&cal.initial_simulated),
                Mark::Line,
            ),
        ],
        legend: spraysim_plot::Legend::UpperRight,
    };
    Ok(vec![
        ("calibrated.toml".into(), toml.into_bytes()),
        ("calibration.json".into(), json.into_bytes()),
        ("profile.csv".into(), csv.into_bytes()),
        ("profile.png".into(), png(&chart, Path::new("profile.png"))?),
    ])
}

fn file_name(origin: &str) -> &str {
    Path::new(origin).file_name().and_then(|n| n.to_str()).unwrap_or(origin)
}
