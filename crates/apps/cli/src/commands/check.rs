//! `spraysim check`: validates a scenario without running it, and prints its size or the
//! scenario resolved.

use super::{load, strict_refusal, warn_size, write_out};
use crate::cli::CheckArgs;
use anyhow::Result;
use spraysim::scenario::sanity;

/// Validates a scenario and prints its size, or the scenario resolved.
pub fn check(args: &CheckArgs) -> Result<()> {
    let sc = load(args.scenario.as_deref(), &args.set)?;
    // What the first line names: the file, or the scene `run` runs without one.
    let name =
        args.scenario.as_ref().map_or_else(|| "the default scene".to_string(), |p| p.display().to_string());
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
        name,
        counted(sc.targets().len(), "target"),
        counted(sc.obstacles().len(), "obstacle"),
        b.steps,
        sanity::sprayed_particles(&sc),
        b.in_flight,
        spraysim::scenario::bytes_text(b.memory),
        spraysim::scenario::bytes_text(b.limit)
    );
    for line in derived_splats(&sc) {
        say!("{line}");
    }
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

/// A line for each target whose splat radius the scenario derived (no `splat_radius` key): the
/// radius, in mm and in cells, and the particles its footprint expects.
fn derived_splats(sc: &spraysim::Scenario) -> Vec<String> {
    let mut out = Vec::new();
    for t in sc.targets() {
        let (Some(splat), Some([cols, rows])) = (t.shape.splat_radius(), t.shape.resolution()) else {
            continue;
        };
        let Some(expected) = splat.expected_particles.filter(|_| splat.derived) else {
            continue;
        };
        let [width, height] = t.size();
        let cell = (width / f64::from(cols)).min(height / f64::from(rows));
        out.push(splat_line(&t.name, splat.radius, cell, expected));
    }
    out
}

/// The line of target `name`, whose derived splat radius is `radius` (m) on cells `cell` (m)
/// wide, its footprint expecting `expected` particles.
fn splat_line(name: &str, radius: f64, cell: f64, expected: f64) -> String {
    let enough = spraysim::scenario::PARTICLES_PER_SPLAT;
    let head = if radius > 0.0 {
        format!(
            "target `{name}`: splat radius {:.3} mm ({:.0} cells) by default",
            radius * 1e3,
            radius / cell
        )
    } else {
        format!("target `{name}`: splat radius 0 (single-cell deposits) by default")
    };
    let tail = if expected >= enough {
        "`splat_radius` sets it; 0 keeps single-cell deposits".to_string()
    } else {
        format!(
            "the widest allowed, short of the {enough:.0} wanted: raise emitter.spawn_rate or lower the resolution"
        )
    };
    format!("{head}, about {expected:.1} particles expected per splat ({tail})")
}
