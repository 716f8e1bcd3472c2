//! # spraysim-validate
//!
//! Verification against closed forms: the experiments of [`checks`] at a chosen size, judged by
//! stated statistical criteria, and written up as a Markdown report with plots
//! (`spraysim validate`). The test suite runs the same experiments at a smaller size.

pub mod checks;
pub mod epochs;
pub mod painting;
mod painting_report;
pub mod shotcrete;
mod shotcrete_report;
pub mod targets;
mod targets_report;

use checks::*;
use spraysim_engine::emission::Direction;
use spraysim_engine::motion::Integrator;
use spraysim_output::OutputError;
use spraysim_plot::{Chart, Legend, Mark, Series, png};
use std::fmt::Write;
use std::path::Path;

/// One check's outcome: what was compared, how, and whether it passed.
#[derive(Clone, Debug)]
pub struct Verdict {
    /// What the check tests, as the report's verdict line names it.
    pub name: String,
    /// The statistic, as measured.
    pub statistic: String,
    /// The pass criterion.
    pub criterion: String,
    /// Whether the statistic meets the criterion.
    pub passed: bool,
}

/// A validation report: Markdown text, the charts it links to, and the verdicts.
#[derive(Clone, Debug)]
pub struct Report {
    /// The Markdown body (links to `validation/NAME.png`).
    pub markdown: String,
    /// Charts by file stem.
    pub charts: Vec<(String, Chart)>,
    /// Every verdict, in report order.
    pub verdicts: Vec<Verdict>,
}

impl Report {
    /// Whether every check passed.
    pub fn passed(&self) -> bool {
        self.verdicts.iter().all(|v| v.passed)
    }

    /// `validation.md` and `validation/NAME.png`, as (relative path, bytes).
    pub fn files(&self) -> Result<Vec<(String, Vec<u8>)>, OutputError> {
        let mut files = vec![("validation.md".to_string(), self.markdown.clone().into_bytes())];
        for (stem, chart) in &self.charts {
            let name = format!("validation/{stem}.png");
            let bytes = png(chart, Path::new(&name))?;
            files.push((name, bytes));
        }
        Ok(files)
    }
}

/// Accumulates sections, charts and verdicts.
#[derive(Default)]
struct Writer {
    body: String,
    charts: Vec<(String, Chart)>,
    verdicts: Vec<Verdict>,
}

impl Writer {
    fn section(&mut self, title: &str, text: &str) {
        let _ = write!(self.body, "\n## {title}\n\n{text}\n");
    }

    fn table(&mut self, header: &[&str], rows: &[Vec<String>]) {
        let _ = writeln!(self.body, "\n| {} |", header.join(" | "));
        let _ = writeln!(self.body, "|{}", "---|".repeat(header.len()));
        for r in rows {
            let _ = writeln!(self.body, "| {} |", r.join(" | "));
        }
    }

    fn chart(&mut self, stem: &str, chart: Chart) {
        let _ = write!(self.body, "\n![{}](validation/{stem}.png)\n", chart.title);
        self.charts.push((stem.to_string(), chart));
    }

    fn verdict(&mut self, name: &str, statistic: String, criterion: String, passed: bool) {
        let mark = if passed { "pass" } else { "**FAIL**" };
        let _ = write!(self.body, "\n**{name}**: {statistic}; criterion {criterion}: {mark}.\n");
        self.verdicts.push(Verdict { name: name.to_string(), statistic, criterion, passed });
    }
}

/// Sample sizes of a report, as multiples of the test suite's.
#[derive(Clone, Copy, Debug)]
pub struct Size {
    /// Particles of the cone-law run.
    pub cone_particles: f64,
    /// Draws per direction law.
    pub direction_draws: u64,
    /// Particles per rebound angle.
    pub rebound_particles: f64,
    /// Forced rebounds per restitution value.
    pub rebounds: u64,
    /// Particles of each curved-target run.
    pub curved_particles: f64,
    /// Seeds per layer-epoch length.
    pub epoch_seeds: u64,
    /// Particles per second of the paint guns' panel runs.
    pub paint_rate: f64,
    /// Droplets per Stokes number of the impaction check.
    pub impaction_droplets: usize,
}

