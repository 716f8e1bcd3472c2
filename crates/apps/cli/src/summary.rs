//! The summary a run prints when it ends: where the emitted material went, and each target's
//! layer or wear, as fixed-width tables.

use anyhow::Result;
use spraysim::Metrics;

/// Prints the summary of a run that simulated `m.time` in `wall` seconds: the fate of what was
/// emitted, the rebound and transfer efficiency, cohesive failures, each target's layer and
/// each eroded target's wear.
pub fn print(m: &Metrics, wall: f64) -> Result<()> {
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
    print_layers(m)?;
    print_erosion(m)
}

/// The layer on every target that holds one: hits, thickness and coverage, and the share
/// within the tolerance band where a target gives one.
fn print_layers(m: &Metrics) -> Result<()> {
    let layered: Vec<_> = m.targets.iter().filter(|t| t.layer_volume > 0.0).collect();
    // The share within the tolerance band, where a target gives one.
    let spec = layered.iter().any(|t| t.thickness.in_tolerance.is_some());
    if !layered.is_empty() {
        say!(
            "{:<12}{:>10}{:>12}{:>12}{:>8}{:>11}{}",
            "target",
            "hits",
            "mean [mm]",
            "max [mm]",
            "CV",
            "covered",
            if spec { format!("{:>11}", "in spec") } else { String::new() }
        );
    }
    for t in layered {
        let th = &t.thickness;
        let in_spec =
            th.in_tolerance.map_or_else(|| format!("{:>11}", "—"), |f| format!("{:>10.1}%", 100.0 * f));
        say!(
            "{:<12}{:>10}{:>12.3}{:>12.3}{:>8.2}{:>10.1}%{}",
            t.name,
            t.hits,
            th.mean * 1e3,
            th.max * 1e3,
            th.cv,
            100.0 * th.covered_fraction,
            if spec { in_spec } else { String::new() }
        );
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
