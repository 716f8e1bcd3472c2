//! Run metrics: where every emitted particle ended, and how the layers came out. With the
//! `serde` feature, [`Metrics`] serializes to the layout of `metrics.json`.

use crate::deposit::DepositSurface;
use crate::events::FailureEvent;
use crate::particles::flags;
use crate::pipeline::Simulation;
use crate::tally::{Amount, Gauge, Quanta, Tallied};
use crate::world::{Role, Target};

/// Minimum, mean and maximum of a path quantity over the spraying time, and the share of that
/// time spent outside the recommended window (or with no substrate in front of the nozzle).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Range {
    /// Smallest value, in the quantity's unit (see [`PathMetrics`]).
    pub min: f64,
    /// Mean over the spraying time, in the quantity's unit.
    pub mean: f64,
    /// Largest value, in the quantity's unit.
    pub max: f64,
    /// Share of spraying time outside the window, 0..1.
    pub outside_share: f64,
}

/// Process quality along the nozzle's path (see `[process.window]`).
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct PathMetrics {
    /// Time spent spraying, s.
    pub spraying_time: f64,
    /// Share of spraying time with no substrate face along the spray axis, 0..1.
    pub off_target_share: f64,
    /// Standoff to the substrate along the spray axis, m.
    pub standoff: Option<Range>,
    /// Angle of the spray axis to the substrate's normal (0: square on), degrees.
    pub angle: Option<Range>,
    /// Travel speed along the path (without a superposed circle), m/s: judged against the
    /// window.
    pub travel_speed: Option<Range>,
    /// The nozzle's total speed, circle included, m/s (`outside_share` is 0: no window).
    pub nozzle_speed: Option<Range>,
}

/// Cohesive failures and what became of the released material.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FailureMetrics {
    /// Every failure, in time order.
    pub events: Vec<FailureEvent>,
    /// Particles released (one per failed, dripping or run-off cell) and their volume.
    pub released: Amount,
    /// Of those, what dripped off sagging films.
    pub dripped: Amount,
    /// Of those, what slumped over the edges of targets.
    pub ran_off: Amount,
    /// Where the released particles are now.
    pub released_fates: Fates,
}

/// Where the emitted volume is now, m³, from the deposit maps (Σ thickness × cell area) and
/// the fates: `residual` is what the other terms miss (rounding only: the fates are exact sums
/// of whole quanta, the maps sums of thicknesses), so a map that lost material shows here.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct VolumeBalance {
    /// Emitted by the nozzle, m³.
    pub emitted: f64,
    /// In the deposit maps of every target: Σ thickness × cell area.
    pub in_maps: f64,
    /// Stuck on the backs of targets, which have no map.
    pub on_backs: f64,
    /// Stuck on obstacles, m³.
    pub on_obstacles: f64,
    /// Carried out of the domain box after striking something, m³.
    pub left_domain: f64,
    /// Carried by particles retired in flight at the maximum lifetime after striking
    /// something, m³.
    pub expired: f64,
    /// Overspray: never struck a surface, and left the domain, expired or was carried off, m³.
    pub overspray: f64,
    /// In flight now (from the nozzle or released), m³.
    pub in_flight: f64,
    /// `emitted` minus the rest, m³: rounding only.
    pub residual: f64,
}

/// Where the emitted particles are: each in exactly one fate.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Fates {
    /// Stuck on a target (front or back).
    pub stuck_on_targets: Amount,
    /// Stuck on an obstacle.
    pub stuck_on_obstacles: Amount,
    /// Left the domain box after striking something.
    pub left_domain: Amount,
    /// Retired still in flight at the maximum lifetime after striking something.
    pub expired: Amount,
    /// Overspray: never struck a surface, and left flight by leaving the domain, expiring or
    /// drifting out of the gun's air into the booth's (see `motion.air.booth_speed`).
    pub overspray: Amount,
    /// Still in flight.
    pub in_flight: Amount,
}

impl Fates {
    /// Sum over all fates; equals the emitted amount.
    pub fn total(&self) -> Amount {
        self.stuck_on_targets
            + self.stuck_on_obstacles
            + self.left_domain
            + self.expired
            + self.overspray
            + self.in_flight
    }
}