impl Size {
    /// `factor` times the sizes the test suite uses.
    pub fn times(factor: f64) -> Size {
        Size {
            cone_particles: 3e5 * factor,
            direction_draws: (2e5 * factor) as u64,
            rebound_particles: 2e4 * factor,
            rebounds: (1e5 * factor) as u64,
            curved_particles: 1e5 * factor,
            epoch_seeds: ((1.2 * factor).round() as u64).max(8),
            paint_rate: 500.0 * factor,
            impaction_droplets: (120.0 * factor).round().max(1.0) as usize,
        }
    }
}

/// χ² limit for `dof` degrees of freedom: the mean plus five standard deviations, a false
/// alarm about once in 10⁵ runs for the sizes here.
pub fn chi2_limit(dof: usize) -> f64 {
    dof as f64 + 5.0 * (2.0 * dof as f64).sqrt()
}

/// Runs every check at `size` on `threads` threads (0: every core), announcing each by name.
pub fn report(size: Size, threads: usize, mut progress: impl FnMut(&str)) -> Report {
    let mut w = Writer::default();
    progress("cone law");
    cone_section(&mut w, size, threads);
    progress("direction laws");
    direction_section(&mut w, size);
    progress("ballistic flight");
    ballistics_section(&mut w);
    progress("rebound fraction");
    rebound_section(&mut w, size, threads);
    progress("shotcrete rebound against orientation");
    shotcrete_report::orientation_section(&mut w, threads);
    progress("cushion effect");
    shotcrete_report::cushion_section(&mut w, threads);
    progress("slump");
    shotcrete_report::slump_section(&mut w);
    progress("curved targets");
    targets_report::curved_section(&mut w, size.curved_particles, threads);
    progress("restitution and scatter");
    restitution_section(&mut w, size);
    progress("conservation");
    conservation_section(&mut w, threads);
    progress("layer epochs");
    epoch_section(&mut w, size, threads);
    progress("droplets in the gun's air");
    painting_report::drag_section(&mut w);
    painting_report::impaction_section(&mut w, size.impaction_droplets);
    progress("paint guns");
    painting_report::guns_section(&mut w, size.paint_rate, threads);

    let mut md = String::from(
        "# Validation report\n\nWritten by `spraysim validate --output docs` (the same command regenerates \
         this page and its plots, bit for bit). Each check runs the engine, or the model it names, on a \
         problem with a closed-form answer, at ten times the size the test suite uses; the test suite runs \
         the same experiments with the same criteria. χ² limits are the mean plus five standard deviations \
         (a false alarm about once in 10⁵ runs); binomial limits are 4.5 standard deviations.\n\n\
         | check | measured | criterion | result |\n|---|---|---|---|\n",
    );
    for v in &w.verdicts {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} |",
            v.name,
            v.statistic,
            v.criterion,
            if v.passed { "pass" } else { "**FAIL**" }
        );
    }
    md.push_str(&w.body);
    Report { markdown: md, charts: w.charts, verdicts: w.verdicts }
}

