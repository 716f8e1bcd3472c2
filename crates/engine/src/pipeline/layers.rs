//! Layer stage: the configured layer stages at their intervals, then the broad phase is told
//! how far the layers have grown.

use super::{Plan, State};
use crate::collision::{Aabb, SurfaceId, SurfaceKind};
use crate::config::SimulationConfig;
use crate::deposit::DepositSurface;
use crate::events::EventHandler;
use crate::process::layer::{LayerContext, Releaser};

/// Runs each layer stage whose period ends with this step, in configuration order.
pub(super) fn run(config: &SimulationConfig, plan: &Plan, state: &mut State, events: &mut dyn EventHandler) {
    let due = |every: u64| every > 0 && (state.step + 1).is_multiple_of(every);
    if !plan.stages.iter().any(|(every, _)| due(*every)) {
        return;
    }
    let found = state.failures.len();
    let time = state.step as f64 * config.dt + config.dt;
    for (every, stage) in &plan.stages {
        if !due(*every) {
            continue;
        }
        let mut ctx = LayerContext {
            time,
            gravity: config.motion.gravity,
            density: config.material.density,
            targets: &mut state.targets,
            failures: &mut state.failures,
            release: Releaser {
                swarm: &mut state.swarm,
                tally: &mut state.tally,
                next_id: &mut state.next_id,
            },
        };
        stage.run(&mut ctx);
    }
    for f in &state.failures[found..] {
        events.failure(f);
    }
}

/// Keeps the broad phase aware of every layer: when a target's layer outgrows the reach it was
/// indexed with, the reach doubles and its zone is marked in the broad phase (a few times per
/// run); the sleeping particles whose flight comes near a grown zone are woken.
pub(super) fn grow_allowances(config: &SimulationConfig, state: &mut State, lazy: bool) {
    let grown: Vec<_> = state
        .targets
        .iter()
        .filter(|t| t.surface.max_thickness() > state.scene.surface(t.surface_id).layer)
        .flat_map(|t| {
            let reach = (2.0 * t.surface.max_thickness()).max(0.01);
            (0..t.pieces).map(move |k| (SurfaceId(t.surface_id.0 + k), reach))
        })
        .collect();
    if grown.is_empty() {
        return;
    }
    state.scene.set_layer_allowances(&grown);
    // Only the exact integrator lets particles sleep.
    if !lazy {
        return;
    }
    // One box per grown target (a mesh has too many pieces to test each).
    let mut zones: Vec<(u32, Aabb)> = Vec::new();
    for &(id, _) in &grown {
        let SurfaceKind::Target(t) = state.scene.surface(id).kind else { continue };
        let Some(b) = state.scene.bounds_of(id) else {
            // An unbounded surface's zone is everywhere.
            super::watch::wake_all(config, state);
            return;
        };
        match zones.last_mut() {
            Some((last, zone)) if *last == t as u32 => *zone = zone.union(b),
            _ => zones.push((t as u32, b)),
        }
    }
    let zones: Vec<Aabb> = zones.into_iter().map(|(_, b)| b).collect();
    super::watch::wake_near(config, state, &zones);
}
