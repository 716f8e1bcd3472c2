//! Builds a simulation's data sets from its configuration.

use super::{Plan, Simulation, State, Workers};
use crate::collision::{Scene, SurfaceId, SurfaceKind, SurfaceRef};
use crate::config::{QUANTA_PER_PARTICLE, SimulationConfig, TargetConfig};
use crate::deposit::{DepositSurface, Pending};
use crate::emission::DropletSizes;
use crate::events::ImpactLog;
use crate::particles::{StreamKey, Swarm};
use crate::tally::{PathTally, Tally};
use crate::world::{ErosionMaps, Obstacle, Target, TargetTally};
use std::sync::Arc;

/// The simulation of a checked configuration, at time 0. `reuse` is a scene index from an
/// earlier simulation: kept (with its layer allowances cleared) if it indexes the same
/// surfaces, as it then equals the one this would build.
pub(super) fn build(config: Arc<SimulationConfig>, reuse: Option<Scene>) -> Simulation {
    let c = &config;
    // One impact model per owner: targets first, then obstacles.
    let mut models = Vec::new();
    let mut surfaces = Vec::new();
    let mut targets = Vec::new();
    for (i, t) in c.targets.iter().enumerate() {
        let surface_id = SurfaceId(surfaces.len() as u32);
        let pieces = t.surface.colliders();
        let count = pieces.len() as u32;
        surfaces.extend(pieces.into_iter().enumerate().map(|(k, shape)| SurfaceRef {
            shape,
            kind: SurfaceKind::Target(i),
            piece: k as u32,
            impact: models.len(),
            layer: 0.0,
        }));
        models.push(t.impact.clone());
        targets.push(new_target(t, surface_id, count));
    }
    let mut obstacles = Vec::new();
    for (i, o) in c.obstacles.iter().enumerate() {
        let impact = models.len();
        models.push(o.impact.clone());
        // Every shape is a surface of its own (a mesh's triangles one by one), so the grid
        // indexes them separately.
        surfaces.extend(o.shapes.iter().enumerate().map(|(k, shape)| SurfaceRef {
            shape: shape.clone(),
            kind: SurfaceKind::Obstacle(i),
            piece: k as u32,
            impact,
            layer: 0.0,
        }));
        obstacles.push(Obstacle { name: o.name.clone(), ..Obstacle::default() });
    }
    let scene = match reuse {
        Some(mut scene) if scene.indexes(&surfaces, c.domain) => {
            scene.clear_layer_allowances();
            scene
        }
        _ => Scene::new(surfaces, c.domain),
    };
    let steps_of = |interval: f64| (interval / c.dt).round().max(1.0) as u64;
    let plan = Plan {
        total_steps: c.total_steps(),
        epoch: u64::from(c.layer_epoch.max(1)),
        key: StreamKey::new(c.seed),
        models,
        stages: c.layer_stages.iter().map(|s| (steps_of(s.interval), s.stage.clone())).collect(),
        sizes: c.motion.air.and(c.emitter.droplets.as_ref()).map(DropletSizes::new),
    };
    let state = State {
        step: 0,
        swarm: Swarm::new(QUANTA_PER_PARTICLE),
        retired: 0,
        spawn_carry: 0.0,
        nozzle: c.nozzle.clone(),
        scene,
        targets,
        obstacles,
        tally: Tally::default(),
        next_id: 0,
        particle_steps: 0,
        particle_updates: 0,
        failures: Vec::new(),
        path: PathTally::default(),
        impact_log: (c.impact_log > 0.0).then(|| ImpactLog::new(c.impact_log, c.seed)),
        touched: vec![Vec::new(); c.targets.len()],
        settled: 0,
    };
    Simulation {
        config,
        plan,
        state,
        workers: Workers::Global,
        coasting: true,
        stage: None,
        stage_error: None,
    }
}

/// A target's record at time 0: its surface bare (or as configured), nothing struck yet.
fn new_target(t: &TargetConfig, surface_id: SurfaceId, pieces: u32) -> Target {
    let cells = t.surface.thickness().len();
    Target {
        name: t.name.clone(),
        role: t.role,
        surface: t.surface.clone(),
        surface_id,
        pieces,
        tally: TargetTally::default(),
        failure_mask: vec![0; cells],
        at_risk: false,
        erosion: t.erosion.as_ref().map(|e| ErosionMaps {
            coating: vec![e.coating; cells],
            substrate: vec![0.0; cells],
            initial_coating: e.coating,
        }),
        pending: Pending::new(cells, t.erosion.is_some()),
    }
}
