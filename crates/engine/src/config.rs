//! The resolved parameters of a simulation: plain data, every unit SI and every angle in
//! radians, with the process behaviour chosen as modules (see [`crate::process`]). A file
//! format (the scenario crate) or a program builds one; `Simulation::new` takes it.

use crate::collision::{Aabb, Face, Shape};
use crate::deposit::{RectangleSurface, Surface};
use crate::emission::{Aperture, Direction, Emitter, NozzlePath};
use crate::motion::{GRAVITY, Integrator, Motion};
use crate::process::rebound::PolynomialRebound;
use crate::process::{ErosionLaw, ImpactModel, LayerStage};
use crate::world::Role;
use glam::DVec3;
use std::sync::Arc;

/// Every parameter of a simulation.
#[derive(Clone, Debug)]
pub struct SimulationConfig {
    /// Time step Δt, s.
    pub dt: f64,
    /// Simulated duration, s; the run takes whole steps, the last may end past it.
    pub duration: f64,
    /// Seed of every random stream: same configuration and seed, same results.
    pub seed: u64,
    /// Most impacts resolved for one particle within one step; past it the particle waits for
    /// the next step at its last impact point.
    pub max_impacts_per_step: u32,
    /// Forces and integrator.
    pub motion: Motion,
    /// The sprayed material.
    pub material: Material,
    /// The nozzle's emitter.
    pub emitter: Emitter,
    /// The nozzle's path (replaceable during a run: `Simulation::set_nozzle_path`).
    pub nozzle: NozzlePath,
    /// Add the nozzle's own velocity to the particles it emits.
    pub add_nozzle_velocity: bool,
    /// Surfaces that collect deposit, in order.
    pub targets: Vec<TargetConfig>,
    /// Surfaces that collect none, in order.
    pub obstacles: Vec<ObstacleConfig>,
    /// Particles that leave this box are retired, m.
    pub domain: Aabb,
    /// Layer stages (cohesion, drip, …), run in this order at their intervals.
    pub layer_stages: Vec<ScheduledStage>,
    /// Wet-film thickness above which a film sags on a vertical surface, m (0: no sag maps).
    pub sag_threshold: f64,
    /// Recommended working window of the nozzle, for the path metrics.
    pub window: PathWindow,
    /// Keep a sample of the impacts (see [`crate::events::ImpactLog`]): the share kept, 0..1
    /// (0: none).
    pub impact_log: f64,
    /// Steps per layer epoch (at least 1): particles see every deposit surface as it stood at
    /// the start of the epoch, and deposits, erosion and the layer stages take effect at its
    /// end (see [`crate::pipeline`]). One step couples particles and layers step by step.
    pub layer_epoch: u32,
}

/// The sprayed material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Density, kg/m³.
    pub density: f64,
    /// A particle still in flight after this long is retired as expired, s.
    pub max_lifetime: f64,
    /// A cell counts as covered when its thickness reaches this, m.
    pub coverage_threshold: f64,
    /// Share of the material's volume left in the dry film (a paint's volume solids), 0–1;
    /// `None`: the deposit is reported wet only.
    pub volume_solids: Option<f64>,
}

/// A surface that collects deposit.
#[derive(Clone, Debug)]
pub struct TargetConfig {
    /// Name (unique among targets and obstacles).
    pub name: String,
    /// Substrate (sprayed) or collector (catches what rebounds or falls).
    pub role: Role,
    /// Geometry and (empty) deposit.
    pub surface: Surface,
    /// What happens on impact.
    pub impact: ImpactModel,
    /// Wear by abrasive impacts, if any.
    pub erosion: Option<ErosionConfig>,
    /// The specified thickness band `[min, max]`, m, whose share of the area the metrics
    /// report.
    pub tolerance: Option<[f64; 2]>,
    /// Cells closer than this to the surface's edges or openings are left out of the thickness
    /// statistics, m (0: none).
    pub margin: f64,
    /// The radius each stuck particle's volume is spread over, m, as the metrics report it
    /// (`None` for a surface without a splat, a mesh); the surface itself holds its footprint.
    pub splat_radius: Option<f64>,
}

/// Wear of a target by abrasive impacts: a coating (paint, epoxy) on a substrate (steel), each
/// with its own resistance. An impact wears the coating where there is some left, and the
/// substrate with what the coating did not absorb.
#[derive(Clone, Debug)]
pub struct ErosionConfig {
    /// Thickness of the coating at the start, m (0: bare substrate).
    pub coating: f64,
    /// Volume of coating one impact removes.
    pub coating_law: Arc<dyn ErosionLaw>,
    /// Volume of substrate one impact removes.
    pub substrate_law: Arc<dyn ErosionLaw>,
}

