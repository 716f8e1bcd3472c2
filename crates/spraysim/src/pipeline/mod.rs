//! The simulation pipeline: a [`Simulation`] owns plain data sets (swarm, scene, targets) and
//! its [`Simulation::step`] runs named stages over them in a fixed order:
//!
//! 1. **emit**: the nozzle's emitter spawns this step's particles (sequential, cheap);
//! 2. **update**: every particle in flight moves, collides and resolves its impacts (parallel
//!    over fixed-size chunks, each particle with its own random stream);
//! 3. **apply**: impact records are applied to heightfields and tallies in particle order;
//! 4. **compact**: retired particles are dropped from the swarm once they are many.
//!
//! Because chunks are fixed in size and records are applied in order, the result is
//! bit-identical whatever the number of threads.

mod setup;
mod update;

use crate::cohesion::{self, Strength};
use crate::collision::{Aabb, Arc, Scene, SurfaceKind};
use crate::emitter::Emitter;
use crate::impact::ImpactModel;
use crate::integrator::{Integrator, Motion};
use crate::metrics::{FailureEvent, Metrics, PathTally, Tally};
use crate::nozzle::NozzlePath;
use crate::rng::StreamKey;
use crate::scenario::Role;
use crate::scenario::{Scenario, ScenarioError};
use crate::swarm::{Swarm, flags};
use crate::target::{Obstacle, Target};
use glam::DVec3;
use rayon::prelude::*;
pub use update::LoggedImpact;
use update::{SwarmChunk, UpdateContext, record};

/// Distance in front of the face at which failed material is released, m: clear of the face
/// for any straight or curved flight test.
const RELEASE_OFFSET: f64 = 1e-6;

/// Particles per work unit of the update stage. Fixed, so that the split of work, and with it
/// the order in which records are applied, never depends on the thread count.
const CHUNK: usize = 4096;

/// Emitting at least this many particles in one step samples them in parallel.
const EMIT_PARALLEL: u64 = 256;

/// Why a simulation could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// The scenario is invalid.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// A mesh file could not be read.
    #[error(transparent)]
    Mesh(#[from] crate::io::mesh::MeshError),
    /// The thread pool could not be built.
    #[error("cannot start {threads} worker threads: {message}")]
    Threads {
        /// Requested count.
        threads: usize,
        /// Reason.
        message: String,
    },
}

/// A running simulation of one scenario.
///
/// ```
/// use spraysim::{Scenario, Simulation};
///
/// let mut scenario = Scenario::default_scene();
/// scenario.simulation.duration = 0.05; // s
/// let mut sim = Simulation::new(&scenario)?;
/// sim.step(); // one Δt
/// sim.run(|_| {}); // to the end
/// let m = sim.metrics();
/// assert_eq!(m.emitted.count, m.fates.total().count);
/// assert!(m.emitted.count >= 499); // 10⁴ particles/s for 0.05 s
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct Simulation {
    scenario: Scenario,
    step: u64,
    total_steps: u64,
    swarm: Swarm,
    retired: usize,
    emitter: Emitter,
    nozzle: NozzlePath,
    scene: Scene,
    models: Vec<ImpactModel>,
    motion: Motion,
    domain: Aabb,
    targets: Vec<Target>,
    obstacles: Vec<Obstacle>,
    tally: Tally,
    key: StreamKey,
    next_id: u64,
    particle_steps: u64,
    particle_updates: u64,
    /// Steps between cohesion analyses (0: off).
    cohesion_every: u64,
    /// Steps between drip passes (0: off).
    drip_every: u64,
    failures: Vec<FailureEvent>,
    path: PathTally,
    impact_log: Vec<LoggedImpact>,
    pool: Option<rayon::ThreadPool>,
    /// See [`Simulation::set_lazy_flight`].
    lazy_flight: bool,
}

impl Simulation {
    /// Sets up a simulation of `scenario` at time 0. The scenario is validated first.
    pub fn new(scenario: &Scenario) -> Result<Simulation, SetupError> {
        scenario.validate().map_err(|inv| ScenarioError::Invalid {
            location: "<scenario>".into(),
            key: inv.key,
            message: inv.message,
        })?;
        setup::build(scenario)
    }

    /// Runs the update stage on at most `threads` threads (0: rayon's global pool, one thread
    /// per core). Results do not depend on it.
    pub fn set_threads(&mut self, threads: usize) -> Result<(), SetupError> {
        self.pool = if threads == 0 {
            None
        } else {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .map_err(|e| SetupError::Threads { threads, message: e.to_string() })?;
            Some(pool)
        };
        Ok(())
    }

    /// The nozzle's path: pose and spray state over time.
    pub fn nozzle(&self) -> &NozzlePath {
        &self.nozzle
    }

