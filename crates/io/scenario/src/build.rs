//! A scenario's configuration for the engine: file units to SI radians, names to modules.

use crate::params::*;
use crate::scenario::Scenario;
use glam::DVec3;
use spraysim_engine::collision::Aabb;
use spraysim_engine::config::{
    ErosionConfig, Material, ObstacleConfig, PathWindow, ScheduledStage, SimulationConfig, TargetConfig,
};
use spraysim_engine::emission::{self, Emitter, NozzlePath, Waypoint, circling, raster};
use spraysim_engine::motion::{AirFlow, DragLaw, Motion};
use spraysim_engine::process::erosion::{Finnie, Oka};
use spraysim_engine::process::layer::{CohesionStage, DripStage, SlumpStage, Strength};
use spraysim_engine::process::{ErosionLaw, ImpactModel};
use std::sync::Arc;

impl Scenario {
    /// The engine's configuration of this scenario.
    pub fn config(&self) -> SimulationConfig {
        config(self)
    }

    /// A simulation of this scenario at time 0.
    pub fn build(&self) -> Result<spraysim_engine::Simulation, spraysim_engine::SetupError> {
        spraysim_engine::Simulation::new(self.config())
    }

    /// Sets `sim` up afresh for this scenario, at time 0: what [`Scenario::build`] gives, bit
    /// for bit, reusing `sim`'s broad phase when the geometry is the same (see
    /// [`spraysim_engine::Simulation::restart`]). On an error `sim` is unchanged.
    pub fn rebuild(&self, sim: &mut spraysim_engine::Simulation) -> Result<(), spraysim_engine::SetupError> {
        sim.restart(self.config())
    }

    /// When the nozzle's path ends, s: the time of its last waypoint (0 for a static or
    /// circling nozzle, which never stops).
    pub fn path_end(&self) -> f64 {
        match &self.nozzle().motion {
            NozzleMotion::Static { .. } | NozzleMotion::Circling { .. } => 0.0,
            _ => nozzle_path(self).waypoints().last().map_or(0.0, |w| w.time),
        }
    }

    /// When the nozzle stops spraying for good, s (`None`: it sprays until the run ends).
    pub fn spraying_ends(&self) -> Option<f64> {
        let end = nozzle_path(self).spray_end();
        end.is_finite().then_some(end)
    }

    /// What the scenario does that a user may not intend, one sentence each: a path cut off
    /// by the simulated duration, say.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let (end, duration) = (self.path_end(), self.simulation().duration);
        if end > duration {
            out.push(format!(
                "the nozzle's path runs until {end:.3} s, past `simulation.duration` = {duration} s: the last \
                 {:.3} s of it are not simulated (set simulation.duration to at least {end:.3})",
                end - duration
            ));
        }
        let kvt = self.process().drag * self.emitter().speed[1] * self.simulation().dt;
        if kvt > 0.1 {
            out.push(format!(
                "process.drag × emitter.speed (max) × simulation.dt = {kvt:.3}: each step changes a particle's \
                 speed by that share of itself, too coarse for drag to be followed accurately (keep it below 0.1 by \
                 lowering simulation.dt)"
            ));
        }
        let gravity = DVec3::from_array(self.simulation().gravity).normalize_or_zero();
        for t in self.targets() {
            // Facing sideways or down, what slumps down the face piles at its held foot without
            // limit (the heightfield measures thickness across the face, not a heap on a floor).
            if t.shape.as_dyn().piles_at_held_foot(gravity) && self.process().slump.interval > 0.0 {
                out.push(format!(
                    "target `{}` holds its edges but is steeper than 45°: what slumps down it piles up at its foot \
                     without limit (leave its edges free over a floor target that catches what runs off)",
                    t.name
                ));
            }
            out.extend(t.shape.as_dyn().warnings(&t.name, self));
        }
        out
    }
}

