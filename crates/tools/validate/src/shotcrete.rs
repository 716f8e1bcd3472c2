//! Shotcrete against the field: rebound on floors, walls and overheads as ACI 506R reports it,
//! the cushion effect of a static shot, and the slump of a fresh layer against Nye's heap and
//! the wall limit.

use glam::DVec3;
use spraysim_engine::collision::Face;
use spraysim_engine::deposit::{DepositSurface, RectangleSurface};
use spraysim_engine::motion::GRAVITY;
use spraysim_engine::process::layer::relax;
use spraysim_scenario::scenes::scenario;
use spraysim_scenario::{CushionLaw, Preset, ProcessParams, ReboundParams, Scenario};
use std::f64::consts::PI;

/// ACI 506R's typical rebound of wet-mix shotcrete, as shares: floors, walls, overheads.
pub const ACI_WET_MIX: [(f64, [f64; 2]); 3] =
    [(0.0, [0.0, 0.05]), (90.0, [0.05, 0.10]), (180.0, [0.10, 0.20])];

/// The shotcrete preset's process.
fn shotcrete() -> ProcessParams {
    Preset::Shotcrete.resolved_process()
}

/// The thickest fresh layer the shotcrete preset holds on a face whose normal is `angle_deg`
/// from straight up (0 a floor, 90 a wall, 180 overhead), m: pull-off overhead (tensile
/// strength f_t) and shear along the face (yield stress τ_y) together,
/// h = 1 / (ρ g √[(max(0, −cos φ)/f_t)² + (sin φ/τ_y)²]); infinite on a floor.
pub fn layer_capacity(angle_deg: f64) -> f64 {
    let p = shotcrete();
    let phi = angle_deg.to_radians();
    let pull = (-phi.cos()).max(0.0) / p.cohesion.tensile_strength;
    let shear = phi.sin().abs() / p.slump.yield_stress;
    let weight = p.density * GRAVITY.length();
    1.0 / (weight * pull.hypot(shear))
}

/// The thickness of one application when `design` m is built in as few equal applications as
/// the layer's capacity at `angle_deg` allows (each on a stiffened base), m.
pub fn application_thickness(angle_deg: f64, design: f64) -> f64 {
    let n = (design / layer_capacity(angle_deg)).ceil().max(1.0);
    design / n
}

/// Closed form of the capture law alone (no gravity, square on): the share of the mix lost while
/// a layer builds evenly from bare substrate to `thickness` m, (1/T) ∫₀ᵀ f S(h/κ) dh, with f the
/// aggregate fraction, κ the capture ratio and S(d) the share of the aggregate coarser than d
/// (the preset's grading, log-linear between sieves).
pub fn uniform_build_loss(thickness: f64) -> f64 {
    let ReboundParams::Cushion(CushionLaw { aggregate_fraction, grading, capture_ratio, .. }) =
        shotcrete().impact.rebound
    else {
        return f64::NAN;
    };
    let coarser = |d: f64| {
        let finer = match grading.iter().position(|g| g[0] >= d) {
            Some(0) => 0.0,
            None => 1.0,
            Some(k) => {
                let ([d0, s0], [d1, s1]) = (grading[k - 1], grading[k]);
                s0 + (s1 - s0) * (d / d0).ln() / (d1 / d0).ln()
            }
        };
        1.0 - finer
    };
    // Midpoint rule: S is smooth between sieves, so 10⁴ points give five digits.
    let n = 10_000;
    let sum: f64 = (0..n).map(|k| coarser((k as f64 + 0.5) / n as f64 * thickness / capture_ratio)).sum();
    aggregate_fraction * sum / n as f64
}

/// The square panel of the practice scenario, m.
pub const PANEL: f64 = 0.6;

