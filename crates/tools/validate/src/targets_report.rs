//! The report's section on curved targets: the cos³ law on a cylinder shell's unrolled map and on
//! a triangulated sphere section.

use super::{Writer, chi2_limit};
use crate::targets::{CurvedLaw, shell_cos3, sphere_cos3};
use spraysim_plot::{Chart, Legend, Mark, Series};

pub(super) fn curved_section(w: &mut Writer, particles: f64, threads: usize) {
    w.section(
        "Deposition on curved targets",
        &format!(
            "A point nozzle sprays {particles:.0} particles uniformly over the solid angle Ω of a 40° cone, with no \
             gravity and no rebound. (a) From the axis of a cylinder shell of radius R = 0.5 m seen from inside \
             (`shape = \"cylinder\"`, 360 × 160 cells), a ray at ψ from the plane across the axis meets the shell \
             at ρ = R / cos ψ with incidence ψ, so the unrolled map must follow t = V cos³ψ / (Ω R²). (b) From the \
             centre of a sphere section of the same radius built of triangles (`shape = \"mesh\"`, rings of 3°, \
             sectors of 6°), each triangle collects the share of Ω it subtends, t = V Ω_tri / (Ω A_tri) \
             (Van Oosterom & Strackee's solid angle). Cells are binned by the angle of their centre from the \
             cone's axis, in 4° rings clear of the cone's edge; the χ² uses each ring's Poisson error. The \
             volume in each map, Σ t × area, must equal the volume emitted to 10⁻⁹."
        ),
    );
    let runs = [
        ("cylinder shell", shell_cos3(particles, threads)),
        ("sphere section (mesh)", sphere_cos3(particles, threads)),
    ];
    let mut rows = Vec::new();
    let mut series = Vec::new();
    for (name, r) in &runs {
        for ((a, s), c) in r.angles.iter().zip(&r.simulated).zip(&r.closed_form) {
            rows.push(vec![
                (*name).to_string(),
                format!("{a:.0}"),
                format!("{:.4}", s * 1e6),
                format!("{:.4}", c * 1e6),
                format!("{:+.2}", 100.0 * (s / c - 1.0)),
            ]);
        }
        series.push(Series::new(format!("{name}: closed form"), um(&r.angles, &r.closed_form), Mark::Line));
        series.push(Series::new(format!("{name}: simulated"), um(&r.angles, &r.simulated), Mark::Points));
    }
    w.table(
        &["target", "angle from axis [°]", "simulated [µm]", "closed form [µm]", "difference [%]"],
        &rows,
    );
    w.chart(
        "curved_targets",
        Chart {
            title: "deposit on curved targets from a point source".into(),
            x_label: "angle from the cone's axis [°]".into(),
            y_label: "mean thickness [µm]".into(),
            series,
            legend: Legend::UpperRight,
        },
    );
    for (name, r) in &runs {
        verdict(w, name, r);
    }
}

fn um(angles: &[f64], t: &[f64]) -> Vec<(f64, f64)> {
    angles.iter().zip(t).map(|(&a, &t)| (a, t * 1e6)).collect()
}

fn verdict(w: &mut Writer, name: &str, r: &CurvedLaw) {
    let dof = r.angles.len();
    let limit = chi2_limit(dof);
    w.verdict(
        &format!("cos³ law on a {name}"),
        format!("χ² = {:.1} over {dof} rings; volume error {:.1e}", r.chi2, r.volume_error),
        format!("χ² < {limit:.1}; |volume error| < 1e-9"),
        r.chi2 < limit && r.volume_error.abs() < 1e-9,
    );
}