fn cone_section(w: &mut Writer, size: Size, threads: usize) {
    let c = cone_law("uniform_solid_angle", size.cone_particles, threads);
    let wrong = cone_law("uniform_polar", size.cone_particles, threads);
    w.section(
        "Deposition under a cone: the cos³ law",
        &format!(
            "A point nozzle {h} m above a plane, no gravity, emitting uniformly over the solid angle of a cone of \
             half-angle θc = {deg:.0}°, every particle sticking. The stuck thickness at radius r is \
             t(r) = V cos³θ / (2π (1 − cos θc) h²) with θ = atan(r/h) and V the stuck volume. The simulated layer \
             is averaged over 2 cm annuli and compared with the law averaged over the same cells; each annulus \
             has the Poisson error of the particles it expects. {n} particles.",
            h = c.height,
            deg = c.half_angle.to_degrees(),
            n = c.emitted
        ),
    );
    let dof = c.radii.len();
    let rows: Vec<Vec<String>> = (0..dof)
        .map(|k| {
            vec![
                format!("{:.0}", c.radii[k] * 1e3),
                format!("{:.4}", c.simulated[k] * 1e3),
                format!("{:.4}", c.closed_form[k] * 1e3),
                format!("{:+.2}", (c.simulated[k] - c.closed_form[k]) / c.sigma[k]),
            ]
        })
        .collect();
    w.table(&["r [mm]", "simulated [mm]", "closed form [mm]", "difference [σ]"], &rows);
    let mm = |x: &[f64]| c.radii.iter().zip(x).map(|(r, t)| (r * 1e3, t * 1e3)).collect();
    w.chart(
        "cone_law",
        Chart {
            title: "thickness under a uniform cone (no gravity)".into(),
            x_label: "radius [mm]".into(),
            y_label: "thickness [mm]".into(),
            series: vec![
                Series::new("closed form V cos³θ / (2π (1 − cos θc) h²)", mm(&c.closed_form), Mark::Line),
                Series::new("simulated (annulus means)", mm(&c.simulated), Mark::Points),
            ],
            legend: Legend::UpperRight,
        },
    );
    let limit = chi2_limit(dof);
    w.verdict(
        "cone law, shape",
        format!("χ² = {:.1} over {dof} annuli", c.chi2),
        format!("< {limit:.1}"),
        c.chi2 < limit,
    );
    let rel = (c.volumes.1 - c.volumes.0).abs() / c.volumes.0;
    w.verdict(
        "cone law, absolute volume",
        format!("{} of {} particles stuck, volume error {rel:.1e}", c.stuck, c.emitted),
        "all stuck, ≤ 1e-12".into(),
        c.stuck == c.emitted && rel <= 1e-12,
    );
    w.verdict(
        "cone law rejects a wrong law",
        format!("χ² = {:.0} for uniform-in-polar-angle emission", wrong.chi2),
        format!("> 10 × {limit:.1}"),
        wrong.chi2 > 10.0 * limit,
    );
}

/// A direction law's probability of a bin `[a, b)` of θ/θ_half.
type BinProbability = Box<dyn Fn(f64, f64) -> f64>;

fn direction_section(w: &mut Writer, size: Size) {
    w.section(
        "Direction laws",
        &format!(
            "Emission directions from a 7° half-angle cone, {} draws per law, binned by s = θ/θ_half into 20 bins \
             and compared with each law's probability per bin: truncated normal Φ((b−μ)/σ) − Φ((a−μ)/σ) over its \
             mass in [0, 1]; uniform polar b − a; uniform solid angle (cos aθc − cos bθc)/(1 − cos θc).",
            size.direction_draws
        ),
    );
    let half = 7f64.to_radians();
    let laws: [(&str, &str, Direction, BinProbability); 3] = [
        (
            "truncated normal, μ = 0.255, σ = 0.102",
            "direction_truncated_normal",
            Direction::TruncatedNormal { mu: 0.255, sigma: 0.102 },
            Box::new(truncated_normal_bin(0.255, 0.102)),
        ),
        (
            "uniform polar",
            "direction_uniform_polar",
            Direction::UniformPolar,
            Box::new(|a: f64, b: f64| b - a),
        ),
        (
            "uniform solid angle",
            "direction_uniform_solid_angle",
            Direction::UniformSolidAngle,
            Box::new(solid_angle_bin(half)),
        ),
    ];
    let limit = chi2_limit(19);
    for (name, stem, law, p) in laws {
        let h = direction_histogram(law, half, size.direction_draws, p);
        let n = size.direction_draws as f64;
        let width = 1.0 / 20.0;
        let mids = h.edges.windows(2).map(|e| 0.5 * (e[0] + e[1]));
        w.chart(
            stem,
            Chart {
                title: format!("direction law: {name}"),
                x_label: "s = θ / θ_half".into(),
                y_label: "probability density".into(),
                series: vec![
                    Series::new(
                        "closed form",
                        mids.clone().zip(&h.expected).map(|(s, e)| (s, e / n / width)).collect(),
                        Mark::Line,
                    ),
                    Series::new(
                        "sampled",
                        mids.zip(&h.counts).map(|(s, &c)| (s, c as f64 / n / width)).collect(),
                        Mark::Points,
                    ),
                ],
                legend: Legend::UpperRight,
            },
        );
        w.verdict(
            &format!("direction law: {name}"),
            format!("χ² = {:.1} over 20 bins", h.chi2),
            format!("< {limit:.1}"),
            h.chi2 < limit,
        );
    }
}