/// Statistics of a target's thickness over its region of interest (the whole surface, or
/// what lies farther than a margin from its edges and openings), weighted by area.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ThicknessStats {
    /// Mean, m.
    pub mean: f64,
    /// Standard deviation, m.
    pub std_dev: f64,
    /// Coefficient of variation std_dev / mean (0 when the mean is 0).
    pub cv: f64,
    /// Minimum, m.
    pub min: f64,
    /// Maximum, m.
    pub max: f64,
    /// Coverage threshold, m.
    pub coverage_threshold: f64,
    /// Share of the area at or above the coverage threshold (and above 0), 0..1.
    pub covered_fraction: f64,
    /// Mean over the cells that hold material (thickness above 0), m: the layer where the
    /// spray reached, unlike `mean`, which spreads it over the whole region (0 when no cell
    /// holds any).
    pub deposited_mean: f64,
    /// Coefficient of variation over the cells that hold material, as `deposited_mean` is
    /// their mean: how even the layer is where the spray reached (0 when no cell holds any).
    pub deposited_cv: f64,
    /// Area the statistics cover, m².
    pub area: f64,
    /// Cells closer than this to an edge or opening are left out, m.
    pub margin: f64,
    /// The specified thickness band `[min, max]`, m, if one was given.
    pub tolerance: Option<[f64; 2]>,
    /// Share of the area whose thickness lies within the band ("in spec"), 0..1.
    pub in_tolerance: Option<f64>,
}

impl ThicknessStats {
    /// Statistics of `surface`'s thickness times `scale` (1 for the deposit itself, the
    /// volume solids for a dry film) over the cells farther than `margin` (m) from its edges,
    /// against the coverage `threshold` (m) and the `tolerance` band (m).
    pub fn of(
        surface: &impl DepositSurface,
        threshold: f64,
        margin: f64,
        tolerance: Option<[f64; 2]>,
        scale: f64,
    ) -> ThicknessStats {
        let t = surface.thickness();
        // Two passes over the cells, without a copy of them (a large grid's would cost more
        // than the sums); each sum runs in cell order, as one pass per figure would.
        let cells = || {
            (0..t.len() as u32)
                .filter(move |&c| margin <= 0.0 || surface.edge_distance(c) >= margin)
                .map(move |c| (t[c as usize] * scale, surface.cell_area(c)))
                .filter(|&(_, a)| a > 0.0)
        };
        let covered = |x: f64| x > 0.0 && x >= threshold;
        let within = |x: f64| tolerance.is_some_and(|[lo, hi]| (lo..=hi).contains(&x));
        let (mut area, mut weighted, mut on, mut inside, mut n) = (0.0, 0.0, 0.0, 0.0, 0_usize);
        let mut deposited = 0.0;
        let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
        for (x, a) in cells() {
            (area, weighted, n) = (area + a, weighted + x * a, n + 1);
            (min, max) = (min.min(x), max.max(x));
            on += if covered(x) { a } else { 0.0 };
            deposited += if x > 0.0 { a } else { 0.0 };
            inside += if within(x) { a } else { 0.0 };
        }
        let share = |part: f64| if area > 0.0 { part / area } else { 0.0 };
        let mean = share(weighted);
        let var = share(cells().map(|(x, a)| (x - mean).powi(2) * a).sum::<f64>());
        let std_dev = var.sqrt();
        let deposited_mean = if deposited > 0.0 { weighted / deposited } else { 0.0 };
        let deposited_var = if deposited > 0.0 {
            cells().filter(|&(x, _)| x > 0.0).map(|(x, a)| (x - deposited_mean).powi(2) * a).sum::<f64>()
                / deposited
        } else {
            0.0
        };
        let empty = n == 0;
        ThicknessStats {
            mean,
            std_dev,
            cv: if mean > 0.0 { std_dev / mean } else { 0.0 },
            min: if empty { 0.0 } else { min },
            max: if empty { 0.0 } else { max },
            coverage_threshold: threshold,
            covered_fraction: share(on),
            deposited_mean,
            deposited_cv: if deposited_mean > 0.0 { deposited_var.sqrt() / deposited_mean } else { 0.0 },
            area,
            margin,
            tolerance,
            in_tolerance: tolerance.map(|_| share(inside)),
        }
    }
}