/// The practice scenario on a face whose normal is `angle_deg` from straight up: a 0.6 m panel
/// sprayed edge to edge with the shotcrete preset by a square-on raster `standoff` m away
/// (passes 50 mm apart, overrunning the panel by the spray's footprint so that every point
/// builds from bare substrate to the same thickness), at the travel speed that builds
/// `thickness` m in one application; `spawn_rate` particles/s. A face that looks up is a slab in
/// formwork (its edges hold the layer); walls and overheads have free edges.
pub fn practice_panel(angle_deg: f64, standoff: f64, thickness: f64, spawn_rate: f64) -> Scenario {
    let phi = angle_deg.to_radians();
    let normal = [-phi.sin(), 0.0, phi.cos()];
    let p = shotcrete();
    let step = 0.05;
    // The footprint reaches the cone's half-angle (7°) plus the 50 mm aperture's radius.
    let margin = standoff * 7f64.to_radians().tan() + 0.05;
    let size = ((PANEL + 2.0 * margin) / step).ceil() * step;
    let speed = p.flow_rate * (1.0 - uniform_build_loss(thickness)) / (thickness * step);
    let edges = if angle_deg < 90.0 { "held" } else { "free" };
    let text = format!(
        r#"
        [simulation]
        duration = 1.0
        [emitter]
        spawn_rate = {spawn_rate}
        [nozzle.raster]
        target = "panel"
        size = [{size}, {size}]
        standoff = {standoff}
        speed = {speed}
        step_over = {step}
        lead = 0.1
        [[target]]
        name = "panel"
        center = [0.0, 0.0, 1.5]
        normal = {normal:?}
        up = [0.0, 1.0, 0.0]
        size = [{PANEL}, {PANEL}]
        resolution = [150, 150]
        splat_radius = 0.01
        edges = "{edges}"
        [domain]
        min = [-4.0, -4.0, -4.0]
        max = [4.0, 4.0, 6.0]
        "#
    );
    let sc = scenario(&text, "practice panel");
    // Until the raster ends, and a second for the last rebounds to land or leave.
    let end = sc.path_end() + 1.0;
    sc.with("simulation.duration", end).unwrap_or_else(|e| panic!("built-in scene: {e}"))
}

/// What one practice run lost.
#[derive(Clone, Copy, Debug)]
pub struct PracticeRun {
    /// The face's normal from straight up, degrees.
    pub angle_deg: f64,
    /// Nozzle standoff, m.
    pub standoff: f64,
    /// Thickness of the application, m.
    pub thickness: f64,
    /// Rebound as ACI counts it: the share of the delivered volume not in place.
    pub loss: f64,
    /// Particles delivered to the panel.
    pub delivered: u64,
    /// Share of the delivered volume that bounced at its first impact.
    pub bounce: f64,
    /// Share that rebounded and was trapped in the layer.
    pub trapped: f64,
    /// Share that fell off or ran off.
    pub fell: f64,
}

impl PracticeRun {
    /// Binomial standard deviation of `loss`.
    pub fn sigma(&self) -> f64 {
        (self.loss * (1.0 - self.loss) / self.delivered.max(1) as f64).sqrt()
    }
}

/// Builds a `design` m layer in the practice scenario at `angle_deg` and `standoff` (one
/// application of [`application_thickness`]) and measures its loss.
pub fn practice_run(
    angle_deg: f64,
    standoff: f64,
    design: f64,
    spawn_rate: f64,
    threads: usize,
) -> PracticeRun {
    let thickness = application_thickness(angle_deg, design);
    let sc = practice_panel(angle_deg, standoff, thickness, spawn_rate);
    let m = super::checks::run(&sc, threads).metrics();
    let t = &m.targets[0];
    let delivered = t.delivered.volume.max(f64::MIN_POSITIVE);
    PracticeRun {
        angle_deg,
        standoff,
        thickness,
        loss: t.rebound_ratio.unwrap_or(f64::NAN),
        delivered: t.delivered.count,
        bounce: m.bounce_ratio.unwrap_or(f64::NAN),
        trapped: t.trapped.volume / delivered,
        fell: t.detached.volume / delivered,
    }
}