fn ballistics_section(w: &mut Writer) {
    let exact = landing_x_closed_form();
    w.section(
        "Ballistic flight",
        &format!(
            "One particle shot horizontally at 7 m/s from 1.2 m onto a floor lands at x = v √(2h/g) = {exact:.9} m. \
             Forward and semi-implicit Euler must converge at first order (halving Δt halves the error: an \
             observed order log₂(e(2Δt)/e(Δt)) near 1); the exact integrator must agree to rounding at every Δt. \
             Errors of exactly zero are drawn at 10⁻¹⁶. For a horizontal shot the two Euler schemes err by the same \
             amount in opposite directions, so their curves coincide."
        ),
    );
    let dts: Vec<f64> = (0..7).map(|k| 8e-3 / f64::from(1 << k)).collect();
    let schemes = [
        ("forward Euler", Integrator::Euler),
        ("semi-implicit Euler", Integrator::SemiImplicitEuler),
        ("exact", Integrator::Exact),
    ];
    let errors: Vec<Vec<f64>> = schemes
        .iter()
        .map(|&(_, s)| dts.iter().map(|&dt| (landing_x(dt, s) - exact).abs()).collect())
        .collect();
    ballistics_table(w, &dts, &errors);
    let series = schemes
        .iter()
        .zip(&errors)
        .map(|(&(name, _), e)| {
            Series::new(
                name,
                dts.iter().zip(e).map(|(dt, x)| (dt.log10(), x.max(1e-16).log10())).collect(),
                Mark::LinePoints,
            )
        })
        .collect();
    w.chart(
        "ballistics",
        Chart {
            title: "landing-point error against time step".into(),
            x_label: "log₁₀ Δt [s]".into(),
            y_label: "log₁₀ |x − x_exact| [m]".into(),
            series,
            legend: Legend::MiddleRight,
        },
    );
    for (k, &(name, _)) in schemes[..2].iter().enumerate() {
        let orders: Vec<f64> = errors[k].windows(2).map(|p| (p[0] / p[1]).log2()).collect();
        let (lo, hi) =
            orders.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &o| (a.min(o), b.max(o)));
        w.verdict(
            &format!("{name}, order of convergence"),
            format!("observed order {lo:.2} to {hi:.2}"),
            "within 0.68 to 1.32 (error ratio 1.6 to 2.5 per halving)".into(),
            lo > 0.68 && hi < 1.32,
        );
    }
    let worst = errors[2].iter().copied().fold(0.0, f64::max);
    w.verdict(
        "exact integrator",
        format!("largest error {worst:.1e} m over Δt from 6e-5 to 8e-3 s"),
        "< 1e-12 m".into(),
        worst < 1e-12,
    );
}