/// Per-target metrics.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct TargetMetrics {
    /// The target's name in the scenario.
    pub name: String,
    /// Substrate (sprayed) or collector (catches what rebounds or falls).
    pub role: Role,
    /// Impacts, stuck or rebounded, either side.
    pub hits: u64,
    /// Stuck on the front, in the deposit (adhering or loose).
    pub stuck: Amount,
    /// Of those, the rebounds that came to rest loose: on the surface, not in place.
    pub loose: Amount,
    /// Of those, the rebounds that adhered where they landed again: in place, but as trapped
    /// rebound (ACI 506R: a defect on floors), not as sprayed material.
    pub trapped: Amount,
    /// Material delivered: particles whose first substrate impact was here.
    pub delivered: Amount,
    /// Volume in place in the layer now: adhering, minus what fell or ran off, m³.
    pub in_place: f64,
    /// Rebound as ACI 506R counts it, for a substrate: the share of `delivered` not in place;
    /// `null` for a collector or before anything was delivered.
    pub rebound_ratio: Option<f64>,
    /// Stuck on the back, which keeps no deposit.
    pub stuck_on_back: Amount,
    /// Σ thickness × cell area, m³: `stuck` plus what was received on the front, less what fell
    /// or ran off (up to rounding).
    pub layer_volume: f64,
    /// Thickness statistics of the wet deposit over the cells away from the edges (see
    /// [`ThicknessStats::of`]); its tolerance band is the dry film's where the material has
    /// volume solids.
    pub thickness: ThicknessStats,
    /// The same statistics of the dry film (the wet one times the volume solids), with the
    /// tolerance band, where the material has volume solids; its coverage threshold is the
    /// wet one's times the volume solids.
    pub dry_thickness: Option<ThicknessStats>,
    /// Released material that landed here.
    pub received: Amount,
    /// Material that failed and fell off: released particles and volume.
    pub detached: Amount,
    /// Share of cells over-loaded but holding at the last cohesion analysis, 0..1.
    pub at_risk_fraction: f64,
    /// Share of cells that have failed, 0..1.
    pub failed_fraction: f64,
    /// Impacts per cm² of the surface, on average.
    pub hits_per_cm2: f64,
    /// Erosion (with an erosion model).
    pub erosion: Option<ErosionStats>,
    /// Share of cells whose wet film risks sagging (with a sag threshold), 0..1.
    pub sag_risk_fraction: Option<f64>,
    /// The radius each stuck particle's volume was spread over, m (0: the struck cell only;
    /// `null` for a mesh, which deposits per triangle).
    pub splat_radius: Option<f64>,
}

/// Erosion of one target.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ErosionStats {
    /// Mean depth removed over the surface, coating and substrate together, m.
    pub mean_depth: f64,
    /// Deepest removal, coating and substrate together, m.
    pub max_depth: f64,
    /// Coating thickness at the start, m.
    pub coating: f64,
    /// Mean coating left, m.
    pub coating_left_mean: f64,
    /// Share of the surface cleaned to bare substrate (coating fully removed), 0..1; `null`
    /// without a coating.
    pub cleaned_fraction: Option<f64>,
    /// Mean depth worn off the substrate, m.
    pub substrate_mean_depth: f64,
    /// Deepest substrate wear, m.
    pub substrate_max_depth: f64,
}

/// Per-obstacle metrics.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ObstacleMetrics {
    /// The obstacle's name in the scenario.
    pub name: String,
    /// Impacts, stuck or rebounded.
    pub hits: u64,
    /// Stuck on it.
    pub stuck: Amount,
    /// Released material that landed on it.
    pub received: Amount,
}

/// Everything `metrics.json` reports.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Metrics {
    /// Simulated time, s.
    pub time: f64,
    /// Time steps of Δt taken so far.
    pub steps: u64,
    /// Particles emitted.
    pub emitted: Amount,
    /// Emitted mass, kg (volume × density).
    pub emitted_mass: f64,
    /// Where they are.
    pub fates: Fates,
    /// Rebound as ACI 506R counts it: of the volume delivered to substrate targets (whose first
    /// substrate impact was on them), the share not in place on them now — bounced away, came
    /// to rest loose, fell off or ran off; `null` before anything has struck one.
    pub rebound_ratio: Option<f64>,
    /// Volume that rebounded from its first impact on a substrate ÷ volume that struck a
    /// substrate (what bounces at once, whatever becomes of it); `null` before anything has
    /// struck one.
    pub bounce_ratio: Option<f64>,
    /// Of the volume delivered to substrate targets, the share in place only as trapped rebound
    /// (counted in place by `rebound_ratio`); `null` before anything has struck one.
    pub trapped_ratio: Option<f64>,
    /// Volume stuck on substrate targets ÷ volume emitted; `null` before anything is emitted.
    pub transfer_efficiency: Option<f64>,
    /// Per target, in scenario order.
    pub targets: Vec<TargetMetrics>,
    /// Per obstacle, in scenario order.
    pub obstacles: Vec<ObstacleMetrics>,
    /// The cohesive failures so far, and the material the layer stages released.
    pub failures: FailureMetrics,
    /// Where the emitted volume is.
    pub volume_balance: VolumeBalance,
    /// Process quality along the nozzle's path.
    pub path: PathMetrics,
}

fn ratio(a: f64, b: f64) -> Option<f64> {
    (b > 0.0).then(|| a / b)
}

