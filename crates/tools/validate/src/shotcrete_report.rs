//! The report's shotcrete sections: rebound against orientation beside ACI 506R, the cushion
//! effect of a static shot, and slump against Nye's heap and the wall limit.

use super::Writer;
use crate::shotcrete::*;
use spraysim_plot::{Chart, Legend, Mark, Series};

/// Particles per second of the practice runs: 0.5 cm³ each, small beside the layers built.
const PRACTICE_RATE: f64 = 3000.0;

/// The design thickness of every face, m.
const DESIGN: f64 = 0.1;

/// Binomial limit of the verdicts, standard deviations.
const Z: f64 = 4.5;

fn pct(x: f64) -> String {
    if x.is_finite() { format!("{:.1}", 100.0 * x) } else { "—".into() }
}

pub(super) fn orientation_section(w: &mut Writer, threads: usize) {
    w.section(
        "Shotcrete rebound against orientation (ACI 506R)",
        &format!(
            "ACI 506R gives the typical rebound of wet-mix shotcrete as 0–5 % on floors, 5–10 % on walls and \
             10–20 % overhead. Those are figures of practice: a nozzleman builds each face to its design thickness \
             in layers no thicker than the face can hold. The practice scenario does that with the shotcrete preset \
             unchanged. A {PANEL} m panel, its normal at φ from straight up, is sprayed edge to edge by a square-on \
             raster 1 m or 2 m away; the raster overruns the panel by the spray's footprint, so that every point \
             builds from bare substrate. The travel speed builds one application of a {:.0} mm design: as few equal \
             applications as the face's capacity h(φ) = 1 / (ρ g √[(max(0, −cos φ)/f_t)² + (sin φ/τ_y)²]) allows \
             (∞ on a floor, {:.0} mm on a wall from slump, {:.0} mm overhead from pull-off), each on a stiffened \
             base. Slabs facing up stand in formwork; walls and overheads have free edges. Loss is rebound as \
             ACI counts it: the share of the volume delivered to the panel that is not in place at the end \
             (bounced off, came to rest loose, fell or ran off). The line is the capture law alone, a layer built \
             evenly from bare substrate with no gravity: (1/T) ∫₀ᵀ f S(h/κ) dh. The one calibrated constant is \
             the capture ratio κ. {PRACTICE_RATE:.0} particles/s.",
            DESIGN * 1e3,
            layer_capacity(90.0) * 1e3,
            layer_capacity(180.0) * 1e3,
        ),
    );
    let angles: Vec<f64> = (0..=12).map(|k| 15.0 * f64::from(k)).collect();
    let runs: Vec<[PracticeRun; 2]> = angles
        .iter()
        .map(|&a| [1.0, 2.0].map(|d| practice_run(a, d, DESIGN, PRACTICE_RATE, threads)))
        .collect();
    let rows: Vec<Vec<String>> = runs
        .iter()
        .map(|[near, far]| {
            vec![
                format!("{:.0}", near.angle_deg),
                format!("{:.0}", near.thickness * 1e3),
                format!("{} ± {}", pct(near.loss), pct(near.sigma())),
                format!("{} ± {}", pct(far.loss), pct(far.sigma())),
                pct(uniform_build_loss(near.thickness)),
                format!("{} / {}", pct(near.trapped), pct(far.trapped)),
                format!("{} / {}", pct(near.fell), pct(far.fell)),
            ]
        })
        .collect();
    w.table(
        &[
            "φ [°]",
            "application [mm]",
            "loss at 1 m [%]",
            "loss at 2 m [%]",
            "capture law alone [%]",
            "trapped rebound, 1 m / 2 m [%]",
            "fell or ran off, 1 m / 2 m [%]",
        ],
        &rows,
    );
    orientation_chart(w, &runs);
    orientation_verdicts(w, &runs);
}