/// The landing errors per time step and scheme (Euler, semi-implicit, exact), with the
/// observed orders of the two Euler schemes.
fn ballistics_table(w: &mut Writer, dts: &[f64], errors: &[Vec<f64>]) {
    let rows: Vec<Vec<String>> = dts
        .iter()
        .enumerate()
        .map(|(i, dt)| {
            let mut row = vec![format!("{dt:.3e}")];
            for e in errors {
                row.push(format!("{:.3e}", e[i]));
            }
            for e in &errors[..2] {
                row.push(if i == 0 { "".into() } else { format!("{:.2}", (e[i - 1] / e[i]).log2()) });
            }
            row
        })
        .collect();
    w.table(
        &[
            "Δt [s]",
            "error, Euler [m]",
            "error, semi-implicit [m]",
            "error, exact [m]",
            "order, Euler",
            "order, semi-implicit",
        ],
        &rows,
    );
}

fn rebound_section(w: &mut Writer, size: Size, threads: usize) {
    w.section(
        "Rebound fraction against impact angle",
        &format!(
            "A straight-down jet onto a shotcrete plate tilted by θ, so that gravity acts along the flight path and \
             every impact is at exactly θ from the normal; {:.0} particles per angle, with α = 1 and with α = 0.5, \
             each run with its own seed. The share that rebounds at its first impact (the bounce ratio) must match \
             α · p_r(θ), with p_r(θ) = 0.10 + 2.4 (θ/90°)³ the shotcrete field curve (`rebound_model = \"polynomial\"`, \
             clamped to [0, 1]), within 4.5 binomial standard deviations at every angle.",
            size.rebound_particles
        ),
    );
    let angles: Vec<f64> = (0..=16).map(|k| 5.0 * f64::from(k)).collect();
    let mut rows = Vec::new();
    let mut series = Vec::new();
    let (mut worst, mut all_conserved) = (0.0_f64, true);
    for alpha in [1.0, 0.5] {
        // A seed per run, so that the runs are independent samples.
        let runs: Vec<ReboundFraction> = angles
            .iter()
            .map(|&t| rebound_fraction(t, alpha, size.rebound_particles, seed_of(t, alpha), threads))
            .collect();
        for r in &runs {
            let sd = (r.expected * (1.0 - r.expected) / r.n as f64).sqrt();
            let z = if sd > 0.0 { (r.measured - r.expected) / sd } else { 0.0 };
            worst = worst.max(z.abs());
            all_conserved &= r.conserved;
            rows.push(vec![
                format!("{:.0}", r.theta_deg),
                format!("{alpha}"),
                format!("{:.4}", r.measured),
                format!("{:.4}", r.expected),
                format!("{z:+.2}"),
            ]);
        }
        let fine: Vec<(f64, f64)> = (0..=85)
            .map(|t| (f64::from(t), (alpha * shotcrete_rebound_probability(f64::from(t))).clamp(0.0, 1.0)))
            .collect();
        series.push(Series::new(format!("α · p_r(θ), α = {alpha}"), fine, Mark::Line));
        series.push(Series::new(
            format!("simulated, α = {alpha}"),
            runs.iter().map(|r| (r.theta_deg, r.measured)).collect(),
            Mark::Points,
        ));
    }
    w.table(&["θ [°]", "α", "bounce ratio", "α · p_r(θ)", "difference [σ]"], &rows);
    w.chart(
        "rebound_fraction",
        Chart {
            title: "rebound fraction against impact angle (shotcrete)".into(),
            x_label: "impact angle from the normal θ [°]".into(),
            y_label: "rebound fraction".into(),
            series,
            legend: Legend::UpperLeft,
        },
    );
    w.verdict(
        "rebound fraction α · p_r(θ)",
        format!("largest deviation {worst:.2} σ over {} runs", rows.len()),
        "< 4.5 σ, and every run conserves its particles".into(),
        worst < 4.5 && all_conserved,
    );
}

/// A distinct seed for each (angle, α) run.
fn seed_of(theta_deg: f64, alpha: f64) -> u64 {
    1000 * (10.0 * alpha).round() as u64 + theta_deg.round() as u64
}