/// A surface that collects no deposit (rebar, formwork, a floor).
#[derive(Clone, Debug)]
pub struct ObstacleConfig {
    /// Name (unique among targets and obstacles).
    pub name: String,
    /// Its shapes: one, or a mesh's triangles.
    pub shapes: Vec<Shape>,
    /// What happens on impact.
    pub impact: ImpactModel,
}

/// A layer stage and how often it runs.
#[derive(Clone, Debug)]
pub struct ScheduledStage {
    /// Time between runs, s (rounded to whole steps, at least one).
    pub interval: f64,
    /// What runs on the layers at each interval (cohesion, drip, slump, …).
    pub stage: Arc<dyn LayerStage>,
}

/// Recommended working window of the nozzle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PathWindow {
    /// `[min, max]` standoff along the spray axis, m.
    pub standoff: [f64; 2],
    /// Largest angle between the spray axis and the surface's normal, degrees.
    pub max_angle: f64,
    /// `[min, max]` travel speed, m/s.
    pub speed: [f64; 2],
}

/// A configuration the engine cannot run: the field and what is wrong.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("`{field}` {message}")]
pub struct ConfigError {
    /// The field, e.g. `dt` or `targets[0].surface`.
    pub field: String,
    /// What is wrong with it.
    pub message: String,
}

/// Largest coordinate magnitude a position may have on any axis, m: beyond any construction
/// site, and small enough that squares and sums of coordinates stay far from overflow.
pub const MAX_COORD: f64 = 1e4;

/// Most steps and most particles one run may take: step and particle indices are 32-bit.
const MAX_STEPS: f64 = 4e9;

/// Steps per layer epoch of [`SimulationConfig::example_wall`] (Δt = 1 ms): 5 ms, the
/// scenarios' default `layer_epoch` (see docs/validation.md for how the figures move with it).
pub const DEFAULT_LAYER_EPOCH_STEPS: u32 = 5;

/// A nozzle particle's volume is this many volume quanta (see
/// [`SimulationConfig::volume_quantum`]).
pub const QUANTA_PER_PARTICLE: u64 = 1 << 24;

impl SimulationConfig {
    /// The run's volume quantum, m³: a nozzle particle's volume over [`QUANTA_PER_PARTICLE`].
    /// The run books every volume (tallies, deposits before they join a layer) in whole quanta,
    /// whose sums are exact whatever their order: a volume is rounded to it once, to 2⁻²⁵ of a
    /// nozzle particle at most.
    pub fn volume_quantum(&self) -> f64 {
        self.emitter.particle_volume / QUANTA_PER_PARTICLE as f64
    }

    /// `volume` (m³) in whole quanta (see [`SimulationConfig::volume_quantum`]), rounded to
    /// the nearest; negative or non-finite volumes count as none.
    pub fn quanta_of(&self, volume: f64) -> u64 {
        let q = volume / self.volume_quantum();
        if q.is_finite() && q > 0.0 { q.round() as u64 } else { 0 }
    }

    /// Number of whole steps covering the duration (the last may end past it); the tolerance
    /// absorbs rounding of duration / dt.
    pub fn total_steps(&self) -> u64 {
        ((self.duration / self.dt) - 1e-9).ceil().max(1.0) as u64
    }

