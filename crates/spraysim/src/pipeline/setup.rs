//! Turns a validated scenario into the simulation's data sets (units converted to SI radians).

use super::{SetupError, Simulation};
use crate::collision::{
    Aabb, Cylinder, Disk, Face, OrientedBox, Plane, Scene, Shape, Sphere, SurfaceKind, SurfaceRef,
};
use crate::emitter::{Aperture, ApertureShape, Direction, DirectionKind, Emitter};
use crate::heightfield::HeightField;
use crate::impact::{ImpactModel, ReboundCurve};
use crate::integrator::Motion;
use crate::metrics::Tally;
use crate::nozzle::{NozzlePath, Waypoint, circling_waypoints, raster_waypoints};
use crate::rng::StreamKey;
use crate::scenario::{ImpactOverride, ImpactParams, ObstacleParams, ObstacleShape, ReboundModel, Scenario};
use crate::swarm::Swarm;
use crate::target::{Amount, Obstacle, Target};
use glam::DVec3;

fn v3(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// Builds the simulation; `scenario` must have passed validation.
pub(super) fn build(scenario: &Scenario) -> Result<Simulation, SetupError> {
    let sc = scenario;
    let mut models = vec![impact_model(&sc.process.impact)];
    let mut model_for = |over: &ImpactOverride| -> usize {
        if *over == ImpactOverride::default() {
            return 0;
        }
        let mut p = sc.process.impact.clone();
        p.apply(over);
        models.push(impact_model(&p));
        models.len() - 1
    };
    let mut surfaces = Vec::new();
    let mut targets = Vec::new();
    let eroding = sc.process.erosion.model != crate::scenario::ErosionModel::None;
    for (i, t) in sc.targets.iter().enumerate() {
        let face = Face::new(v3(t.center), v3(t.normal), v3(t.up), t.size);
        let [cols, rows] = t.resolution.map(|r| r as usize);
        targets.push(Target {
            name: t.name.clone(),
            role: t.role,
            face,
            field: HeightField::new(t.size[0], t.size[1], cols, rows, t.splat_radius),
            hits: 0,
            stuck: Amount::default(),
            stuck_back: Amount::default(),
            received: Amount::default(),
            received_back: 0.0,
            detached: Amount::default(),
            failure_mask: vec![0; cols * rows],
            erosion: if eroding { vec![0.0; cols * rows] } else { Vec::new() },
            coating: if eroding { vec![t.coating; cols * rows] } else { Vec::new() },
            initial_coating: t.coating,
        });
        surfaces.push(SurfaceRef {
            shape: Shape::Face(face),
            kind: SurfaceKind::Target(i),
            impact: model_for(&t.impact),
            layer: 0.0,
        });
    }
    let mut obstacles = Vec::new();
    for (i, o) in sc.obstacles.iter().enumerate() {
        let impact = model_for(&o.impact);
        let kind = SurfaceKind::Obstacle(i);
        match o.mesh() {
            // Every triangle is a surface of its own, so the grid indexes them one by one.
            Some(mesh) => surfaces.extend(mesh?.into_iter().map(|t| SurfaceRef {
                shape: Shape::Triangle(t),
                kind,
                impact,
                layer: 0.0,
            })),
            None => surfaces.push(SurfaceRef { shape: obstacle_shape(o), kind, impact, layer: 0.0 }),
        }
        obstacles.push(Obstacle {
            name: o.name.clone(),
            hits: 0,
            stuck: Amount::default(),
            received: Amount::default(),
        });
    }

    let e = &sc.emitter;
    let aperture = match e.shape {
        ApertureShape::Point => Aperture::Point,
        ApertureShape::Circle => Aperture::Circle { r: e.diameter / 2.0 },
        ApertureShape::Rectangle => Aperture::Rectangle { hw: e.width / 2.0, hh: e.height / 2.0 },
        ApertureShape::Annulus => {
            Aperture::Annulus { r_in: e.inner_diameter / 2.0, r_out: e.outer_diameter / 2.0 }
        }
    };
    let direction = match e.direction {
        DirectionKind::UniformPolar => Direction::UniformPolar,
        DirectionKind::TruncatedNormal => Direction::TruncatedNormal { mu: e.mu, sigma: e.sigma },
        DirectionKind::UniformSolidAngle => Direction::UniformSolidAngle,
        DirectionKind::Fan => {
            Direction::Fan { wide: e.fan_wide_angle.to_radians(), narrow: e.fan_narrow_angle.to_radians() }
        }
    };
    let emitter = Emitter::new(
        aperture,
        direction,
        (e.cone_angle / 2.0).to_radians(),
        e.speed,
        e.spawn_rate,
        sc.process.flow_rate / e.spawn_rate,
    );

    let n = &sc.nozzle;
    let roll = n.roll.to_radians();
    let nozzle = if let Some(r) = &n.raster {
        // Validation guarantees the raster's target exists.
        let face = sc.targets.iter().position(|t| t.name == r.target).map(|i| targets[i].face);
        NozzlePath::through(face.map(|f| raster_waypoints(&f, r)).unwrap_or_default(), roll)
    } else if n.circle_radius > 0.0 {
        let until = sc.simulation.duration;
        NozzlePath::through(
            circling_waypoints(v3(n.position), v3(n.axis), n.circle_radius, n.circle_frequency, until),
            roll,
        )
    } else if n.waypoints.is_empty() {
        NozzlePath::fixed(v3(n.position), v3(n.axis), roll)
    } else {
        let w = n.waypoints.iter().map(|w| Waypoint {
            time: w.time,
            position: v3(w.position),
            axis: v3(w.axis),
            spray: w.spray,
        });
        NozzlePath::through(w.collect(), roll)
    };

    let domain = Aabb { min: v3(sc.domain.min), max: v3(sc.domain.max) };
    let scene = Scene::new(surfaces, domain);
    let s = &sc.simulation;
    // Whole steps covering the duration; the tolerance absorbs rounding of duration / dt.
    let total_steps = ((s.duration / s.dt) - 1e-9).ceil().max(1.0) as u64;
    Ok(Simulation {
        scenario: sc.clone(),
        step: 0,
        total_steps,
        swarm: Swarm::new(emitter.particle_volume as f32),
        retired: 0,
        emitter,
        nozzle,
        scene,
        models,
        motion: Motion { gravity: v3(s.gravity), drag: sc.process.drag, integrator: s.integrator },
        domain,
        targets,
        obstacles,
        tally: Tally::default(),
        key: StreamKey::new(s.seed),
        next_id: 0,
        particle_steps: 0,
        particle_updates: 0,
        cohesion_every: if sc.process.cohesion.interval > 0.0 {
            (sc.process.cohesion.interval / s.dt).round().max(1.0) as u64
        } else {
            0
        },
        drip_every: if sc.process.drip_interval > 0.0 {
            (sc.process.drip_interval / s.dt).round().max(1.0) as u64
        } else {
            0
        },
        failures: Vec::new(),
        path: Default::default(),
        impact_log: Vec::new(),
        pool: None,
        lazy_flight: true,
    })
}

/// Impact parameters in file units → the impact model in radians.
pub(crate) fn impact_model(p: &ImpactParams) -> ImpactModel {
    ImpactModel {
        alpha: p.alpha,
        curve: match p.rebound_model {
            ReboundModel::Polynomial => ReboundCurve::Polynomial(p.rebound_polynomial.clone()),
            ReboundModel::Always => ReboundCurve::Always,
            ReboundModel::Never => ReboundCurve::Never,
        },
        restitution: p.restitution,
        scatter: p.scatter_angle.to_radians(),
        rest_speed: p.rest_speed,
        rest_max_slope: p.rest_max_slope.to_radians(),
        cushion_factor: p.cushion_factor,
        cushion_thickness: p.cushion_thickness,
    }
}

/// The collision shape of a validated obstacle that is not a mesh (validation guarantees the
/// fields it reads).
fn obstacle_shape(o: &ObstacleParams) -> Shape {
    let center = v3(o.center.unwrap_or_default());
    let normal = v3(o.normal.unwrap_or([0.0, 0.0, 1.0])).normalize();
    let radius = o.radius.unwrap_or(0.0);
    let size = o.size.clone().unwrap_or_default();
    let dim = |i: usize| size.get(i).copied().unwrap_or(0.0);
    match o.shape {
        ObstacleShape::Plane => Shape::Plane(Plane { point: center, normal }),
        ObstacleShape::Face => {
            Shape::Face(Face::new(center, normal, v3(o.up.unwrap_or([0.0, 0.0, 1.0])), [dim(0), dim(1)]))
        }
        ObstacleShape::Disk => Shape::Disk(Disk { center, normal, radius }),
        ObstacleShape::Sphere => Shape::Sphere(Sphere { center, radius }),
        ObstacleShape::Box => {
            let x = v3(o.x_axis.unwrap_or([1.0, 0.0, 0.0])).normalize();
            let y = v3(o.y_axis.unwrap_or([0.0, 1.0, 0.0]));
            let y = (y - x * y.dot(x)).normalize();
            Shape::Box(OrientedBox {
                center,
                axes: [x, y, x.cross(y)],
                half_extents: DVec3::new(dim(0), dim(1), dim(2)) / 2.0,
            })
        }
        // A mesh never gets here: `ObstacleParams::mesh` expands it into triangles.
        ObstacleShape::Cylinder | ObstacleShape::Mesh => Shape::Cylinder(Cylinder {
            a: v3(o.start.unwrap_or_default()),
            b: v3(o.end.unwrap_or_default()),
            radius,
        }),
    }
}
