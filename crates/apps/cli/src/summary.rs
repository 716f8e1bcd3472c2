//! The summary a run prints when it ends: where the emitted material went, how the nozzle kept
//! to its working window, each target's layer or wear, as fixed-width tables, and the sanity
//! warnings about the run.

use anyhow::Result;
use spraysim::scenario::NozzleMotion;
use spraysim::scenario::sanity::Warning;
use spraysim::{Metrics, Scenario};

/// Prints the summary of a run of `sc` that simulated `m.time` in `wall` seconds: the fate of
/// what was emitted, the rebound and transfer efficiency, cohesive failures, the nozzle's
/// window, each target's layer and each eroded target's wear, then the `warnings`.
pub fn print(m: &Metrics, sc: &Scenario, warnings: &[Warning], wall: f64) -> Result<()> {
    let pct = |a: f64, b: f64| if b > 0.0 { 100.0 * a / b } else { 0.0 };
    let e = m.emitted;
    say!("simulated {:.3} s in {:.2} s ({:.2}× real time)", m.time, wall, m.time / wall.max(1e-9));
    say!("{:<22}{:>12}{:>16}{:>9}", "fate", "particles", "volume [m³]", "share");
    let f = &m.fates;
    for (name, a) in [
        ("emitted", e),
        ("stuck on targets", f.stuck_on_targets),
        ("stuck on obstacles", f.stuck_on_obstacles),
        ("left the domain", f.left_domain),
        ("expired", f.expired),
        ("overspray", f.overspray),
        ("in flight", f.in_flight),
    ] {
        say!("{name:<22}{:>12}{:>16.6e}{:>8.2}%", a.count, a.volume, pct(a.volume, e.volume));
    }
    let show = |x: Option<f64>| x.map_or("n/a".to_string(), |v| format!("{:.2} %", 100.0 * v));
    say!(
        "rebound (ACI: not in place) {}   bounced at first impact {}   trapped rebound {}",
        show(m.rebound_ratio),
        show(m.bounce_ratio),
        show(m.trapped_ratio)
    );
    say!("transfer efficiency {}", show(m.transfer_efficiency));
    let fell = m.failures.events.iter().fold(0.0, |acc, e| acc + e.volume);
    say!(
        "cohesive failures {}   fallen volume {fell:.3e} m³   slumped off the edges {:.3e} m³",
        m.failures.events.len(),
        m.failures.ran_off.volume
    );
    print_window(m, sc)?;
    print_layers(m)?;
    print_erosion(m)?;
    for w in warnings {
        say!("warning: {w}");
    }
    Ok(())
}

/// How the nozzle kept to the process's working window (`[process.window]`): the mean of each
/// quantity over the spraying time and the share of that time outside the window.
fn print_window(m: &Metrics, sc: &Scenario) -> Result<()> {
    let (p, w) = (&m.path, &sc.process().window);
    if p.spraying_time <= 0.0 {
        return Ok(());
    }
    let pct = |share: f64| format!("{:.1}%", 100.0 * share);
    say!("{:<24}{:>16}{:>16}{:>10}", "nozzle", "mean", "window", "outside");
    let travels = matches!(sc.nozzle().motion, NozzleMotion::Waypoints { .. } | NozzleMotion::Raster { .. });
    let rows = [
        ("standoff", p.standoff, (3, " m"), format!("{}–{} m", w.standoff[0], w.standoff[1])),
        ("angle off square", p.angle, (1, "°"), format!("≤ {}°", w.max_angle)),
        ("travel speed", p.travel_speed, (3, " m/s"), format!("{}–{} m/s", w.speed[0], w.speed[1])),
    ];
    for (name, range, (decimals, unit), window) in rows {
        let value = |x: f64| format!("{x:.decimals$}{unit}");
        let (mean, outside) = match range {
            // A static or circling nozzle does not travel: its speed is not judged.
            Some(_) if name == "travel speed" && !travels => ("does not travel".to_string(), "—".to_string()),
            Some(r) => (value(r.mean), pct(r.outside_share)),
            None => ("n/a".to_string(), "n/a".to_string()),
        };
        say!("{name:<24}{mean:>16}{window:>16}{outside:>10}");
    }
    say!("{:<24}{:>16}{:>16}{:>10}", "off target (axis misses)", "", "", pct(p.off_target_share));
    Ok(())
}

