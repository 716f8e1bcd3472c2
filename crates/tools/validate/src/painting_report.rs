//! The report's sections on droplets in the gun's air: Stokes drag against its closed form,
//! impaction against the critical Stokes number, and the paint guns' transfer efficiency
//! against the published ranges and trends.

use super::Writer;
use crate::painting::{
    PanelRun, drag_law_error, impaction, local_strain_bound, stokes_flight, transfer_efficiency,
};
use spraysim_plot::{Chart, Legend, Mark, Series};
use spraysim_scenario::Gun;

/// The drag checks: a droplet in still air against the closed form, and the Schiller–Naumann
/// step's order.
pub(super) fn drag_section(w: &mut Writer) {
    w.section(
        "Droplets in the gun's air: drag",
        "A 30 µm paint droplet (ρ = 1200 kg/m³) is sprayed horizontally at 20 m/s into still air by the \
         engine (`[air]` on, Stokes drag, Δt = 1 ms, 300 steps) and falls under gravity. Its path must follow \
         x = v₀τ(1 − e^{−t/τ}), z = −gτt + gτ²(1 − e^{−t/τ}) with τ = ρd²/(18μ): each step is that closed \
         form for air held over the step, so only the rounding of the velocity to single precision at each \
         step, at most n|v₀|Δt·2⁻²⁴ over n steps, may separate them. Seen from a frame moving with a \
         uniform cross-flow, this is a droplet released into that flow. Under Schiller–Naumann drag \
         (C_d = 24/Re (1 + 0.15 Re^0.687)) the relaxation time changes as the droplet slows; the step holds \
         it at the step's mean slip, and a 50 µm droplet at 30 m/s, flown for 50 ms, is compared with a \
         fourth-order Runge–Kutta integration 1000 times finer.",
    );
    let f = stokes_flight(30e-6, 20.0, 1e-3, 300);
    let bound = 300.0 * 20.0 * 1e-3 * f64::from(f32::EPSILON);
    let series = vec![
        Series::new("closed form", mm(&f.closed_form), Mark::Line),
        Series::new("engine", mm(&f.simulated).into_iter().step_by(10).collect(), Mark::Points),
    ];
    w.chart(
        "paint_stokes_flight",
        Chart {
            title: "a 30 µm droplet sprayed at 20 m/s into still air".into(),
            x_label: "distance [mm]".into(),
            y_label: "height [mm]".into(),
            series,
            legend: Legend::UpperRight,
        },
    );
    w.verdict(
        "Stokes drag against its closed form",
        format!("largest distance {:.1e} m over 300 steps (τ = {:.2} ms)", f.max_error, f.tau * 1e3),
        format!("< {bound:.1e} m"),
        f.max_error < bound,
    );
    let errors: Vec<(f64, f64, f64)> =
        [1e-3, 5e-4, 2.5e-4].iter().map(|&dt| (dt, drag_law_error(50e-6, 30.0, dt, 0.05).1, 0.0)).collect();
    let (distance, _) = drag_law_error(50e-6, 30.0, 1e-3, 0.05);
    let rows: Vec<Vec<String>> = errors
        .iter()
        .map(|(dt, e, _)| {
            vec![format!("{}", dt * 1e3), format!("{:.3}", e * 1e3), format!("{:.3}", 100.0 * e / distance)]
        })
        .collect();
    w.table(&["Δt [ms]", "error in the distance flown [mm]", "of the distance [%]"], &rows);
    let order = (errors[0].1 / errors[1].1).log2();
    w.verdict(
        "Schiller–Naumann step, order and size of its error",
        format!("order {order:.2}; {:.2} % of the distance at Δt = 1 ms", 100.0 * errors[0].1 / distance),
        "order 1.6 to 2.6; < 0.5 %".into(),
        (1.6..2.6).contains(&order) && errors[0].1 < 5e-3 * distance,
    );
}

fn mm(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    points.iter().map(|&(x, z)| (x * 1e3, z * 1e3)).collect()
}