/// A static shot: the shotcrete preset's nozzle held still `standoff` m square onto the middle
/// of a 2 m × 2 m face whose normal is `angle_deg` from straight up, for `duration` s.
pub fn static_shot(angle_deg: f64, standoff: f64, duration: f64) -> Scenario {
    let phi = angle_deg.to_radians();
    let normal = DVec3::new(-phi.sin(), 0.0, phi.cos());
    let centre = DVec3::new(0.0, 0.0, 1.5);
    let nozzle = centre + normal * standoff;
    let text = format!(
        r#"
        [simulation]
        duration = {duration}
        [nozzle]
        position = {:?}
        axis = {:?}
        [[target]]
        name = "face"
        center = {:?}
        normal = {:?}
        up = [0.0, 1.0, 0.0]
        size = [2.0, 2.0]
        resolution = [500, 500]
        splat_radius = 0.01
        [domain]
        min = [-4.0, -4.0, -4.0]
        max = [4.0, 4.0, 6.0]
        "#,
        nozzle.to_array(),
        (-normal).to_array(),
        centre.to_array(),
        normal.to_array(),
    );
    scenario(&text, "static shot")
}

/// Rebound over a static shot, sampled as it goes.
#[derive(Clone, Debug, Default)]
pub struct CushionSeries {
    /// Sample times, s.
    pub times: Vec<f64>,
    /// Rebound (ACI) of everything delivered until each time.
    pub cumulative: Vec<f64>,
    /// Rebound of what was delivered since the previous sample: delivered minus in place, over
    /// delivered, both taken as differences.
    pub window: Vec<f64>,
    /// Particles delivered until each time.
    pub delivered: Vec<u64>,
}

/// Runs [`static_shot`] to the last of `times` (ascending, s) and samples its rebound.
pub fn cushion_series(angle_deg: f64, standoff: f64, times: &[f64], threads: usize) -> CushionSeries {
    let end = times.last().copied().unwrap_or(0.0);
    let sc = static_shot(angle_deg, standoff, end);
    let mut sim = sc.build().unwrap_or_else(|e| panic!("built-in scene: {e}"));
    let _ = sim.set_threads(threads);
    let mut out = CushionSeries::default();
    let (mut last_delivered, mut last_placed) = (0.0, 0.0);
    for &t in times {
        while sim.time() < t - 1e-9 && !sim.is_finished() {
            sim.step();
        }
        let m = sim.metrics();
        let target = &m.targets[0];
        let (delivered, placed) = (target.delivered.volume, target.in_place);
        out.times.push(sim.time());
        out.cumulative.push(target.rebound_ratio.unwrap_or(f64::NAN));
        let fresh = delivered - last_delivered;
        out.window.push(if fresh > 0.0 { 1.0 - (placed - last_placed) / fresh } else { f64::NAN });
        out.delivered.push(target.delivered.count);
        (last_delivered, last_placed) = (delivered, placed);
    }
    out
}

/// A column slumped into a heap on a floor, against Nye's plastic heap.
#[derive(Clone, Debug)]
pub struct NyeHeap {
    /// Annulus centres, m.
    pub radii: Vec<f64>,
    /// Mean thickness per annulus, m.
    pub simulated: Vec<f64>,
    /// Nye's h(r) = √(2a(R − r)) (a = τ_y/(ρ g)) averaged over the same cells, m.
    pub closed_form: Vec<f64>,
    /// Peak thickness, simulated and Nye's, m.
    pub peak: (f64, f64),
    /// Volume after, relative to before, minus one.
    pub volume_error: f64,
    /// Largest basal stress over yield stress on any edge after.
    pub worst_stress_ratio: f64,
}