fn restitution_section(w: &mut Writer, size: Size) {
    let scatter = 30f64.to_radians();
    w.section(
        "Restitution and scatter",
        &format!(
            "Forced rebounds at normal incidence through the impact model, {} per restitution factor e, with a \
             scatter cone of half-angle 30°. The rebound speed must be e times the impact speed; the scattered \
             direction must be uniform over the cone's solid angle, so u = (1 − cos ψ)/(1 − cos 30°) is uniform \
             on [0, 1] (ψ from the specular direction) and ψ never exceeds 30°.",
            size.rebounds
        ),
    );
    let limit = chi2_limit(19);
    let mut rows = Vec::new();
    let mut ok = true;
    let mut series = vec![Series::new("uniform over the cone", vec![(0.0, 1.0), (1.0, 1.0)], Mark::Line)];
    for e in [0.3, 0.5, 0.7, 0.9] {
        let r = restitution(e, scatter, size.rebounds);
        ok &= (r.speed_ratio - e).abs() < 1e-9 && r.scatter_chi2 < limit && r.max_scatter <= scatter + 1e-12;
        rows.push(vec![
            format!("{e}"),
            format!("{:.12}", r.speed_ratio),
            format!("{:.1}", r.scatter_chi2),
            format!("{:.3}", r.max_scatter.to_degrees()),
        ]);
        if e == 0.5 {
            let n = size.rebounds as f64 / 20.0;
            series.push(Series::new(
                "sampled, e = 0.5",
                r.scatter_counts
                    .iter()
                    .enumerate()
                    .map(|(i, &c)| ((i as f64 + 0.5) / 20.0, c as f64 / n))
                    .collect(),
                Mark::Points,
            ));
        }
    }
    w.table(&["e", "mean rebound speed / impact speed", "scatter χ² (20 bins)", "largest ψ [°]"], &rows);
    w.chart(
        "scatter",
        Chart {
            title: "scatter directions over the 30° cone".into(),
            x_label: "u = (1 − cos ψ) / (1 − cos 30°)".into(),
            y_label: "probability density".into(),
            series,
            legend: Legend::MiddleRight,
        },
    );
    w.verdict(
        "restitution and scatter",
        "speed ratio, χ² and largest ψ as tabled".into(),
        format!("speed ratio = e to 1e-9, χ² < {limit:.1}, ψ ≤ 30°"),
        ok,
    );
}