/// The layer on every target that holds one: hits, thickness and coverage, and the share
/// within the tolerance band where a target gives one. Thicknesses are in µm when every layer
/// is thinner than 1 mm (paint films), else in mm.
fn print_layers(m: &Metrics) -> Result<()> {
    let layered: Vec<_> = m.targets.iter().filter(|t| t.layer_volume > 0.0).collect();
    if layered.is_empty() {
        return Ok(());
    }
    // The share within the tolerance band, where a target gives one (judged on the dry film
    // where the material has volume solids).
    let spec = layered.iter().any(|t| {
        t.thickness.in_tolerance.or(t.dry_thickness.as_ref().and_then(|d| d.in_tolerance)).is_some()
    });
    let thickest = layered.iter().map(|t| t.thickness.max).fold(0.0, f64::max);
    let (unit, scale) = if thickest < 1e-3 { ("µm", 1e6) } else { ("mm", 1e3) };
    say!(
        "{:<12}{:>10}{:>22}{:>12}{:>18}{:>10}{}",
        "target",
        "hits",
        format!("mean covered [{unit}]"),
        format!("max [{unit}]"),
        "CV covered [%]",
        "covered",
        if spec { format!("{:>11}", "in spec") } else { String::new() }
    );
    for t in layered {
        // The wet layer, and the dry film where the material has volume solids.
        let rows = std::iter::once((t.name.clone(), &t.thickness))
            .chain(t.dry_thickness.as_ref().map(|d| (format!("{} dry", t.name), d)));
        for (name, th) in rows {
            let in_spec =
                th.in_tolerance.map_or_else(|| format!("{:>11}", "—"), |f| format!("{:>10.1}%", 100.0 * f));
            say!(
                "{:<12}{:>10}{:>22.3}{:>12.3}{:>18.1}{:>9.1}%{}",
                name,
                t.hits,
                th.deposited_mean * scale,
                th.max * scale,
                100.0 * th.deposited_cv,
                100.0 * th.covered_fraction,
                if spec { in_spec } else { String::new() }
            );
        }
    }
    say!("(mean and CV covered: over the cells that hold material; covered: share of the whole target)");
    if m.targets.iter().any(|t| t.dry_thickness.is_some()) {
        say!("(dry: the wet film times the paint's volume solids; a tolerance band judges the dry film)");
    }
    Ok(())
}

/// The wear of every eroded target: the coat cleaned and left, the substrate worn.
fn print_erosion(m: &Metrics) -> Result<()> {
    let eroded: Vec<_> = m.targets.iter().filter_map(|t| t.erosion.as_ref().map(|e| (t, e))).collect();
    if eroded.is_empty() {
        return Ok(());
    }
    say!(
        "{:<12}{:>10}{:>12}{:>11}{:>14}{:>14}",
        "target",
        "hits/cm²",
        "cleaned",
        "coat [µm]",
        "wear [µm]",
        "max wear [µm]"
    );
    for (t, e) in eroded {
        let cleaned = e.cleaned_fraction.map_or("n/a".to_string(), |c| format!("{:.1}%", 100.0 * c));
        say!(
            "{:<12}{:>10.2}{:>12}{:>11.1}{:>14.3}{:>14.3}",
            t.name,
            t.hits_per_cm2,
            cleaned,
            e.coating_left_mean * 1e6,
            e.substrate_mean_depth * 1e6,
            e.substrate_max_depth * 1e6
        );
    }
    Ok(())
}
