//! Layer epochs against epochs of one step: how every reported figure moves with the length of
//! the epoch over which particles see the layers as they stood at its start.
//!
//! Three test scenes, each run on several seeds at each epoch length:
//!
//! - **static shot**: the default scene (wet-mix shotcrete from a static nozzle square onto a
//!   wall, rebound caught by a floor), where the layer grows fastest (25 mm/s at the spot's
//!   centre): fates, the rebound, bounce and trapped ratios, the transfer efficiency, the cushion
//!   effect (the rebound of the second half of the shot, over a layer already built), the
//!   wall's thickness mean and CV, and its radial profile ring by ring;
//! - **failing ceiling** (see [`crate::checks::failing_ceiling`]): the time of the first
//!   cohesive failure and the volume that fell in it;
//! - **blasting**: grit at 20° onto a wall under a thin coat: the share of the coat cleaned and
//!   the mean depth worn into the steel.
//!
//! **The criterion.** The seeds are paired: the same seed at two epoch lengths draws the same
//! random numbers, so the difference of a figure between them is the epoch's effect, with
//! little noise. A particle sees the layer as it stood up to one epoch earlier, so the effect is
//! systematic, in proportion to the epoch: what matters is whether it is small against the
//! figure's own scatter, which a user sees between two runs of one set-up that differ only in
//! their seed. A figure passes when its mean shift, plus two standard errors of that mean (a
//! 97.5 % upper bound), is at most half its seed-to-seed standard deviation: a shift that a
//! user would need about 16 runs of each kind to tell from noise. A failure time may also move
//! by one epoch (a layer stage runs at the end of the epoch its interval ends in).

use spraysim_engine::deposit::DepositSurface;
use spraysim_engine::world::Target;
use spraysim_scenario::Scenario;
use spraysim_scenario::scenes::wall;

/// Epoch lengths compared, s: the first, one step of the scenes' 1 ms, is the reference.
pub const EPOCHS: [f64; 5] = [0.001, 0.002, 0.005, 0.010, 0.020];

/// Outer radii of the rings of the static shot's radial profile, m (each ring from the previous
/// radius, the first from 0).
pub const RINGS: [f64; 8] = [0.02, 0.04, 0.06, 0.08, 0.10, 0.12, 0.15, 0.20];

/// The rings of [`RINGS`], by name.
const RING_NAMES: [&str; 8] = [
    "shot: wall thickness, 0–20 mm from the centre",
    "shot: wall thickness, 20–40 mm",
    "shot: wall thickness, 40–60 mm",
    "shot: wall thickness, 60–80 mm",
    "shot: wall thickness, 80–100 mm",
    "shot: wall thickness, 100–120 mm",
    "shot: wall thickness, 120–150 mm",
    "shot: wall thickness, 150–200 mm",
];

/// Sizes of the comparison.
#[derive(Clone, Copy, Debug)]
pub struct Plan {
    /// Seeds per epoch length.
    pub seeds: u64,
    /// Length of the static shot, s.
    pub shot: f64,
    /// Length of the blasting run, s.
    pub blast: f64,
}

/// One figure of one epoch length: its value on each seed.
#[derive(Clone, Debug)]
pub struct Figure {
    /// What it is.
    pub name: &'static str,
    /// Its unit, for the report.
    pub unit: &'static str,
    /// Its value on each seed, in that unit.
    pub values: Vec<f64>,
    /// Beyond the statistical tolerance, how far it may move by construction, in its unit (the
    /// failure time: one epoch).
    pub allowance: f64,
}

impl Figure {
    /// Mean over the seeds.
    pub fn mean(&self) -> f64 {
        self.values.iter().sum::<f64>() / self.values.len().max(1) as f64
    }

    /// Standard error of the mean: the seeds' standard deviation over √n.
    pub fn standard_error(&self) -> f64 {
        let n = self.values.len() as f64;
        if n < 2.0 {
            return f64::NAN;
        }
        let m = self.mean();
        let var = self.values.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
        (var / n).sqrt()
    }
}

/// Every figure of one epoch length, and the static shot's ring means on each seed.
#[derive(Clone, Debug)]
pub struct EpochFigures {
    /// Epoch length, s.
    pub epoch: f64,
    /// The figures, in report order.
    pub figures: Vec<Figure>,
    /// Per ring of [`RINGS`], the mean thickness on each seed, m.
    pub profile: Vec<Figure>,
}

/// Share of a figure's seed-to-seed standard deviation its shift may reach: see the module's
/// docs.
pub const TOLERANCE_OF_SCATTER: f64 = 0.5;