fn epoch_section(w: &mut Writer, size: Size, threads: usize) {
    use epochs::{EPOCHS, Plan, TOLERANCE_OF_SCATTER, compare_all, figures};
    let plan = Plan { seeds: size.epoch_seeds, shot: 2.0, blast: 0.3 };
    let default = spraysim_scenario::DEFAULT_LAYER_EPOCH;
    let runs: Vec<_> = EPOCHS.iter().map(|&e| figures(&plan, e, threads)).collect();
    let reference = &runs[0];
    let comparisons: Vec<_> = runs[1..].iter().map(|r| compare_all(reference, r)).collect();
    // The longest epoch length up to which every length passes.
    let longest = comparisons.iter().take_while(|c| c.iter().all(|c| c.passed)).count();
    w.section(
        "Layer epochs",
        &format!(
            "Particles see every deposit surface as it stood at the start of a layer epoch, and what lands takes \
             effect at its end (`[simulation] layer_epoch`, {ms} ms by default). Three scenes (the default static \
             shot, where the layer grows fastest, 25 mm/s at the spot's centre, so 0.13 mm in a default epoch; a \
             ceiling sprayed until it fails; grit blasting a thin coat) run on {seeds} seeds at each epoch length, the \
             reference being one step (1 ms). The same seed draws the same random numbers at every length, so the \
             shift of a figure from the reference, seed by seed, is the epoch's effect. A figure passes when its \
             mean shift plus two standard errors is at most {tol} of its seed-to-seed standard deviation (plus one \
             epoch for a failure time): a shift a user would need about 16 runs of each kind to tell from noise. The \
             table gives each figure's reference mean ± its seed-to-seed standard deviation, then, per epoch \
             length, the mean shift ± its standard error, marked ✗ where it does not pass. The effect grows in \
             proportion to the epoch (a thinner cushion under the impacts of the static shot: a little more \
             rebound). Every figure passes up to {longest} ms, and the default lies within that.",
            ms = 1e3 * default,
            seeds = plan.seeds,
            tol = TOLERANCE_OF_SCATTER,
            longest = 1e3 * EPOCHS[longest],
        ),
    );
    let all_figures: Vec<_> = reference.figures.iter().chain(&reference.profile).collect();
    let mut header = vec!["figure".to_string(), "1 ms (one step)".to_string()];
    header.extend(EPOCHS[1..].iter().map(|e| format!("{:.0} ms", 1e3 * e)));
    let rows: Vec<Vec<String>> = all_figures
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let unit = if f.unit.is_empty() { String::new() } else { format!(" [{}]", f.unit) };
            let scatter = f.standard_error() * (f.values.len() as f64).sqrt();
            let mut row = vec![format!("{}{unit}", f.name), format!("{} ± {}", sig(f.mean()), sig(scatter))];
            row.extend(comparisons.iter().map(|c| {
                let c = &c[k];
                format!("{:+.3} ± {:.3}{}", c.shift, c.shift_error, if c.passed { "" } else { " ✗" })
            }));
            row
        })
        .collect();
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    w.table(&header, &rows);
    let at_default = EPOCHS.iter().position(|&e| (e - default).abs() < 1e-12).map_or(0, |i| i - 1);
    let worst = comparisons[at_default]
        .iter()
        .map(|c| (c.shift.abs() + 2.0 * c.shift_error) / c.tolerance.max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max);
    w.verdict(
        &format!("layer epoch of {:.0} ms (the default) against one step", 1e3 * default),
        format!("largest (|shift| + 2 SE) / tolerance over {} figures: {worst:.2}", all_figures.len()),
        "at most 1 for every figure".into(),
        comparisons[at_default].iter().all(|c| c.passed),
    );
}

/// `x` with four significant figures, for a table.
fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let digits = (3 - x.abs().log10().floor() as i32).max(0) as usize;
    format!("{x:.digits$}")
}

fn conservation_section(w: &mut Writer, threads: usize) {
    w.section(
        "Conservation of material",
        "Every emitted particle must end in exactly one fate (stuck on a target or obstacle, left the domain, \
         expired, or still in flight), by count exactly and by volume to rounding; through cohesive failure, the \
         volume balance (material on targets and obstacles, fallen, lost and in flight against emitted, with \
         failed material followed as released particles) must close to 10⁻⁶.",
    );
    let scenes = [
        ("default scene (shotcrete)", spraysim_scenario::Scenario::default_scene()),
        ("painting panel", panel_scene("painting", 0.3, "")),
        ("blasting panel", panel_scene("blasting", 0.3, "")),
        ("shotcrete panel", panel_scene("shotcrete", 0.3, "")),
        ("shotcrete ceiling, failing", failing_ceiling(8.0)),
    ];
    let mut rows = Vec::new();
    let mut ok = true;
    let mut failures = 0;
    for (name, sc) in scenes {
        let b = balance(name, &sc, threads);
        ok &= b.in_fates == b.emitted && b.fate_volume_error <= 1e-12 && b.balance_residual <= 1e-6;
        failures += b.failures;
        rows.push(vec![
            b.name.clone(),
            b.emitted.to_string(),
            b.in_fates.to_string(),
            format!("{:.1e}", b.fate_volume_error),
            format!("{:.1e}", b.balance_residual),
            b.failures.to_string(),
            format!("{:.3e}", b.released),
        ]);
    }
    w.table(
        &[
            "scene",
            "emitted",
            "in fates",
            "fate volume error",
            "balance residual",
            "failure events",
            "released [m³]",
        ],
        &rows,
    );
    w.verdict(
        "conservation",
        format!("{} scenes, {failures} failure events", rows.len()),
        "counts equal, volume error ≤ 1e-12, balance residual ≤ 1e-6, at least one failure".into(),
        ok && failures > 0,
    );
}