/// Volume in place in `t`'s layer: what adhered, less what left it again, m³, with the run's
/// volume quantum `q` (m³).
fn in_place(t: &Target, q: f64) -> f64 {
    let b = &t.tally;
    (b.stuck.volume(q) - b.loose.volume(q) - b.detached.volume(q)).max(0.0)
}

impl Gauge {
    fn report(&self, samples: u64) -> Option<Range> {
        (self.n > 0).then(|| Range {
            min: self.min,
            mean: self.sum / self.n as f64,
            max: self.max,
            outside_share: (self.outside + samples - self.n) as f64 / samples as f64,
        })
    }
}

impl Simulation {
    /// The metrics as of now.
    pub fn metrics(&self) -> Metrics {
        let (targets, obstacles, tally) = (self.targets(), self.obstacles(), self.tally());
        let q = self.config().volume_quantum();
        let (mut in_flight, mut released_in_flight) = (Tallied::default(), Tallied::default());
        let swarm = self.swarm();
        for (i, p) in swarm.particles.iter().enumerate() {
            if p.is_alive() {
                let a =
                    if p.flags() & flags::RELEASED != 0 { &mut released_in_flight } else { &mut in_flight };
                a.add(swarm.volume(i));
            }
        }
        let fates = Fates {
            stuck_on_targets: targets
                .iter()
                .map(|t| t.tally.stuck + t.tally.stuck_back)
                .sum::<Tallied>()
                .amount(q),
            stuck_on_obstacles: obstacles.iter().map(|o| o.tally.stuck).sum::<Tallied>().amount(q),
            left_domain: tally.left_domain.amount(q),
            expired: tally.expired.amount(q),
            overspray: tally.overspray.amount(q),
            in_flight: in_flight.amount(q),
        };
        let released_fates = Fates {
            stuck_on_targets: targets.iter().map(|t| t.tally.received).sum::<Tallied>().amount(q),
            stuck_on_obstacles: obstacles.iter().map(|o| o.tally.received).sum::<Tallied>().amount(q),
            left_domain: tally.released_left.amount(q),
            expired: tally.released_expired.amount(q),
            overspray: Amount::default(),
            in_flight: released_in_flight.amount(q),
        };
        let on_substrate: f64 =
            targets.iter().filter(|t| t.role == Role::Substrate).map(|t| t.surface.volume()).sum();
        let emitted = tally.emitted.amount(q);
        let balance = VolumeBalance::of(emitted.volume, targets, q, &fates, &released_fates);
        let density = self.config().material.density;
        let sub = || targets.iter().filter(|t| t.role == Role::Substrate);
        let delivered: f64 = sub().map(|t| t.tally.delivered.volume(q)).sum();
        Metrics {
            time: self.time(),
            steps: self.steps_done(),
            emitted,
            emitted_mass: emitted.volume * density,
            rebound_ratio: {
                let placed: f64 = sub().map(|t| in_place(t, q)).sum();
                ratio(delivered - placed.min(delivered), delivered)
            },
            bounce_ratio: ratio(
                tally.substrate_first_rebounds.volume(q),
                tally.substrate_first_impacts.volume(q),
            ),
            trapped_ratio: ratio(sub().map(|t| t.tally.trapped.volume(q)).sum(), delivered),
            transfer_efficiency: ratio(on_substrate, emitted.volume),
            fates,
            targets: targets
                .iter()
                .zip(&self.config().targets)
                .map(|(t, c)| self.target_metrics(t, c))
                .collect(),
            obstacles: obstacles
                .iter()
                .map(|o| ObstacleMetrics {
                    name: o.name.clone(),
                    hits: o.tally.hits,
                    stuck: o.tally.stuck.amount(q),
                    received: o.tally.received.amount(q),
                })
                .collect(),
            failures: FailureMetrics {
                events: self.failures().to_vec(),
                released: tally.released.amount(q),
                dripped: tally.dripped.amount(q),
                ran_off: tally.ran_off.amount(q),
                released_fates,
            },
            volume_balance: balance,
            path: self.path_metrics(),
        }
    }

