//! Emit stage: the nozzle's emitter spawns this step's particles, and the path metrics take
//! their sample of the nozzle's pose.

use super::{Plan, State, Workers};
use crate::config::SimulationConfig;
use crate::deposit::DepositSurface;
use crate::emission::NozzleFrame;
use crate::events::{EmissionEvent, EventHandler};
use crate::world::Role;
use glam::DVec3;
use rayon::prelude::*;

/// Emitting at least this many particles in one step samples them in parallel (a raster at
/// 10⁵ particles/s and Δt = 1 ms emits 100 a step, which is worth sharing).
const EMIT_PARALLEL: u64 = 64;

/// Spawns the step's particles, if the nozzle sprays.
pub(super) fn run(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    workers: &Workers,
    events: &mut dyn EventHandler,
) {
    let time = state.step as f64 * config.dt;
    let (frame, spraying) = state.nozzle.at(time);
    if !spraying {
        return;
    }
    let nozzle_velocity = state.nozzle.velocity(time);
    record_path(config, state, &frame, state.nozzle.travel_velocity(time), nozzle_velocity);
    let carried = if config.add_nozzle_velocity { nozzle_velocity } else { DVec3::ZERO };
    let emitter = &config.emitter;
    let n = emitter.spawn_count(config.dt, &mut state.spawn_carry);
    let volume = emitter.particle_volume as f32;
    let (key, first) = (plan.key, state.next_id);
    // Each particle samples from its own stream, so the split over threads cannot change the
    // result; small batches are not worth the dispatch.
    let sampler = emitter.sampler();
    // The configuration bounds the run's particle count by 2³², so every id fits in 32 bits.
    let sample = |id: u64| {
        let (pos, vel) = sampler.sample(&frame, &mut key.stream(id as u32, 0));
        (pos, vel + carried)
    };
    let born: Vec<_> = if n >= EMIT_PARALLEL && workers.parallel() {
        workers.install(|| (first..first + n).into_par_iter().map(sample).collect())
    } else {
        (first..first + n).map(sample).collect()
    };
    for (k, (pos, vel)) in born.into_iter().enumerate() {
        state.swarm.push(pos, vel, (first + k as u64) as u32);
        state.tally.emitted.add(f64::from(volume));
    }
    state.next_id += n;
    events.emission(&EmissionEvent { time, first, count: n, volume: emitter.particle_volume });
}

/// Path-quality sample of a spraying step: standoff and angle to the nearest substrate surface
/// along the spray axis, and travel speed, against the recommended window; the nozzle's total
/// speed (`velocity`, circle included) beside it.
fn record_path(
    config: &SimulationConfig,
    state: &mut State,
    frame: &NozzleFrame,
    travel: DVec3,
    velocity: DVec3,
) {
    let w = &config.window;
    let reach = config.domain.max.distance(config.domain.min);
    let far = frame.position + frame.axis * reach;
    let nearest = state
        .targets
        .iter()
        .filter(|t| t.role == Role::Substrate)
        .filter_map(|t| t.surface.intersect(frame.position, far))
        .min_by(|a, b| a.t.total_cmp(&b.t));
    let p = &mut state.path;
    p.samples += 1;
    if let Some(hit) = nearest {
        let standoff = hit.t * reach;
        let angle = (-frame.axis.dot(hit.normal)).clamp(-1.0, 1.0).acos().to_degrees();
        p.standoff.add(standoff, (w.standoff[0]..=w.standoff[1]).contains(&standoff));
        p.angle.add(angle, angle <= w.max_angle);
    }
    let speed = travel.length();
    p.travel_speed.add(speed, (w.speed[0]..=w.speed[1]).contains(&speed));
    p.nozzle_speed.add(velocity.length(), true);
}