/// Impaction in the stagnation layer against the critical Stokes number.
pub(super) fn impaction_section(w: &mut Writer, droplets: usize) {
    w.section(
        "Impaction onto a wall in a stagnation flow",
        &format!(
            "In a linear stagnation flow u_n = −a h a droplet obeys τ h'' + h' + a h = 0: entering with the air's \
             velocity, it reaches the wall only if its Stokes number τa exceeds 1/4; below, it is carried past \
             (Taylor 1940; Langmuir & Blodgett 1946; the inviscid critical Stokes number of impaction). A \
             round jet (U₀ = 100 m/s, d₀ = 6 mm, spread 0.094) strikes a wall 0.2 m away; {droplets} droplets \
             enter its stagnation layer (δ = 0.14 H) with the air, spread over the jet by its flux, and are \
             stepped through it (Stokes drag, no gravity, Δt = 0.1 ms with the engine's substeps). Their \
             Stokes number is τ W_c/δ, with W_c the centreline's speed at the wall: the strain there. The \
             strain grows by up to 16 % towards the layer's top, where the jet is faster, so the droplet on \
             the axis must be captured above Stk = 1/4 (the strain it meets is never below the wall's) and not \
             below 0.25/1.16 = 0.216 (never above 1.16 times it). Off the axis the strain \
             is W(ρ)/δ, which gives the local-strain bound E = 1 − 1/(4 Stk) over a Gaussian jet's flux; the \
             wall jet sweeps some droplets out of the jet before they land, so the efficiency must lie below \
             it, rise with Stk and approach 1."
        ),
    );
    let stokes = [0.1, 0.15, 0.2, 0.23, 0.26, 0.3, 0.4, 0.6, 1.0, 1.5, 2.5, 4.0, 8.0];
    let runs = impaction(&stokes, droplets);
    let rows: Vec<Vec<String>> = runs
        .iter()
        .map(|r| {
            vec![
                format!("{}", r.stokes),
                format!("{:.3}", r.efficiency),
                format!("{:.3}", local_strain_bound(r.stokes)),
                if r.on_axis { "yes" } else { "no" }.into(),
            ]
        })
        .collect();
    w.table(&["Stokes number", "capture efficiency", "local-strain bound", "axis droplet captured"], &rows);
    let bound: Vec<(f64, f64)> = (0..=200)
        .map(|k| 0.1 * 80f64.powf(f64::from(k) / 200.0))
        .map(|s| (s.log10(), local_strain_bound(s)))
        .collect();
    w.chart(
        "paint_impaction",
        Chart {
            title: "capture of droplets in a stagnation flow against the Stokes number".into(),
            x_label: "log₁₀ Stokes number τ W_c/δ".into(),
            y_label: "capture efficiency".into(),
            series: vec![
                Series::new("local-strain bound 1 − 1/(4 Stk)", bound, Mark::Line),
                Series::new(
                    "critical Stk = 1/4 (Taylor; Langmuir & Blodgett)",
                    vec![(0.25f64.log10(), 0.0), (0.25f64.log10(), 1.0)],
                    Mark::Ranges,
                ),
                Series::new(
                    "engine's air and drag",
                    runs.iter().map(|r| (r.stokes.log10(), r.efficiency)).collect(),
                    Mark::LinePoints,
                ),
            ],
            legend: Legend::UpperLeft,
        },
    );
    let axis_ok = runs.iter().all(|r| {
        (r.stokes <= 0.25 / 1.16 && !r.on_axis)
            || (r.stokes > 0.25 && r.on_axis)
            || (0.25 / 1.16..=0.25).contains(&r.stokes)
    });
    let below = runs.iter().all(|r| r.efficiency <= local_strain_bound(r.stokes) + 0.01);
    let rising = runs.windows(2).all(|p| p[0].efficiency <= p[1].efficiency);
    let last = runs.last().map_or(0.0, |r| r.efficiency);
    w.verdict(
        "critical Stokes number of a stagnation flow",
        format!("axis droplet captured above Stk = 1/4 and not below 0.216: {axis_ok}; efficiency below the bound: {below}; rising: {rising}; {last:.2} at Stk = 8"),
        "all three, and > 0.7 at Stk = 8".into(),
        axis_ok && below && rising && last > 0.7,
    );
}