/// How one figure of an epoch length compares with the reference, seed by seed.
#[derive(Clone, Debug)]
pub struct Comparison {
    /// Name of the figure compared, as in the report's table.
    pub name: &'static str,
    /// Mean shift from the reference over the seeds, in the figure's unit.
    pub shift: f64,
    /// Standard error of the mean shift.
    pub shift_error: f64,
    /// The shift allowed: [`TOLERANCE_OF_SCATTER`] of the reference's seed-to-seed standard
    /// deviation, plus the figure's allowance.
    pub tolerance: f64,
    /// Whether |shift| + 2 standard errors lies within the tolerance.
    pub passed: bool,
}

/// Compares one figure with its reference, seed by seed (both run on the same seeds).
pub fn compare(reference: &Figure, other: &Figure) -> Comparison {
    let shifts: Vec<f64> = reference.values.iter().zip(&other.values).map(|(a, b)| b - a).collect();
    let shift = Figure { name: other.name, unit: other.unit, values: shifts, allowance: 0.0 };
    let (mean, error) = (shift.mean(), shift.standard_error());
    let scatter = reference.standard_error() * (reference.values.len() as f64).sqrt();
    let tolerance = TOLERANCE_OF_SCATTER * scatter + other.allowance;
    // Identical on every seed: no shift, whatever the scatter.
    let passed = mean == 0.0 && error == 0.0 || mean.abs() + 2.0 * error <= tolerance;
    Comparison { name: other.name, shift: mean, shift_error: error, tolerance, passed }
}

/// Every figure of `other` (the static shot's rings included) compared with `reference`'s.
pub fn compare_all(reference: &EpochFigures, other: &EpochFigures) -> Vec<Comparison> {
    let figures = reference.figures.iter().zip(&other.figures);
    let rings = reference.profile.iter().zip(&other.profile);
    figures.chain(rings).map(|(a, b)| compare(a, b)).collect()
}

/// Runs every scene of `plan` at `epoch` (s), on `threads` threads (0: every core).
pub fn figures(plan: &Plan, epoch: f64, threads: usize) -> EpochFigures {
    let seeds: Vec<u64> = (1..=plan.seeds).collect();
    let mut figures = Vec::new();
    let mut profile = RINGS.iter().map(|_| Vec::new()).collect::<Vec<Vec<f64>>>();
    let mut shot: Vec<Vec<f64>> = vec![Vec::new(); SHOT.len()];
    let mut failure: Vec<Vec<f64>> = vec![Vec::new(); 2];
    let mut blast: Vec<Vec<f64>> = vec![Vec::new(); 2];
    for &seed in &seeds {
        let (values, rings) = static_shot(plan.shot, seed, epoch, threads);
        values.into_iter().zip(&mut shot).for_each(|(v, s)| s.push(v));
        rings.into_iter().zip(&mut profile).for_each(|(v, s)| s.push(v));
        failing_ceiling(seed, epoch, threads).into_iter().zip(&mut failure).for_each(|(v, s)| s.push(v));
        blasting(plan.blast, seed, epoch, threads).into_iter().zip(&mut blast).for_each(|(v, s)| s.push(v));
    }
    for ((name, unit), values) in SHOT.iter().zip(shot) {
        figures.push(Figure { name, unit, values, allowance: 0.0 });
    }
    figures.push(Figure {
        name: "ceiling: first failure",
        unit: "s",
        values: failure[0].clone(),
        allowance: epoch,
    });
    figures.push(Figure {
        name: "ceiling: volume of the first failure",
        unit: "cm³",
        values: failure[1].clone(),
        allowance: 0.0,
    });
    figures.push(Figure {
        name: "blasting: coat cleaned",
        unit: "%",
        values: blast[0].clone(),
        allowance: 0.0,
    });
    figures.push(Figure {
        name: "blasting: steel worn, mean",
        unit: "nm",
        values: blast[1].clone(),
        allowance: 0.0,
    });
    let profile = profile
        .into_iter()
        .zip(RING_NAMES)
        .map(|(values, name)| Figure { name, unit: "mm", values, allowance: 0.0 })
        .collect();
    EpochFigures { epoch, figures, profile }
}

/// The static shot's figures, by name and unit, in the order [`static_shot`] returns them.
const SHOT: [(&str, &str); 9] = [
    ("shot: stuck on targets", "%"),
    ("shot: still in flight", "%"),
    ("shot: rebound (ACI)", "%"),
    ("shot: bounced at first impact", "%"),
    ("shot: trapped rebound", "%"),
    ("shot: transfer efficiency", "%"),
    ("shot: rebound of the second half (cushion)", "%"),
    ("shot: wall thickness, mean", "µm"),
    ("shot: wall thickness, CV", ""),
];