fn orientation_chart(w: &mut Writer, runs: &[[PracticeRun; 2]]) {
    let aci = ACI_WET_MIX.iter().flat_map(|&(a, [lo, hi])| [(a, 100.0 * lo), (a, 100.0 * hi)]).collect();
    let fine: Vec<(f64, f64)> = (0..=180)
        .map(|a| {
            let t = application_thickness(f64::from(a), DESIGN);
            (f64::from(a), 100.0 * uniform_build_loss(t))
        })
        .collect();
    let simulated = |k: usize| runs.iter().map(|r| (r[k].angle_deg, 100.0 * r[k].loss)).collect();
    w.chart(
        "rebound_orientation",
        Chart {
            title: "shotcrete rebound against the face's orientation".into(),
            x_label: "face normal from straight up φ [°] (0 floor, 90 wall, 180 overhead)".into(),
            y_label: "loss: rebound, fall-out and run-off [%]".into(),
            series: vec![
                Series::new("ACI 506R wet-mix ranges", aci, Mark::Ranges),
                Series::new("simulated, 1 m standoff", simulated(0), Mark::LinePoints),
                Series::new("simulated, 2 m standoff", simulated(1), Mark::LinePoints),
                Series::new("capture law alone, even build", fine, Mark::Line),
            ],
            legend: Legend::UpperLeft,
        },
    );
}

fn orientation_verdicts(w: &mut Writer, runs: &[[PracticeRun; 2]]) {
    let at = |angle: f64, k: usize| runs.iter().find(|r| r[k].angle_deg == angle).map(|r| r[k]);
    let (mut inside, mut ordered, mut worst) = (true, true, f64::INFINITY);
    for k in 0..2 {
        let faces: Vec<PracticeRun> = ACI_WET_MIX.iter().filter_map(|&(a, _)| at(a, k)).collect();
        for (run, (_, [lo, hi])) in faces.iter().zip(ACI_WET_MIX) {
            inside &= run.loss >= lo - Z * run.sigma() && run.loss <= hi + Z * run.sigma();
        }
        for pair in faces.windows(2) {
            let z = (pair[1].loss - pair[0].loss) / pair[0].sigma().hypot(pair[1].sigma());
            worst = worst.min(z);
            ordered &= z > Z;
        }
        ordered &= faces.len() == 3;
    }
    let summary = |k: usize| {
        ACI_WET_MIX.iter().filter_map(|&(a, _)| at(a, k)).map(|r| pct(r.loss)).collect::<Vec<_>>().join(" / ")
    };
    w.verdict(
        "rebound on floor, wall, overhead within ACI 506R",
        format!("{} % at 1 m, {} % at 2 m", summary(0), summary(1)),
        format!("inside 0–5 / 5–10 / 10–20 % within {Z} σ"),
        inside,
    );
    w.verdict(
        "rebound ordered floor < wall < overhead",
        format!("smallest step {worst:.0} σ"),
        format!("each step > {Z} σ at both standoffs"),
        ordered,
    );
}

pub(super) fn cushion_section(w: &mut Writer, threads: usize) {
    w.section(
        "Cushion effect: rebound over a static shot",
        "The shotcrete preset's nozzle held 1 m (and 2 m) square onto the middle of a 2 m × 2 m wall for 1 s. On \
         bare substrate every aggregate grain bounces; as the plastic layer builds, it catches the finer grains \
         first and all of them once it is κ times the largest grain deep, so rebound is highest at the start \
         and falls as the layer builds (ACI 506R). Plotted: the rebound of what arrived in each interval, and \
         of everything so far. The static shot is no practice figure (most of its footprint stays thin at 2 m): \
         the ACI range is drawn for scale. The check: the rebound over the first 0.1 s exceeds three times the \
         rebound over the whole second.",
    );
    // Nothing arrives from 2 m before 0.08 s: its first interval reads "—".
    let times = [0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0];
    let series = [1.0, 2.0].map(|d| cushion_series(90.0, d, &times, threads));
    let rows: Vec<Vec<String>> = (0..times.len())
        .map(|i| {
            let [near, far] = &series;
            vec![
                format!("{:.3}", near.times[i]),
                pct(near.window[i]),
                pct(near.cumulative[i]),
                pct(far.window[i]),
                pct(far.cumulative[i]),
            ]
        })
        .collect();
    w.table(
        &["t [s]", "1 m, interval [%]", "1 m, so far [%]", "2 m, interval [%]", "2 m, so far [%]"],
        &rows,
    );
    let curve = |s: &CushionSeries, v: &[f64]| s.times.iter().zip(v).map(|(&t, &x)| (t, 100.0 * x)).collect();
    let [near, far] = &series;
    w.chart(
        "rebound_static_shot",
        Chart {
            title: "rebound of a static shot onto a wall".into(),
            x_label: "time [s]".into(),
            y_label: "rebound [%]".into(),
            series: vec![
                Series::new("ACI 506R wet-mix, walls", vec![(1.05, 5.0), (1.05, 10.0)], Mark::Ranges),
                Series::new("1 m, per interval", curve(near, &near.window), Mark::LinePoints),
                Series::new("1 m, so far", curve(near, &near.cumulative), Mark::Line),
                Series::new("2 m, per interval", curve(far, &far.window), Mark::LinePoints),
                Series::new("2 m, so far", curve(far, &far.cumulative), Mark::Line),
            ],
            legend: Legend::UpperRight,
        },
    );
    let at = |s: &CushionSeries, t: f64| {
        s.times.iter().position(|&x| (x - t).abs() < 1e-6).map(|i| s.cumulative[i])
    };
    let (early, late) = (at(near, 0.1).unwrap_or(f64::NAN), at(near, 1.0).unwrap_or(f64::NAN));
    w.verdict(
        "cushion effect",
        format!("rebound {} % over 0.1 s, {} % over 1 s (1 m)", pct(early), pct(late)),
        "first 0.1 s > 3 × the whole second".into(),
        early > 3.0 * late,
    );
}