    /// The resolved scenario being simulated.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.scenario.simulation.dt
    }

    /// Steps taken so far.
    pub fn steps_done(&self) -> u64 {
        self.step
    }

    /// Particle-steps so far: Σ over steps of the particles in flight during that step.
    pub fn particle_steps(&self) -> u64 {
        self.particle_steps
    }

    /// Particle updates so far: the particle-steps not skipped in free flight (fewer than
    /// [`Simulation::particle_steps`] only with the exact integrator; see
    /// [`Simulation::set_lazy_flight`]). The work done, where particle-steps are the work
    /// simulated.
    pub fn particle_updates(&self) -> u64 {
        self.particle_updates
    }

    /// Steps the scenario's duration takes (the last one may end past the duration).
    pub fn total_steps(&self) -> u64 {
        self.total_steps
    }

    /// True once the scenario's duration has been simulated.
    pub fn is_finished(&self) -> bool {
        self.step >= self.total_steps
    }

    /// The particles, in flight and recently retired (see [`crate::swarm::flags`]).
    pub fn swarm(&self) -> &Swarm {
        &self.swarm
    }

    /// The collidable surfaces (target faces first, then obstacles).
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The targets and their heightfields.
    pub fn targets(&self) -> &[Target] {
        &self.targets
    }

    /// The obstacles and their tallies.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.obstacles
    }

    /// The sampled impacts so far, in the order they were applied (see `[output] impact_log`).
    pub fn impact_log(&self) -> &[LoggedImpact] {
        &self.impact_log
    }

    /// The metrics as of now.
    pub fn metrics(&self) -> Metrics {
        Metrics::collect(self, &self.tally, &self.failures, &self.path)
    }

    /// Runs steps until the duration is reached, calling `progress` after each.
    pub fn run(&mut self, mut progress: impl FnMut(&Simulation)) {
        while !self.is_finished() {
            self.step();
            progress(self);
        }
    }

    /// Advances the simulation by one time step Δt (also past the scenario's duration).
    pub fn step(&mut self) {
        self.emit();
        let outcomes = self.update();
        self.apply(outcomes);
        if self.cohesion_every > 0 && (self.step + 1).is_multiple_of(self.cohesion_every) {
            self.cohesion();
        }
        if self.drip_every > 0 && (self.step + 1).is_multiple_of(self.drip_every) {
            self.drip();
        }
        self.grow_layer_allowances();
        if self.retired > CHUNK && self.retired * 4 > self.swarm.len() {
            self.swarm.compact();
            self.retired = 0;
        }
        self.step += 1;
    }

    fn emit(&mut self) {
        let (frame, spraying) = self.nozzle.at(self.time());
        if !spraying {
            return;
        }
        let nozzle_velocity = self.nozzle.velocity(self.time());
        self.record_path(&frame, nozzle_velocity);
        let carried = if self.scenario.nozzle.add_velocity { nozzle_velocity } else { DVec3::ZERO };
        let n = self.emitter.spawn_count(self.scenario.simulation.dt);
        let volume = self.emitter.particle_volume as f32;
        let (emitter, key, first) = (&self.emitter, self.key, self.next_id);
        // Each particle samples from its own stream, so the split over threads cannot change
        // the result; small batches are not worth the dispatch.
        let sample = |id: u64| {
            let (pos, vel) = emitter.sample(&frame, &mut key.stream(id, 0));
            (pos, vel + carried)
        };
        let born: Vec<_> = if n >= EMIT_PARALLEL {
            let work = || (first..first + n).into_par_iter().map(sample).collect();
            match &self.pool {
                Some(pool) => pool.install(work),
                None => work(),
            }
        } else {
            (first..first + n).map(sample).collect()
        };
        for (k, (pos, vel)) in born.into_iter().enumerate() {
            // Validation bounds the run's particle count by 2³², so the id fits.
            self.swarm.push(pos, vel, (first + k as u64) as u32);
            self.tally.emitted.add(f64::from(volume));
        }
        self.next_id += n;
    }

    /// Path-quality sample of a spraying step: standoff and angle to the nearest substrate face
    /// along the spray axis, and travel speed, against the process's window.
    fn record_path(&mut self, frame: &crate::nozzle::NozzleFrame, velocity: DVec3) {
        let w = &self.scenario.process.window;
        let reach = self.domain.max.distance(self.domain.min);
        let far = frame.position + frame.axis * reach;
        let nearest = self
            .targets
            .iter()
            .filter(|t| t.role == Role::Substrate)
            .filter_map(|t| t.face.intersect(frame.position, far))
            .min_by(|a, b| a.t.total_cmp(&b.t));
        let p = &mut self.path;
        p.samples += 1;
        if let Some(hit) = nearest {
            let standoff = hit.t * reach;
            let angle = (-frame.axis.dot(hit.normal)).clamp(-1.0, 1.0).acos().to_degrees();
            p.standoff.add(standoff, (w.standoff[0]..=w.standoff[1]).contains(&standoff));
            p.angle.add(angle, angle <= w.max_angle);
        }
        let speed = velocity.length();
        p.speed.add(speed, (w.speed[0]..=w.speed[1]).contains(&speed));
    }

    /// Drip stage: on tilted faces, wet film beyond the sag limit (`sag_threshold / sin β`)
    /// runs off and falls as released particles, one per cell.
    fn drip(&mut self) {
        let threshold = self.scenario.process.sag_threshold;
        for t in &mut self.targets {
            let Some(limit) = t.sag_limit(threshold) else { continue };
            for cell in 0..t.field.thickness().len() as u32 {
                let excess = t.field.thickness()[cell as usize] - limit;
                if excess > 0.0 {
                    let area = t.field.cell_area();
                    let removed =
                        release(t, cell, excess * area, &mut self.swarm, &mut self.tally, &mut self.next_id);
                    self.tally.dripped.add(removed);
                }
            }
        }
    }

    /// Keeps the broad phase aware of every layer: when a target's layer outgrows the reach it
    /// was indexed with, the reach doubles and the scene is re-indexed (a few times per run).
    fn grow_layer_allowances(&mut self) {
        let mut grown = false;
        for (i, t) in self.targets.iter().enumerate() {
            // Target faces come first among the surfaces, in target order.
            let top = t.field.max_thickness();
            if top > self.scene.surfaces()[i].layer {
                self.scene.set_layer_allowance(i, (2.0 * top).max(0.01));
                grown = true;
            }
        }
        // Only the exact integrator lets particles sleep.
        if grown && self.lazy() {
            self.wake_all();
        }
    }

    /// With the exact integrator, particles in free flight skip the steps in which they
    /// certainly meet nothing (see [`crate::swarm::Swarm::wake`]); on by default. Turning it
    /// off steps every particle through every step, for comparison: results agree to rounding.
    pub fn set_lazy_flight(&mut self, on: bool) {
        self.lazy_flight = on;
        if !on {
            self.wake_all();
        }
    }

    fn lazy(&self) -> bool {
        self.lazy_flight && self.motion.integrator == Integrator::Exact
    }

    /// Brings every sleeping particle back to the present (in closed form) so that it is
    /// updated next step: the scene it was cleared against has grown.
    fn wake_all(&mut self) {
        let now = self.step + 1;
        let (dt, g) = (self.scenario.simulation.dt, self.motion.gravity);
        let s = &mut self.swarm;
        for i in 0..s.len() {
            let wake = u64::from(s.wake[i]);
            if wake > now {
                let back = -((wake - now) as f64 * dt);
                let flight = Arc { x0: s.pos[i], v0: s.vel[i], g, duration: 0.0 };
                s.pos[i] = flight.at(back);
                s.vel[i] = flight.velocity(back);
                s.age[i] = (f64::from(s.age[i]) + back) as f32;
            }
            s.wake[i] = 0;
        }
    }

    /// Cohesion stage: analyses every target's layer; failing regions leave the heightfield
    /// and fall as particles, one per cell carrying that cell's volume, released just in front
    /// of the face at rest (in target, region and cell order, so deterministically).
    fn cohesion(&mut self) {
        let c = &self.scenario.process.cohesion;
        let strength =
            Strength { tensile: c.tensile_strength, shear: c.shear_strength, cohesion: c.cohesion };
        let density = self.scenario.process.density;
        let time = self.time() + self.scenario.simulation.dt;
        for t in &mut self.targets {
            let analysis =
                cohesion::analyse(&t.field, t.face.normal, density, self.motion.gravity, &strength);
            t.failure_mask.iter_mut().filter(|m| **m == 1).for_each(|m| *m = 0);
            for region in &analysis.regions {
                if !region.fails() {
                    for &cell in &region.cells {
                        let m = &mut t.failure_mask[cell as usize];
                        *m = (*m).max(1);
                    }
                    continue;
                }
                let mut volume = 0.0;
                for &cell in &region.cells {
                    t.failure_mask[cell as usize] = 2;
                    volume +=
                        release(t, cell, f64::INFINITY, &mut self.swarm, &mut self.tally, &mut self.next_id);
                }
                let area = region.cells.len() as f64 * t.field.cell_area();
                self.failures.push(FailureEvent {
                    time,
                    target: t.name.clone(),
                    cells: region.cells.len(),
                    area,
                    volume,
                });
            }
        }
    }

    fn update(&mut self) -> Vec<update::ChunkOutcome> {
        let ctx = UpdateContext {
            scene: &self.scene,
            models: &self.models,
            targets: &self.targets,
            motion: self.motion,
            domain: self.domain,
            dt: self.scenario.simulation.dt,
            key: self.key,
            max_impacts: self.scenario.simulation.max_impacts_per_step,
            max_lifetime: self.scenario.process.max_lifetime,
            erosion: &self.scenario.process.erosion,
            density: self.scenario.process.density,
            time: self.time(),
            log_fraction: self.scenario.output.impact_log,
            log_salt: self.scenario.simulation.seed,
            step: self.step,
            lazy: self.lazy(),
        };
        let s = &mut self.swarm;
        self.particle_steps += (s.len() - self.retired) as u64;
        let chunks: Vec<SwarmChunk<'_>> = s
            .pos
            .chunks_mut(CHUNK)
            .zip(s.vel.chunks_mut(CHUNK))
            .zip(s.age.chunks_mut(CHUNK))
            .zip(s.id.chunks(CHUNK))
            .zip(s.impacts.chunks_mut(CHUNK))
            .zip(s.flags.chunks_mut(CHUNK))
            .zip(s.wake.chunks_mut(CHUNK))
            .map(|((((((pos, vel), age), id), impacts), flags), wake)| SwarmChunk {
                pos,
                vel,
                age,
                volumes: &s.volumes,
                id,
                impacts,
                flags,
                wake,
            })
            .collect();
        // One task per chunk: their costs differ widely (old rebounds near surfaces against
        // young particles in free flight), so idle threads must be able to take any of them.
        let work = || chunks.into_par_iter().with_max_len(1).map(|c| ctx.run_chunk(c)).collect();
        match &self.pool {
            Some(pool) => pool.install(work),
            None => work(),
        }
    }

    fn apply(&mut self, outcomes: Vec<update::ChunkOutcome>) {
        for out in outcomes {
            for rec in &out.impacts {
                let volume = f64::from(rec.volume);
                let stuck = rec.flags & record::STUCK != 0;
                let released = rec.flags & record::RELEASED != 0;
                let back = rec.flags & record::BACK != 0;
                match self.scene.surfaces()[rec.surface as usize].kind {
                    SurfaceKind::Target(i) => {
                        let t = &mut self.targets[i];
                        t.hits += 1;
                        if !back {
                            t.field.add_hit(rec.cell);
                            if rec.eroded > 0.0 {
                                let depth = f64::from(rec.eroded) / t.field.cell_area();
                                let c = rec.cell as usize;
                                t.erosion[c] += depth;
                                t.coating[c] = (t.coating[c] - depth).max(0.0);
                            }
                        }
                        if stuck {
                            if !back {
                                t.field.deposit(rec.cell, volume);
                            }
                            match (released, back) {
                                (true, _) => {
                                    t.received.add(volume);
                                    if back {
                                        t.received_back += volume;
                                    }
                                }
                                (false, true) => t.stuck_back.add(volume),
                                (false, false) => t.stuck.add(volume),
                            }
                        }
                    }
                    SurfaceKind::Obstacle(i) => {
                        let o = &mut self.obstacles[i];
                        o.hits += 1;
                        if stuck {
                            if released { &mut o.received } else { &mut o.stuck }.add(volume);
                        }
                    }
                }
                if rec.flags & record::FIRST_SUBSTRATE != 0 {
                    self.tally.substrate_first_impacts.add(volume);
                    if !stuck {
                        self.tally.substrate_first_rebounds.add(volume);
                    }
                }
            }
            let t = &mut self.tally;
            t.left_domain = t.left_domain + out.left_domain;
            t.expired = t.expired + out.expired;
            t.released_left = t.released_left + out.released_left;
            t.released_expired = t.released_expired + out.released_expired;
            self.retired += out.retired;
            self.particle_updates += out.updated;
            self.impact_log.extend(out.log);
        }
        debug_assert_eq!(self.retired, self.swarm.flags.iter().filter(|&&f| f & flags::ALIVE == 0).count());
    }
}

/// Releases up to `volume` (m³) of cell `cell`'s layer as a particle at rest just in front of
/// the face (released material never counts towards the rebound ratio); returns the volume.
fn release(
    t: &mut Target,
    cell: u32,
    volume: f64,
    swarm: &mut Swarm,
    tally: &mut Tally,
    next_id: &mut u64,
) -> f64 {
    let removed = t.field.remove(cell, volume);
    let (u, v) = t.field.cell_center(cell);
    let pos = t.face.center + t.face.right * u + t.face.up * v + t.face.normal * RELEASE_OFFSET;
    let bits = flags::ALIVE | flags::RELEASED | flags::HIT_SUBSTRATE;
    swarm.push_released(pos, DVec3::ZERO, removed as f32, *next_id as u32, bits);
    *next_id += 1;
    tally.released.add(f64::from(removed as f32));
    t.detached.add(removed);
    removed
}