/// The engine's configuration of `sc`.
fn config(sc: &Scenario) -> SimulationConfig {
    let (s, p) = (sc.simulation(), sc.process());
    let erosion = erosion_laws(&p.erosion);
    let targets: Vec<TargetConfig> = sc
        .targets()
        .iter()
        .map(|t| TargetConfig {
            name: t.name.clone(),
            role: t.role,
            surface: t.shape.surface(),
            impact: impact_model(t.impact.as_ref().unwrap_or(&p.impact)),
            erosion: erosion.clone().map(|(coating_law, substrate_law)| ErosionConfig {
                coating: t.coating,
                coating_law,
                substrate_law,
            }),
            tolerance: t.tolerance,
            margin: t.margin,
            splat_radius: t.shape.splat_radius().map(|s| s.radius),
        })
        .collect();
    let obstacles = sc
        .obstacles()
        .iter()
        .map(|o| ObstacleConfig {
            name: o.name.clone(),
            shapes: o.shape.shapes(),
            impact: impact_model(o.impact.as_ref().unwrap_or(&p.impact)),
        })
        .collect();
    let mut layer_stages = Vec::new();
    // Slump first: cohesion judges the layer as it stands after flowing.
    let sl = &p.slump;
    if sl.interval > 0.0 {
        let stage = Arc::new(SlumpStage { yield_stress: sl.yield_stress, max_sweeps: sl.max_sweeps });
        layer_stages.push(ScheduledStage { interval: sl.interval, stage });
    }
    let c = &p.cohesion;
    if c.interval > 0.0 {
        let strength =
            Strength { tensile: c.tensile_strength, shear: c.shear_strength, cohesion: c.cohesion };
        layer_stages
            .push(ScheduledStage { interval: c.interval, stage: Arc::new(CohesionStage { strength }) });
    }
    if p.drip_interval > 0.0 {
        let stage = Arc::new(DripStage { threshold: p.sag_threshold });
        layer_stages.push(ScheduledStage { interval: p.drip_interval, stage });
    }
    let w = &p.window;
    SimulationConfig {
        dt: s.dt,
        duration: s.duration,
        seed: s.seed,
        max_impacts_per_step: s.max_impacts_per_step,
        motion: Motion { gravity: v3(s.gravity), drag: p.drag, integrator: s.integrator, air: air(sc.air()) },
        material: Material {
            density: p.density,
            max_lifetime: p.max_lifetime,
            coverage_threshold: p.coverage_threshold,
            volume_solids: p.volume_solids,
        },
        emitter: emitter(sc.emitter(), p.flow_rate),
        nozzle: nozzle_path(sc),
        add_nozzle_velocity: sc.nozzle().add_velocity,
        targets,
        obstacles,
        domain: Aabb { min: v3(sc.domain().min), max: v3(sc.domain().max) },
        layer_stages,
        sag_threshold: p.sag_threshold,
        window: PathWindow { standoff: w.standoff, max_angle: w.max_angle, speed: w.speed },
        impact_log: sc.output().impact_log,
        layer_epoch: (sc.simulation().layer_epoch / sc.simulation().dt)
            .round()
            .clamp(1.0, f64::from(u32::MAX)) as u32,
    }
}

/// Impact parameters in file units → the impact model in radians.
pub fn impact_model(p: &ImpactParams) -> ImpactModel {
    ImpactModel {
        alpha: p.alpha,
        rebound: p.rebound.law(),
        restitution: p.restitution,
        scatter: p.scatter_angle.to_radians(),
        rest_speed: p.rest_speed,
        rest_max_slope: p.rest_max_slope.to_radians(),
        cushion_radius: p.cushion_radius,
    }
}

/// The erosion laws of the coating and of the substrate, if erosion is on.
type Laws = (Arc<dyn ErosionLaw>, Arc<dyn ErosionLaw>);

fn erosion_laws(e: &ErosionParams) -> Option<Laws> {
    match *e {
        ErosionParams::None => None,
        ErosionParams::Finnie { coating, substrate } => {
            Some((Arc::new(Finnie { k: coating.finnie_k }), Arc::new(Finnie { k: substrate.finnie_k })))
        }
        ErosionParams::Oka { grain_diameter, oka_v_ref, oka_d_ref, oka_k3, coating, substrate } => {
            let law = |l: OkaLayer| -> Arc<dyn ErosionLaw> {
                Arc::new(Oka::for_hardness(
                    l.hardness,
                    l.oka_e90,
                    oka_v_ref,
                    oka_d_ref,
                    oka_k3,
                    grain_diameter,
                ))
            };
            Some((law(coating), law(substrate)))
        }
    }
}