/// The default scene for `duration` s at `seed` and `epoch` s: the figures of [`SHOT`] and the
/// wall's mean thickness in each ring of [`RINGS`] around the spot's centre, mm.
fn static_shot(duration: f64, seed: u64, epoch: f64, threads: usize) -> (Vec<f64>, Vec<f64>) {
    let sc = Scenario::default_scene()
        .with_all(&[
            ("simulation.duration".into(), duration.into()),
            ("simulation.seed".into(), (seed as i64).into()),
            ("simulation.layer_epoch".into(), epoch.into()),
        ])
        .unwrap_or_else(|e| panic!("built-in scene: {e}"));
    let mut sim = sc.build().unwrap_or_else(|e| panic!("built-in scene: {e}"));
    let _ = sim.set_threads(threads);
    // The first half, then the second: the cushion effect is the second half's rebound.
    sim.advance(sim.total_steps() / 2);
    let half = sim.metrics();
    sim.run(|_| {});
    let m = sim.metrics();
    let (w0, w1) = (&half.targets[0], &m.targets[0]);
    let fresh = w1.delivered.volume - w0.delivered.volume;
    let cushion = 1.0 - (w1.in_place - w0.in_place) / fresh;
    let pct = |x: f64| 100.0 * x;
    let share = |a: f64| pct(a / m.emitted.volume);
    let values = vec![
        share(m.fates.stuck_on_targets.volume),
        share(m.fates.in_flight.volume),
        pct(m.rebound_ratio.unwrap_or(f64::NAN)),
        pct(m.bounce_ratio.unwrap_or(f64::NAN)),
        pct(m.trapped_ratio.unwrap_or(f64::NAN)),
        pct(m.transfer_efficiency.unwrap_or(f64::NAN)),
        pct(cushion),
        1e6 * w1.thickness.mean,
        w1.thickness.cv,
    ];
    (values, rings(&sim.targets()[0]))
}

/// The mean thickness (mm) of `wall`'s cells in each ring of [`RINGS`] around the point of the
/// wall the default nozzle aims at.
fn rings(wall: &Target) -> Vec<f64> {
    let s = &wall.surface;
    let centre = glam::DVec3::new(0.0, 0.0, 1.0);
    let mut sums = vec![(0.0, 0.0); RINGS.len()];
    for (c, &t) in s.thickness().iter().enumerate() {
        let r = s.point_above(c as u32, 0.0).distance(centre);
        if let Some(k) = RINGS.iter().position(|&outer| r < outer) {
            let a = s.cell_area(c as u32);
            sums[k].0 += t * a;
            sums[k].1 += a;
        }
    }
    sums.into_iter().map(|(v, a)| 1e3 * v / a.max(f64::MIN_POSITIVE)).collect()
}

/// The failing ceiling at `seed` and `epoch` s, run until its first failure (or 8 s): the time
/// of that failure (s) and the volume that fell in it, cm³ (NaN and 0 when nothing fails).
fn failing_ceiling(seed: u64, epoch: f64, threads: usize) -> Vec<f64> {
    let sc = crate::checks::failing_ceiling(8.0)
        .with_all(&[
            ("simulation.seed".into(), (seed as i64).into()),
            ("simulation.layer_epoch".into(), epoch.into()),
        ])
        .unwrap_or_else(|e| panic!("built-in scene: {e}"));
    let mut sim = sc.build().unwrap_or_else(|e| panic!("built-in scene: {e}"));
    let _ = sim.set_threads(threads);
    while !sim.is_finished() && sim.failures().is_empty() {
        sim.advance(sim.steps_to_epoch_end());
    }
    let first = sim.failures().first();
    vec![first.map_or(f64::NAN, |e| e.time), first.map_or(0.0, |e| 1e6 * e.volume)]
}

/// Grit at 20° onto a wall under a 2 µm coat for `duration` s at `seed` and `epoch` s: the
/// share of the wall's area cleaned, %, and the mean depth worn into the steel, nm.
fn blasting(duration: f64, seed: u64, epoch: f64, threads: usize) -> Vec<f64> {
    let g = 20f64.to_radians();
    let text = format!(
        r#"
        [simulation]
        duration = {duration}
        seed = {seed}
        layer_epoch = {epoch}
        [process]
        preset = "blasting"
        [emitter]
        cone_angle = 15.0
        [nozzle]
        position = [{x}, 0.0, {z}]
        axis = [{ax}, 0.0, {az}]
        {wall}
        "#,
        wall = wall().size(1.0, 1.0).resolution(100, 100).coating(2e-6),
        x = -0.3 * g.sin(),
        z = 1.0 + 0.3 * g.cos(),
        ax = g.sin(),
        az = -g.cos(),
    );
    let sc = spraysim_scenario::scenes::scenario(&text, "blasting");
    let mut sim = sc.build().unwrap_or_else(|e| panic!("built-in scene: {e}"));
    let _ = sim.set_threads(threads);
    sim.run(|_| {});
    let m = sim.metrics();
    let e = m.targets[0].erosion.as_ref().unwrap_or_else(|| panic!("built-in scene: erosion on"));
    vec![100.0 * e.cleaned_fraction.unwrap_or(f64::NAN), 1e9 * e.substrate_mean_depth]
}