/// Each gun's transfer efficiency on the flat panel, and the trends.
pub(super) fn guns_section(w: &mut Writer, rate: f64, threads: usize) {
    w.section(
        "Transfer efficiency of the paint guns",
        &format!(
            "Each gun preset (`[process] gun`) sprays the flat-panel test (`scenes::painted_panel`): a 1 m × 1 m \
             panel, the gun at its standard standoff and travel speed, horizontal passes from the bottom edge \
             to the top overlapping by half the pattern's width, the fan across the passes, triggered 5 cm \
             beyond each edge, {rate} particles/s, two seeds. Transfer efficiency is the paint on the panel \
             over the paint sprayed; what misses it is overspray (droplets that drift out of the jet, are \
             turned along the panel by the stagnation flow, or pass its edges). Published ranges: conventional \
             air about 30 % (20–40), airless 40–50 %, HVLP 50–60 %, air-assisted airless 60–80 % (\"A Primer \
             on Transfer Efficiency\", Products Finishing; SCAQMD). A bell's published 65–90 % is with \
             electrostatics, which spraysim does not model: its figure is reported, not judged. docs/painting.md \
             gives each gun's parameters and their sources."
        ),
    );
    let runs: Vec<PanelRun> =
        Gun::ALL.iter().map(|&g| transfer_efficiency(g, rate, 2, &[], threads)).collect();
    let mut rows = Vec::new();
    let mut simulated = Vec::new();
    let mut published = Vec::new();
    for (k, r) in runs.iter().enumerate() {
        let x = k as f64 + 1.0;
        let range = r.gun.published_transfer_efficiency();
        let spread = r.efficiencies.iter().fold(0.0f64, |a, &e| a.max((e - r.mean()).abs()));
        let b = &r.metrics.volume_balance;
        rows.push(vec![
            format!("{x:.0}: {}", r.gun.name()),
            format!("{:.1} ± {:.1}", 100.0 * r.mean(), 100.0 * spread),
            range.map_or("— (electrostatic only)".into(), |([lo, hi], _)| {
                format!("{:.0}–{:.0}", 100.0 * lo, 100.0 * hi)
            }),
            format!("{:.1}", 100.0 * r.metrics.fates.overspray.volume / r.metrics.emitted.volume),
            format!("{:.0e}", b.residual / b.emitted),
        ]);
        simulated.push((x, 100.0 * r.mean()));
        if let Some(([lo, hi], _)) = range {
            published.extend([(x, 100.0 * lo), (x, 100.0 * hi)]);
        }
    }
    w.table(&["gun", "transfer efficiency [%]", "published [%]", "overspray [%]", "balance residual"], &rows);
    w.chart(
        "paint_transfer_efficiency",
        Chart {
            title:
                "transfer efficiency on a 1 m panel: 1 air, 2 HVLP, 3 airless, 4 air-assisted airless, 5 bell"
                    .into(),
            x_label: "gun".into(),
            y_label: "transfer efficiency [%]".into(),
            series: vec![
                Series::new("published range", published, Mark::Ranges),
                Series::new("spraysim", simulated, Mark::Points),
            ],
            legend: Legend::UpperLeft,
        },
    );
    guns_verdicts(w, &runs);
    trends(w, rate, threads);
}

/// The verdicts on the guns' runs: each inside its published range, their order, and the
/// volume balance.
fn guns_verdicts(w: &mut Writer, runs: &[PanelRun]) {
    for r in runs {
        if let Some(([lo, hi], _)) = r.gun.published_transfer_efficiency() {
            w.verdict(
                &format!("transfer efficiency of the {} gun", r.gun.name()),
                format!("{:.1} %", 100.0 * r.mean()),
                format!("within {:.0}–{:.0} %", 100.0 * lo, 100.0 * hi),
                (lo..=hi).contains(&r.mean()),
            );
        }
    }
    let te = |g: Gun| runs.iter().find(|r| r.gun == g).map_or(0.0, PanelRun::mean);
    let (air, hvlp, airless, aaa) =
        (te(Gun::Air), te(Gun::Hvlp), te(Gun::Airless), te(Gun::AirAssistedAirless));
    w.verdict(
        "order of the guns",
        format!(
            "air {:.1} < airless {:.1} ≤ HVLP {:.1} < air-assisted airless {:.1} %",
            100.0 * air,
            100.0 * airless,
            100.0 * hvlp,
            100.0 * aaa
        ),
        "air < airless ≤ HVLP < air-assisted airless".into(),
        air < airless && airless <= hvlp && hvlp < aaa,
    );
    let worst = runs
        .iter()
        .map(|r| (r.metrics.volume_balance.residual / r.metrics.emitted.volume).abs())
        .fold(0.0, f64::max);
    w.verdict(
        "volume balance with overspray as a fate",
        format!("largest residual {worst:.1e} of the emitted volume"),
        "≤ 1e-9".into(),
        worst <= 1e-9,
    );
}