/// The engine's emitter of `e`, at the process's `flow_rate` (m³/s).
pub(crate) fn emitter(e: &EmitterParams, flow_rate: f64) -> Emitter {
    let aperture = match e.aperture {
        Aperture::Point => emission::Aperture::Point,
        Aperture::Circle { diameter } => emission::Aperture::Circle { r: diameter / 2.0 },
        Aperture::Rectangle { width, height } => {
            emission::Aperture::Rectangle { hw: width / 2.0, hh: height / 2.0 }
        }
        Aperture::Annulus { inner_diameter, outer_diameter } => {
            emission::Aperture::Annulus { r_in: inner_diameter / 2.0, r_out: outer_diameter / 2.0 }
        }
    };
    let (direction, cone_angle) = match e.direction {
        DirectionLaw::UniformPolar { cone_angle } => (emission::Direction::UniformPolar, cone_angle),
        DirectionLaw::TruncatedNormal { cone_angle, mu, sigma } => {
            (emission::Direction::TruncatedNormal { mu, sigma }, cone_angle)
        }
        DirectionLaw::UniformSolidAngle { cone_angle } => {
            (emission::Direction::UniformSolidAngle, cone_angle)
        }
        DirectionLaw::Fan { fan_wide_angle, fan_narrow_angle } => (
            emission::Direction::Fan {
                wide: fan_wide_angle.to_radians(),
                narrow: fan_narrow_angle.to_radians(),
            },
            fan_wide_angle.max(fan_narrow_angle),
        ),
    };
    Emitter {
        aperture,
        direction,
        cone_half_angle: (cone_angle / 2.0).to_radians(),
        speed: e.speed,
        spawn_rate: e.spawn_rate,
        particle_volume: flow_rate / e.spawn_rate,
        droplets: e.droplets.distribution(),
    }
}

/// The engine's air flow of `a` (`None`: still air).
fn air(a: &AirParams) -> Option<AirFlow> {
    let AirParams::Jet(j) = a else { return None };
    Some(AirFlow {
        speed: j.speed,
        outlet_diameter: j.outlet_diameter,
        spread: j.spread,
        stagnation_layer: j.stagnation_layer,
        viscosity: j.viscosity,
        density: j.density,
        drag_law: match j.drag {
            DragLawName::Stokes => DragLaw::Stokes,
            DragLawName::SchillerNaumann => DragLaw::SchillerNaumann,
        },
        booth_speed: j.booth_speed,
    })
}

/// The surface a raster over the target named `name` covers.
fn raster_chart(sc: &Scenario, name: &str) -> Option<RasterChart> {
    sc.targets().iter().find(|t| t.name == name)?.shape.as_dyn().raster_chart()
}

/// The nozzle's path in `sc`.
pub(crate) fn nozzle_path(sc: &Scenario) -> NozzlePath {
    let n = sc.nozzle();
    let roll = n.roll.to_radians();
    match &n.motion {
        NozzleMotion::Static { position, axis } => NozzlePath::fixed(v3(*position), v3(*axis), roll),
        NozzleMotion::Circling { position, axis, circle_radius, circle_frequency } => {
            circling(v3(*position), v3(*axis), *circle_radius, *circle_frequency, roll)
        }
        NozzleMotion::Waypoints { waypoints } => NozzlePath::through(
            waypoints
                .iter()
                .map(|w| Waypoint {
                    time: w.time,
                    position: v3(w.position),
                    axis: v3(w.axis),
                    spray: w.spray,
                })
                .collect(),
            roll,
        ),
        NozzleMotion::Raster { raster: r } => match raster_chart(sc, &r.target) {
            Some(RasterChart::Face(f)) => raster(&f, &r.plan, roll),
            Some(RasterChart::Shell(c)) => raster(&c, &r.plan, roll),
            // Reading the raster checked that its target exists.
            None => NozzlePath::through(Vec::new(), roll),
        },
    }
}