    fn target_metrics(&self, t: &Target, tc: &crate::config::TargetConfig) -> TargetMetrics {
        let c = self.config();
        let s = &t.surface;
        let count = s.thickness().len() as u32;
        // The figures every target has, in one pass over the cells (each sum in cell order).
        let (mut area, mut at_risk, mut failed) = (0.0, 0.0, 0.0);
        for (k, &mask) in (0..count).zip(&t.failure_mask) {
            let a = s.cell_area(k);
            area += a;
            at_risk += if mask == 1 { a } else { 0.0 };
            failed += if mask == 2 { a } else { 0.0 };
        }
        let area = area.max(f64::MIN_POSITIVE);
        // Area-weighted shares and means over the whole surface (for the optional figures).
        let share = |keep: &dyn Fn(usize) -> bool| {
            (0..count).filter(|&k| keep(k as usize)).map(|k| s.cell_area(k)).sum::<f64>() / area
        };
        let mean = |value: &dyn Fn(usize) -> f64| {
            (0..count).map(|k| value(k as usize) * s.cell_area(k)).sum::<f64>() / area
        };
        let erosion = t.erosion.as_ref().map(|e| ErosionStats {
            mean_depth: mean(&|k| e.eroded(k)),
            max_depth: (0..e.coating.len()).map(|k| e.eroded(k)).fold(0.0, f64::max),
            coating: e.initial_coating,
            coating_left_mean: mean(&|k| e.coating[k]),
            cleaned_fraction: (e.initial_coating > 0.0).then(|| share(&|k| e.coating[k] <= 0.0)),
            substrate_mean_depth: mean(&|k| e.substrate[k]),
            substrate_max_depth: e.substrate.iter().copied().fold(0.0, f64::max),
        });
        let sag = c.sag_threshold;
        let solids = c.material.volume_solids;
        let sag_risk_fraction = (sag > 0.0).then(|| {
            let risk = t.sag_risk(sag);
            share(&|k| risk[k] > 0)
        });
        let hits: f64 = s.hits().iter().map(|&h| f64::from(h)).sum();
        let (b, q) = (&t.tally, c.volume_quantum());
        let delivered = b.delivered.volume(q);
        TargetMetrics {
            name: t.name.clone(),
            role: t.role,
            hits: b.hits,
            stuck: b.stuck.amount(q),
            loose: b.loose.amount(q),
            trapped: b.trapped.amount(q),
            delivered: b.delivered.amount(q),
            in_place: in_place(t, q),
            rebound_ratio: (t.role == Role::Substrate)
                .then(|| ratio(delivered - in_place(t, q).min(delivered), delivered))
                .flatten(),
            stuck_on_back: b.stuck_back.amount(q),
            layer_volume: t.surface.volume(),
            thickness: ThicknessStats::of(
                s,
                c.material.coverage_threshold,
                tc.margin,
                if solids.is_some() { None } else { tc.tolerance },
                1.0,
            ),
            dry_thickness: solids.map(|v| {
                ThicknessStats::of(s, c.material.coverage_threshold * v, tc.margin, tc.tolerance, v)
            }),
            received: b.received.amount(q),
            detached: b.detached.amount(q),
            at_risk_fraction: at_risk / area,
            failed_fraction: failed / area,
            hits_per_cm2: hits / (area * 1e4),
            erosion,
            sag_risk_fraction,
            splat_radius: tc.splat_radius,
        }
    }

    fn path_metrics(&self) -> PathMetrics {
        let path = self.path_tally();
        PathMetrics {
            spraying_time: path.samples as f64 * self.config().dt,
            off_target_share: if path.samples > 0 {
                (path.samples - path.standoff.n) as f64 / path.samples as f64
            } else {
                0.0
            },
            standoff: path.standoff.report(path.samples),
            angle: path.angle.report(path.samples),
            travel_speed: path.travel_speed.report(path.samples.max(1)),
            nozzle_speed: path.nozzle_speed.report(path.samples.max(1)),
        }
    }
}

impl VolumeBalance {
    /// Where `emitted` (m³) is now, from the deposits and the fates, with the run's volume
    /// quantum `q` (m³).
    fn of(emitted: f64, targets: &[Target], q: f64, fates: &Fates, released: &Fates) -> VolumeBalance {
        let backs: Quanta = targets.iter().map(|t| t.tally.stuck_back.quanta + t.tally.received_back).sum();
        let b = VolumeBalance {
            emitted,
            in_maps: targets.iter().map(|t| t.surface.volume()).sum(),
            on_backs: backs as f64 * q,
            on_obstacles: fates.stuck_on_obstacles.volume + released.stuck_on_obstacles.volume,
            left_domain: fates.left_domain.volume + released.left_domain.volume,
            expired: fates.expired.volume + released.expired.volume,
            overspray: fates.overspray.volume,
            in_flight: fates.in_flight.volume + released.in_flight.volume,
            residual: 0.0,
        };
        let residual = b.emitted
            - (b.in_maps
                + b.on_backs
                + b.on_obstacles
                + b.left_domain
                + b.expired
                + b.overspray
                + b.in_flight);
        VolumeBalance { residual, ..b }
    }
}