    /// Checks what the engine relies on: finite, positive times and rates, a domain with
    /// volume, unique names. The scenario crate checks far more, with the keys of its files.
    pub fn check(&self) -> Result<(), ConfigError> {
        let bad = |field: &str, message: String| Err(ConfigError { field: field.into(), message });
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return bad("dt", format!("must be a positive number of seconds, got {}", self.dt));
        }
        if !(self.duration.is_finite() && self.duration > 0.0 && self.duration / self.dt < MAX_STEPS) {
            return bad("duration", format!("must be positive and under 4·10⁹ steps, got {}", self.duration));
        }
        let e = &self.emitter;
        if !(e.spawn_rate.is_finite() && e.spawn_rate > 0.0 && e.spawn_rate * self.duration < MAX_STEPS) {
            return bad(
                "emitter.spawn_rate",
                format!("must be positive and emit under 4·10⁹ particles, got {}", e.spawn_rate),
            );
        }
        if !(e.speed[0].is_finite()
            && e.speed[1].is_finite()
            && 0.0 <= e.speed[0]
            && e.speed[0] <= e.speed[1])
        {
            return bad("emitter.speed", format!("must be [min, max] with 0 ≤ min ≤ max, got {:?}", e.speed));
        }
        if !(self.domain.min.is_finite()
            && self.domain.max.is_finite()
            && self.domain.min.cmplt(self.domain.max).all())
        {
            return bad("domain", "must be a finite box with volume".into());
        }
        if !(e.particle_volume.is_finite() && e.particle_volume > 0.0) {
            return bad(
                "emitter.particle_volume",
                format!("must be a positive volume, got {}", e.particle_volume),
            );
        }
        if let Some(d) = &e.droplets
            && let Err(message) = d.check()
        {
            return bad("emitter.droplets", message);
        }
        if let Some(air) = &self.motion.air {
            if let Err(message) = air.check() {
                return bad("motion.air", message);
            }
            if e.droplets.is_none() {
                return bad("motion.air", "needs the emitter's droplet sizes (`emitter.droplets`)".into());
            }
            if self.motion.integrator == Integrator::Exact {
                return bad(
                    "motion.air",
                    "has no closed form with the exact integrator: use an Euler one".into(),
                );
            }
            if self.motion.drag != 0.0 {
                return bad("motion.air", "replaces the quadratic drag: set `motion.drag` to 0".into());
            }
        }
        if self.layer_epoch == 0 {
            return bad("layer_epoch", "must be at least one step".into());
        }
        if self.max_impacts_per_step == 0 {
            return bad("max_impacts_per_step", "must be at least 1".into());
        }
        if let Err(message) = self.nozzle.check(MAX_COORD) {
            return bad("nozzle", message);
        }
        let mut names: Vec<&str> = self.targets.iter().map(|t| t.name.as_str()).collect();
        names.extend(self.obstacles.iter().map(|o| o.name.as_str()));
        names.sort_unstable();
        if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
            return bad("targets", format!("the name {:?} is used twice", w[0]));
        }
        Ok(())
    }

    /// A small configuration in code, for examples and tests: wet-mix shotcrete (the paper's
    /// Table 1) from a static nozzle 1 m from a 2 m × 2 m wall, for `duration` seconds.
    pub fn example_wall(duration: f64) -> SimulationConfig {
        let impact = ImpactModel {
            alpha: 1.0,
            rebound: Arc::new(PolynomialRebound { coefficients: vec![0.10, 0.0, 0.0, 2.4] }),
            restitution: 0.04,
            scatter: 5f64.to_radians(),
            rest_speed: 0.5,
            rest_max_slope: 90f64.to_radians(),
            cushion_radius: 0.0,
        };
        let face = Face::new(DVec3::new(0.0, 0.0, 1.0), DVec3::NEG_X, DVec3::Z, [2.0, 2.0]);
        SimulationConfig {
            dt: 1e-3,
            duration,
            seed: 1,
            max_impacts_per_step: 8,
            motion: Motion { gravity: GRAVITY, drag: 0.0, integrator: Integrator::Euler, air: None },
            material: Material {
                density: 2300.0,
                max_lifetime: 5.0,
                coverage_threshold: 1e-3,
                volume_solids: None,
            },
            emitter: Emitter {
                aperture: Aperture::Circle { r: 0.025 },
                direction: Direction::TruncatedNormal { mu: 0.255, sigma: 0.102 },
                cone_half_angle: 7f64.to_radians(),
                speed: [20.0, 30.0],
                spawn_rate: 1e4,
                particle_volume: 1.5e-3 / 1e4,
                droplets: None,
            },
            nozzle: NozzlePath::fixed(DVec3::new(-1.0, 0.0, 1.0), DVec3::X, 0.0),
            add_nozzle_velocity: false,
            targets: vec![TargetConfig {
                name: "wall".into(),
                role: Role::Substrate,
                surface: Surface::Rectangle(RectangleSurface::new(face, 256, 256, 0.0)),
                impact,
                erosion: None,
                tolerance: None,
                margin: 0.0,
                splat_radius: Some(0.0),
            }],
            obstacles: Vec::new(),
            domain: Aabb { min: DVec3::new(-2.0, -2.0, -1.0), max: DVec3::new(1.0, 2.0, 3.0) },
            layer_stages: Vec::new(),
            sag_threshold: 0.0,
            window: PathWindow { standoff: [1.0, 2.0], max_angle: 20.0, speed: [0.0, 1.0] },
            impact_log: 0.0,
            layer_epoch: DEFAULT_LAYER_EPOCH_STEPS,
        }
    }
}
