//! The end of a layer epoch: what the epoch's particles left on each target takes effect, the
//! layer stages that fall due run, and the broad phase is told how far the layers have grown.
//!
//! Everything here is serial and in a fixed order (targets in configuration order, stages in
//! configuration order), and its work is in proportion to what changed: the cells the epoch
//! touched, the particles the stages release; only a layer stage that falls due visits its
//! targets.

use super::{COMPACT_MIN, Plan, State};
use crate::collision::SurfaceId;
use crate::config::SimulationConfig;
use crate::deposit::DepositSurface;
use crate::events::EventHandler;
use crate::process::layer::{LayerContext, Releaser};

/// Settles the epoch that ends with step `to` (exclusive): deposits, impacts and wear join the
/// targets, then the layer stages due run, the layers' allowances in the broad phase grow
/// where they must, and the swarm is compacted once many of its slots have retired.
pub(super) fn run(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    to: u64,
    events: &mut dyn EventHandler,
) {
    let q = config.volume_quantum();
    for (target, touched) in state.targets.iter_mut().zip(&mut state.touched) {
        target.settle(touched, q);
        touched.clear();
    }
    stages(config, plan, state, to, events);
    grow_allowances(state);
    state.settled = to;
    if state.retired > COMPACT_MIN && state.retired * 4 > state.swarm.len() {
        state.swarm.compact();
        state.retired = 0;
    }
}

/// Runs each layer stage, in configuration order, whose period ends within the epoch that ends
/// with step `to`: at most once per epoch, at its end.
fn stages(config: &SimulationConfig, plan: &Plan, state: &mut State, to: u64, events: &mut dyn EventHandler) {
    let due = |every: u64| every > 0 && to / every > state.settled / every;
    if !plan.stages.iter().any(|(every, _)| due(*every)) {
        return;
    }
    let found = state.failures.len();
    let time = to as f64 * config.dt;
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
                born: to as u32,
                quantum: config.volume_quantum(),
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
/// run).
fn grow_allowances(state: &mut State) {
    let grown: Vec<_> = state
        .targets
        .iter()
        .filter(|t| t.surface.max_thickness() > state.scene.surface(t.surface_id).layer)
        .flat_map(|t| {
            let reach = (2.0 * t.surface.max_thickness()).max(0.01);
            (0..t.pieces).map(move |k| (SurfaceId(t.surface_id.0 + k), reach))
        })
        .collect();
    if !grown.is_empty() {
        state.scene.set_layer_allowances(&grown);
    }
}