/// How the conventional air gun's transfer efficiency moves with droplet size, air speed and
/// standoff.
fn trends(w: &mut Writer, rate: f64, threads: usize) {
    w.section(
        "Transfer efficiency against droplet size, air speed and standoff",
        "The conventional air gun on the same panel, one setting changed at a time (one seed each). \
         Published trends: transfer efficiency falls as droplets get smaller, as the atomising air gets \
         faster, and as the gun is held farther away (Kwok 1991; Im et al. 2001; the painters' rule of \
         15–25 cm). An air-atomised gun's droplets get finer as its air gets faster (D₃₂ ∝ 1/U₀, the leading \
         term of plain-jet airblast atomisation, Lorenzetto & Lefebvre 1977), which is how faster air \
         lowers the transfer efficiency; at a fixed droplet size faster air would raise it (larger Stokes \
         numbers at the wall), and the second series shows that too. Each step must move it by more than \
         2 points, four times its seed-to-seed scatter.",
    );
    let te =
        |settings: &[(&str, f64)]| 100.0 * transfer_efficiency(Gun::Air, rate, 1, settings, threads).mean();
    let sizes = [10e-6, 13e-6, 16e-6, 20e-6, 25e-6, 32e-6];
    let by_size: Vec<(f64, f64)> =
        sizes.iter().map(|&d| (d * 1e6, te(&[("emitter.sauter_mean", d)]))).collect();
    let speeds = [150.0, 200.0, 250.0, 300.0, 350.0];
    let by_air: Vec<(f64, f64)> = speeds.iter().map(|&u| (u, te(&[("air.speed", u)]))).collect();
    let by_air_fixed: Vec<(f64, f64)> =
        speeds.iter().map(|&u| (u, te(&[("air.speed", u), ("emitter.sauter_mean", 16e-6)]))).collect();
    let standoffs = [0.12, 0.16, 0.2, 0.24, 0.28];
    let by_standoff: Vec<(f64, f64)> =
        standoffs.iter().map(|&s| (s * 100.0, te(&[("nozzle.raster.standoff", s)]))).collect();
    let chart = |stem: &str, title: &str, x: &str, series: Vec<Series>| {
        (
            stem.to_string(),
            Chart {
                title: title.into(),
                x_label: x.into(),
                y_label: "transfer efficiency [%]".into(),
                series,
                legend: Legend::UpperRight,
            },
        )
    };
    let charts = [
        chart(
            "paint_te_droplet_size",
            "air gun: transfer efficiency against droplet size",
            "Sauter mean diameter [µm]",
            vec![Series::new("spraysim", by_size.clone(), Mark::LinePoints)],
        ),
        chart(
            "paint_te_air_speed",
            "air gun: transfer efficiency against air speed",
            "air speed at the cap [m/s]",
            vec![
                Series::new("droplets atomised by the air (D₃₂ ∝ 1/U₀)", by_air.clone(), Mark::LinePoints),
                Series::new("droplets held at 16 µm", by_air_fixed, Mark::LinePoints),
            ],
        ),
        chart(
            "paint_te_standoff",
            "air gun: transfer efficiency against standoff",
            "standoff [cm]",
            vec![Series::new("spraysim", by_standoff.clone(), Mark::LinePoints)],
        ),
    ];
    for (stem, c) in charts {
        w.chart(&stem, c);
    }
    let steps = |v: &[(f64, f64)], sign: f64| {
        v.windows(2).map(|p| sign * (p[1].1 - p[0].1)).fold(f64::INFINITY, f64::min)
    };
    let (s, a, d) = (steps(&by_size, 1.0), steps(&by_air, -1.0), steps(&by_standoff, -1.0));
    w.verdict(
        "published trends of transfer efficiency",
        format!("smallest step: {s:.1} points rising with size, {a:.1} falling with air speed, {d:.1} falling with standoff"),
        "each > 2 points".into(),
        s > 2.0 && a > 2.0 && d > 2.0,
    );
}