pub(super) fn slump_section(w: &mut Writer) {
    w.section(
        "Slump: Nye's heap and the wall limit",
        "Half a litre stacked in a 20 mm column on a floor of 4 mm cells, relaxed by the slump stage with the \
         shotcrete preset's yield stress τ_y. A yield-stress layer stands where ρ g h |∇e| ≤ τ_y; on a floor \
         that is Nye's plastic heap h(r) = √(2a(R − r)), a = τ_y/(ρ g), whose volume (8π/15) √(2a) R^{5/2} fixes \
         R. On a wall the layer holds at most a: a uniform 200 mm layer slides down to it and the rest runs off \
         the bottom edge. Volume is conserved to rounding; afterwards no edge carries more than τ_y (1 + 10⁻²), the \
         stage's tolerance (it aims 1 % under the limit). The lattice flattens the heap's tip and rounds its rim by a few per cent (half that on 2 mm cells).",
    );
    let heap = nye_heap(0.004);
    let mm = |v: &[f64]| heap.radii.iter().zip(v).map(|(r, t)| (r * 1e3, t * 1e3)).collect();
    w.chart(
        "slump_nye_heap",
        Chart {
            title: "half a litre slumped on a floor".into(),
            x_label: "radius [mm]".into(),
            y_label: "thickness [mm]".into(),
            series: vec![
                Series::new("Nye's plastic heap √(2a(R − r))", mm(&heap.closed_form), Mark::Line),
                Series::new("slump stage (annulus means)", mm(&heap.simulated), Mark::Points),
            ],
            legend: Legend::UpperRight,
        },
    );
    let (peak, nye) = heap.peak;
    // Inside the heap's edge (where the lattice's last step stands): the profile's largest gap.
    let gap = (0..heap.radii.len())
        .filter(|&k| heap.closed_form[k] > 0.2 * nye)
        .map(|k| (heap.simulated[k] - heap.closed_form[k]).abs() / nye)
        .fold(0.0, f64::max);
    w.verdict(
        "slump on a floor",
        format!(
            "peak {:.1} mm against Nye's {:.1} mm, profile within {:.1} % of it, volume error {:.0e}, largest \
             stress ratio {:.4}",
            peak * 1e3,
            nye * 1e3,
            100.0 * gap,
            heap.volume_error,
            heap.worst_stress_ratio
        ),
        "peak and profile within 5 %, volume ≤ 1e-9, stress ratio ≤ 1.01".into(),
        (peak / nye - 1.0).abs() < 0.05
            && gap < 0.05
            && heap.volume_error.abs() <= 1e-9
            && heap.worst_stress_ratio <= 1.01,
    );
    let a = layer_capacity(90.0);
    let (top, ran_off, error) = wall_slump(0.2);
    let expected = (0.2 - a) * 0.04;
    w.verdict(
        "slump on a wall",
        format!(
            "thickest {:.2} mm against a = {:.2} mm; ran off {ran_off:.3e} m³ against {expected:.3e}; volume error \
             {error:.0e}",
            top * 1e3,
            a * 1e3
        ),
        "0.99 a ≤ thickest ≤ 1.01 a, run-off within 2 %, volume ≤ 1e-9".into(),
        top <= a * 1.01 && top >= 0.99 * a * (1.0 - 1e-9) && (ran_off / expected - 1.0).abs() < 0.02 && error.abs() <= 1e-9,
    );
}
