//! Emission: the particles the nozzle spawns in each step, and the path metrics' samples of
//! its pose.
//!
//! The schedule is serial and cheap (a spawn count that carries its fraction from step to
//! step, ids handed out in order, one pose per step); sampling each particle's start is done
//! in the parallel part of a call, each from its own random stream.

use super::State;
use crate::collision::Hit;
use crate::config::SimulationConfig;
use crate::deposit::DepositSurface;
use crate::emission::{NozzleFrame, NozzlePath, Sampler};
use crate::events::EmissionEvent;
use crate::motion::JetFrame;
use crate::particles::{Particle, StreamKey, flags};
use crate::world::Role;
use glam::DVec3;

/// The particles the nozzle spawns in one step: how many, their ids, and the nozzle's pose
/// they start from. Each one's start (a point of the aperture, a direction in the cone, a
/// speed) is drawn from the emitter's laws ([`crate::emission::Emitter`]) when it is flown.
#[derive(Clone, Copy, Debug)]
pub struct Births {
    /// The step, whose start they are born at.
    pub step: u64,
    /// The first one's id; the others follow.
    pub first: u64,
    /// Particles the nozzle spawns in this step, ids `first .. first + count`.
    pub count: u64,
    /// The nozzle's pose in that step.
    pub frame: NozzleFrame,
    /// Velocity added to each (the nozzle's own, where the configuration asks for it), m/s.
    pub carried: DVec3,
}

impl Births {
    /// Particle number `k` of this batch (from 0), its start sampled from its own stream of
    /// the run's `key`, as the engine's own flight samples it.
    #[inline]
    pub fn particle(&self, k: u64, sampler: &Sampler<'_>, key: StreamKey) -> Particle {
        // The configuration bounds the run's particle count by 2³², so every id fits in 32 bits.
        let id = (self.first + k) as u32;
        let (pos, vel) = sampler.sample(&self.frame, &mut key.stream(id, 0));
        Particle::new(pos, vel + self.carried, self.step as u32, id, flags::ALIVE)
    }
}

/// Schedules the births of steps `from..to`: hands out their ids, counts them as emitted and
/// takes the path metrics' sample of each spraying step. Returns the batches (one per spraying
/// step) and the emission events with their steps, in step order.
pub(super) fn schedule(
    config: &SimulationConfig,
    state: &mut State,
    from: u64,
    to: u64,
) -> (Vec<Births>, Vec<(u64, EmissionEvent)>) {
    let (mut births, mut events) = (Vec::new(), Vec::new());
    let nozzle_quanta = state.swarm.volumes.nozzle;
    for step in from..to {
        let time = step as f64 * config.dt;
        // A step sprays when the leg it starts in does; a waypoint that rounds to just after the
        // step's time is the same instant, so that every spraying step of a leg whose ends fall
        // on steps is counted, and no step after it.
        if !state.nozzle.sprays(time, NozzlePath::step_slack(time, config.dt)) {
            continue;
        }
        let (frame, _) = state.nozzle.at(time);
        let nozzle_velocity = state.nozzle.velocity(time);
        record_path(config, state, &frame, state.nozzle.travel_velocity(time), nozzle_velocity);
        let carried = if config.add_nozzle_velocity { nozzle_velocity } else { DVec3::ZERO };
        let count = config.emitter.spawn_count(config.dt, &mut state.spawn_carry);
        let first = state.next_id;
        state.next_id += count;
        let emitted = &mut state.tally.emitted;
        emitted.count += count;
        emitted.quanta += u128::from(count) * u128::from(nozzle_quanta);
        births.push(Births { step, first, count, frame, carried });
        events.push((step, EmissionEvent { time, first, count, volume: config.emitter.particle_volume }));
    }
    (births, events)
}

/// Where the spray axis of `frame` first strikes a substrate target's surface: the distance
/// along the axis, m, and the hit.
fn axis_strike(config: &SimulationConfig, state: &State, frame: &NozzleFrame) -> Option<(f64, Hit)> {
    let reach = config.domain.max.distance(config.domain.min);
    let far = frame.position + frame.axis * reach;
    state
        .targets
        .iter()
        .filter(|t| t.role == Role::Substrate)
        .filter_map(|t| t.surface.intersect(frame.position, far))
        .min_by(|a, b| a.t.total_cmp(&b.t))
        .map(|hit| (hit.t * reach, hit))
}

/// The gun's jet in each step of `from..to` (see [`crate::motion::air`]): from the nozzle's
/// pose, striking the first substrate surface along its axis; `None` where the nozzle does not
/// spray (the air is still). Empty without air.
pub(super) fn jets(config: &SimulationConfig, state: &State, from: u64, to: u64) -> Vec<Option<JetFrame>> {
    let Some(air) = &config.motion.air else { return Vec::new() };
    (from..to)
        .map(|step| {
            let time = step as f64 * config.dt;
            if !state.nozzle.sprays(time, NozzlePath::step_slack(time, config.dt)) {
                return None;
            }
            let (frame, _) = state.nozzle.at(time);
            let strike = axis_strike(config, state, &frame).map(|(_, hit)| (hit.point, hit.normal));
            Some(air.frame(frame.position, frame.axis, [frame.width_axis, frame.height_axis], strike))
        })
        .collect()
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
    let nearest = axis_strike(config, state, frame);
    let p = &mut state.path;
    p.samples += 1;
    if let Some((standoff, hit)) = nearest {
        let angle = (-frame.axis.dot(hit.normal)).clamp(-1.0, 1.0).acos().to_degrees();
        p.standoff.add(standoff, (w.standoff[0]..=w.standoff[1]).contains(&standoff));
        p.angle.add(angle, angle <= w.max_angle);
    }
    let speed = travel.length();
    p.travel_speed.add(speed, (w.speed[0]..=w.speed[1]).contains(&speed));
    p.nozzle_speed.add(velocity.length(), true);
}