/// Half a litre stacked in a column of 20 mm radius on a 0.4 m floor of `cell` m cells,
/// relaxed by the slump stage with the shotcrete preset's yield stress until it settles.
pub fn nye_heap(cell: f64) -> NyeHeap {
    let p = shotcrete();
    let (rho, tau, g) = (p.density, p.slump.yield_stress, GRAVITY);
    let n = (0.4 / cell).round() as usize;
    let face = Face::new(DVec3::ZERO, DVec3::Z, DVec3::Y, [0.4, 0.4]);
    let mut floor = RectangleSurface::new(face, n, n, 0.0);
    let cells = floor.thickness().len() as u32;
    let column: Vec<u32> = (0..cells).filter(|&c| floor.point_above(c, 0.0).length() <= 0.02).collect();
    let volume = 5e-4;
    let h0 = volume / floor.area_of(&column);
    column.iter().for_each(|&c| floor.add_thickness(c, h0));
    // Ample sweeps: the column settles in a few hundred.
    relax(&mut floor, rho, g, tau, 1_000_000);
    let a = tau / (rho * g.length());
    let radius = (15.0 * volume / (8.0 * PI * (2.0 * a).sqrt())).powf(0.4);
    let nye = |r: f64| (2.0 * a * (radius - r).max(0.0)).sqrt();
    let width = 0.005;
    let bins = (0.08 / width) as usize;
    let (mut sim, mut cf, mut count) = (vec![0.0; bins], vec![0.0; bins], vec![0.0; bins]);
    for c in 0..cells {
        let r = floor.point_above(c, 0.0).length();
        let k = (r / width) as usize;
        if k < bins {
            sim[k] += floor.thickness()[c as usize];
            cf[k] += nye(r);
            count[k] += 1.0;
        }
    }
    let keep: Vec<usize> = (0..bins).filter(|&k| count[k] > 0.0).collect();
    let top = floor.thickness().iter().copied().fold(0.0, f64::max);
    NyeHeap {
        radii: keep.iter().map(|&k| (k as f64 + 0.5) * width).collect(),
        simulated: keep.iter().map(|&k| sim[k] / count[k]).collect(),
        closed_form: keep.iter().map(|&k| cf[k] / count[k]).collect(),
        peak: (top, nye(0.0)),
        volume_error: floor.volume() / volume - 1.0,
        worst_stress_ratio: worst_stress_ratio(&floor, rho, tau),
    }
}

/// The largest basal stress ρ g h Δe/ℓ over the yield stress on any edge between two cells of
/// `s`, e = z + max(n_z, 0) h the elevation of the layer's top (shallow-layer theory).
pub fn worst_stress_ratio(s: &RectangleSurface, rho: f64, tau: f64) -> f64 {
    let t = s.thickness();
    let lift = s.chart.normal.z.max(0.0);
    let g = GRAVITY.length();
    let mut worst = 0.0_f64;
    for i in 0..t.len() as u32 {
        let own = s.point_above(i, 0.0);
        s.stencil(i, &mut |k, centre| {
            if let Some(k) = k {
                let de = own.z + lift * t[i as usize] - centre.z - lift * t[k as usize];
                worst = worst.max(rho * g * t[i as usize] * de / centre.distance(own) / tau);
            }
        });
    }
    worst
}

/// A uniform layer `thickness` m thick on a 0.2 m wall of 4 mm cells, relaxed until it settles:
/// the largest thickness left and the volume that ran off the bottom edge, m and m³, with the
/// volume error (after plus run-off, relative to before, minus one).
pub fn wall_slump(thickness: f64) -> (f64, f64, f64) {
    let p = shotcrete();
    let face = Face::new(DVec3::ZERO, DVec3::X, DVec3::Z, [0.2, 0.2]);
    let mut wall = RectangleSurface::new(face, 50, 50, 0.0);
    (0..2500).for_each(|c| wall.add_thickness(c, thickness));
    let before = wall.volume();
    let r = relax(&mut wall, p.density, GRAVITY, p.slump.yield_stress, 1_000_000);
    let ran_off: f64 = r.run_off.iter().map(|o| o.volume).sum();
    let top = wall.thickness().iter().copied().fold(0.0, f64::max);
    (top, ran_off, (wall.volume() + ran_off) / before - 1.0)
}
