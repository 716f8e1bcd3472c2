//! The simulation pipeline. A [`Simulation`] holds its resolved parameters (a
//! [`SimulationConfig`], shared and immutable) and plain data sets (swarm, scene, targets,
//! obstacles, tallies); [`Simulation::step`] runs named stages over them in a fixed order:
//!
//! 1. **emit** (`emit.rs`): the nozzle's emitter spawns this step's particles;
//! 2. **update** (`update.rs`): every particle in flight moves, collides and resolves its
//!    impacts (parallel over fixed-size chunks, each particle with its own random stream);
//! 3. **apply** (`apply.rs`): impact records are applied to deposits and tallies in particle
//!    order, each booked by the target or obstacle struck (`Target::record_impact`), and
//!    impact events reach the event handler;
//! 4. **layers** (`layers.rs`): the layer stages (cohesion, drip, …) at their intervals; then
//!    **watch** (`watch.rs`) wakes the sleeping particles a layer has grown under, and the
//!    broad phase is told how far the layers have grown (waking the sleepers that come near a
//!    grown zone);
//! 5. **compact**: retired particles are dropped from the swarm once they are many.
//!
//! Because chunks are fixed in size and records are applied in order, the result is
//! bit-identical whatever the number of threads.

mod apply;
mod emit;
mod layers;
mod persist;
mod setup;
mod update;
mod watch;

use crate::collision::Scene;
use crate::config::{ConfigError, MAX_COORD, SimulationConfig};
use crate::emission::NozzlePath;
use crate::events::{Both, EventHandler, FailureEvent, ImpactEvent, ImpactLog};
use crate::motion::{Integrator, Lanes};
use crate::particles::{StreamKey, Swarm};
use crate::process::{ImpactModel, LayerStage};
use crate::tally::{PathTally, Tally};
use crate::world::{Obstacle, Target};
use std::sync::Arc;

/// Particles per work unit of the update stage. Fixed, so that the split of work, and with it
/// the order in which records are applied, never depends on the thread count.
/// Small enough that a step with few particles awake still splits into enough tasks to keep
/// every thread busy: a raster at 10⁵ particles/s has about 11 000 in flight, of which about 800
/// are awake in a step, most of them in the youngest chunks.
const CHUNK: usize = 256;

/// The swarm is compacted once more slots than this have retired (and a quarter of them): the
/// former chunk size, so that compaction runs at the steps it always has.
const COMPACT_MIN: usize = 1024;

/// Why a simulation could not be set up.
#[derive(Debug, thiserror::Error)]
pub enum SetupError {
    /// The configuration is not one the engine can run.
    #[error("invalid configuration: {0}")]
    Config(#[from] ConfigError),
    /// The thread pool could not be built.
    #[error("cannot start {threads} worker threads: {message}")]
    Threads {
        /// Worker threads asked for (0: one per core).
        threads: usize,
        /// Why they were refused: over the limit, or the pool failed to start (rayon's error).
        message: String,
    },
}

/// Worker threads per core allowed at most: more only adds start-up time and switching (a
/// pool of 10⁵ threads takes seconds to start before any step runs).
pub const THREADS_PER_CORE: usize = 8;

/// The most worker threads a simulation or a batch accepts on this machine:
/// [`THREADS_PER_CORE`] times its cores, and at least 64, so that thread-count independence can
/// be checked on small machines.
pub fn max_threads() -> usize {
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    (THREADS_PER_CORE * cores).max(64)
}

/// Refuses a thread count above [`max_threads`] (0 stands for one per core, and passes).
pub fn check_threads(threads: usize) -> Result<(), SetupError> {
    let max = max_threads();
    if threads > max {
        let message = format!(
            "at most {max} are allowed on this machine ({THREADS_PER_CORE} per core; 0 uses one per core)"
        );
        return Err(SetupError::Threads { threads, message });
    }
    Ok(())
}

/// Where the stages' parallel loops run (see [`Simulation::set_threads`]).
#[derive(Clone, Debug, Default)]
enum Workers {
    /// rayon's global pool.
    #[default]
    Global,
    /// A pool of the simulation's own.
    Pool(Arc<rayon::ThreadPool>),
    /// The calling thread alone: with one thread, handing every step to a pool only adds a
    /// wake-up and a wait per stage.
    Caller,
}

impl Workers {
    /// True unless the work stays on the calling thread.
    fn parallel(&self) -> bool {
        !matches!(self, Workers::Caller)
    }

    /// Runs `work` (which uses rayon's parallel iterators) on these workers.
    fn install<R: Send>(&self, work: impl FnOnce() -> R + Send) -> R {
        match self {
            Workers::Pool(pool) => pool.install(work),
            Workers::Global | Workers::Caller => work(),
        }
    }
}

/// What the configuration fixes for the whole run, worked out once.
#[derive(Clone, Debug)]
struct Plan {
    total_steps: u64,
    key: StreamKey,
    /// Impact model of each surface owner (targets, then obstacles); surfaces index it.
    models: Vec<ImpactModel>,
    /// Layer stages with their period in steps.
    stages: Vec<(u64, Arc<dyn LayerStage>)>,
}

/// The data sets the stages work on.
#[derive(Clone, Debug)]
struct State {
    step: u64,
    swarm: Swarm,
    retired: usize,
    /// Fractional particles carried to the next spraying step.
    spawn_carry: f64,
    nozzle: NozzlePath,
    scene: Scene,
    targets: Vec<Target>,
    obstacles: Vec<Obstacle>,
    tally: Tally,
    next_id: u64,
    particle_steps: u64,
    particle_updates: u64,
    failures: Vec<FailureEvent>,
    path: PathTally,
    impact_log: Option<ImpactLog>,
    /// The layer nodes that sleeping particles watch.
    watches: watch::Watches,
}

/// A running simulation.
///
/// Cloning one is a snapshot: the clone continues exactly as the original would.
///
/// ```
/// use spraysim_engine::{Simulation, SimulationConfig};
///
/// let mut sim = Simulation::new(SimulationConfig::example_wall(0.05))?;
/// sim.step(); // one Δt
/// let snapshot = sim.clone();
/// sim.run(|_| {}); // to the end
/// let m = sim.metrics();
/// assert_eq!(m.emitted.count, m.fates.total().count);
/// assert!(m.emitted.count >= 499); // 10⁴ particles/s for 0.05 s
/// let mut again = snapshot;
/// again.run(|_| {});
/// assert_eq!(again.metrics().emitted, m.emitted);
/// # Ok::<(), spraysim_engine::SetupError>(())
/// ```
#[derive(Clone, Debug)]
pub struct Simulation {
    config: Arc<SimulationConfig>,
    plan: Plan,
    state: State,
    workers: Workers,
    /// See [`Simulation::set_lazy_flight`].
    lazy_flight: bool,
    /// See [`Simulation::set_lanes`].
    lanes: Lanes,
}

impl Simulation {
    /// Sets up a simulation of `config` at time 0.
    pub fn new(config: SimulationConfig) -> Result<Simulation, SetupError> {
        config.check()?;
        Ok(setup::build(Arc::new(config), None))
    }

    /// Sets this simulation up afresh for `config`, at time 0, as [`Simulation::new`] would and
    /// with bit-identical results, but reusing the broad phase when the geometry (the targets'
    /// and obstacles' shapes and the domain) is unchanged: in a loop of many runs of one scene
    /// (calibration, trajectory optimisation, seeds) the index is built once. The thread and
    /// lazy-flight and lane settings are kept. On an error nothing changes.
    ///
    /// ```
    /// use spraysim_engine::{Simulation, SimulationConfig};
    ///
    /// let config = SimulationConfig::example_wall(0.2);
    /// let mut sim = Simulation::new(config.clone())?;
    /// let mut layers = Vec::new();
    /// for seed in 0..3 {
    ///     sim.restart(SimulationConfig { seed, ..config.clone() })?;
    ///     sim.run(|_| {});
    ///     layers.push(sim.metrics().targets[0].layer_volume);
    /// }
    /// let mut fresh = Simulation::new(SimulationConfig { seed: 2, ..config })?;
    /// fresh.run(|_| {});
    /// assert!(layers[2] > 0.0 && layers[2] != layers[1]);
    /// assert_eq!(fresh.metrics().targets[0].layer_volume, layers[2]);
    /// # Ok::<(), spraysim_engine::SetupError>(())
    /// ```
    pub fn restart(&mut self, config: SimulationConfig) -> Result<(), SetupError> {
        config.check()?;
        let scene = std::mem::take(&mut self.state.scene);
        let fresh = setup::build(Arc::new(config), Some(scene));
        (self.config, self.plan, self.state) = (fresh.config, fresh.plan, fresh.state);
        Ok(())
    }

    /// Runs the update stage on at most `threads` threads (0: rayon's global pool, one thread
    /// per core; 1: the calling thread alone, without a pool). Results do not depend on it.
    /// A count above [`max_threads`] is refused at once, before any thread starts.
    pub fn set_threads(&mut self, threads: usize) -> Result<(), SetupError> {
        check_threads(threads)?;
        self.workers = match threads {
            0 => Workers::Global,
            1 => Workers::Caller,
            _ => {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .map_err(|e| SetupError::Threads { threads, message: e.to_string() })?;
                Workers::Pool(Arc::new(pool))
            }
        };
        Ok(())
    }

    /// The resolved parameters being simulated.
    pub fn config(&self) -> &SimulationConfig {
        &self.config
    }

    /// The nozzle's path: pose and spray state over time.
    pub fn nozzle(&self) -> &NozzlePath {
        &self.state.nozzle
    }

    /// Replaces the nozzle's path from the next step on (closed-loop control): the path is in
    /// absolute time, so a path built for the rest of a run starts at [`Simulation::time`].
    /// A path that [`NozzlePath::check`] refuses (a NaN position, a zero axis, a point beyond
    /// [`MAX_COORD`] m) is refused, and the path is left as it was.
    pub fn set_nozzle_path(&mut self, path: NozzlePath) -> Result<(), ConfigError> {
        path.check(MAX_COORD).map_err(|message| ConfigError { field: "nozzle".into(), message })?;
        self.state.nozzle = path;
        Ok(())
    }

    /// Simulated time, s.
    pub fn time(&self) -> f64 {
        self.state.step as f64 * self.config.dt
    }

    /// Steps taken so far.
    pub fn steps_done(&self) -> u64 {
        self.state.step
    }

    /// Particle-steps so far: Σ over steps of the particles in flight during that step.
    pub fn particle_steps(&self) -> u64 {
        self.state.particle_steps
    }

    /// Particle updates so far: the particle-steps not skipped in free flight (fewer than
    /// [`Simulation::particle_steps`] only with the exact integrator; see
    /// [`Simulation::set_lazy_flight`]). The work done, where particle-steps are the work
    /// simulated.
    pub fn particle_updates(&self) -> u64 {
        self.state.particle_updates
    }

    /// Steps the configured duration takes (the last one may end past the duration).
    pub fn total_steps(&self) -> u64 {
        self.plan.total_steps
    }

    /// True once the configured duration has been simulated.
    pub fn is_finished(&self) -> bool {
        self.state.step >= self.plan.total_steps
    }

    /// The particles, in flight and recently retired (see [`crate::particles::flags`]).
    pub fn swarm(&self) -> &Swarm {
        &self.state.swarm
    }

    /// Position (m), velocity (m/s) and age (s) of the particle in swarm slot `i` at the present
    /// time ([`Simulation::time`]). These are the swarm's own arrays, except for a particle
    /// asleep in free flight (exact integrator, see [`Simulation::set_lazy_flight`]), whose
    /// arrays hold its state at the step it wakes: it is brought back to the present in closed
    /// form. Panics if `i` is not a slot of the swarm.
    pub fn particle_now(&self, i: usize) -> (glam::DVec3, glam::DVec3, f64) {
        use crate::collision::Flight;
        let s = &self.state.swarm;
        let (pos, vel, age) = (s.pos[i], s.vel[i], f64::from(s.age[i]));
        let wake = u64::from(s.wake[i]);
        if wake <= self.state.step {
            return (pos, vel, age);
        }
        let back = -((wake - self.state.step) as f64 * self.config.dt);
        let flight = Flight { x0: pos, v0: vel, g: self.config.motion.gravity, duration: 0.0 };
        (flight.at(back), flight.velocity(back), age + back)
    }

    /// The collidable surfaces, indexed.
    pub fn scene(&self) -> &Scene {
        &self.state.scene
    }

    /// The targets and their deposits, in configuration order.
    pub fn targets(&self) -> &[Target] {
        &self.state.targets
    }

    /// The obstacles and their tallies, in configuration order.
    pub fn obstacles(&self) -> &[Obstacle] {
        &self.state.obstacles
    }

    /// Running totals.
    pub fn tally(&self) -> &Tally {
        &self.state.tally
    }

    /// Statistics of the nozzle's path while spraying.
    pub fn path_tally(&self) -> &PathTally {
        &self.state.path
    }

    /// Every cohesive failure so far, in time order.
    pub fn failures(&self) -> &[FailureEvent] {
        &self.state.failures
    }

    /// The sampled impacts so far, in the order they were applied (see
    /// [`SimulationConfig::impact_log`]).
    pub fn impact_log(&self) -> &[ImpactEvent] {
        self.state.impact_log.as_ref().map_or(&[], |l| &l.entries)
    }

    /// Runs steps until the duration is reached, calling `progress` after each.
    pub fn run(&mut self, mut progress: impl FnMut(&Simulation)) {
        while !self.is_finished() {
            self.step();
            progress(self);
        }
    }

    /// Advances the simulation by one time step Δt (also past the configured duration).
    pub fn step(&mut self) {
        self.step_with(&mut ());
    }

    /// [`Simulation::step`], reporting what happens to `events`.
    pub fn step_with(&mut self, events: &mut dyn EventHandler) {
        let mut log = self.state.impact_log.take();
        // Impacts are gathered in the parallel stage only as far as someone wants them.
        let capture = match &log {
            _ if events.wants_impacts() => update::Capture::All,
            Some(l) if l.wants_impacts() => update::Capture::Sampled { fraction: l.fraction, salt: l.salt },
            _ => update::Capture::Nothing,
        };
        {
            let mut none = ();
            let log: &mut dyn EventHandler = match &mut log {
                Some(l) => l,
                None => &mut none,
            };
            let mut both = Both(log, events);
            let time = self.time();
            emit::run(&self.config, &self.plan, &mut self.state, &self.workers, &mut both);
            let lazy = self.lazy();
            let outcomes = update::run(
                &self.config,
                &self.plan,
                &mut self.state,
                &self.workers,
                lazy,
                self.lanes,
                capture,
            );
            apply::run(&mut self.state, outcomes, &mut both);
            layers::run(&self.config, &self.plan, &mut self.state, &mut both);
            watch::run(&self.config, &mut self.state);
            layers::grow_allowances(&self.config, &mut self.state, lazy);
            if self.state.retired > COMPACT_MIN && self.state.retired * 4 > self.state.swarm.len() {
                self.state.swarm.compact();
                self.state.retired = 0;
            }
            self.state.step += 1;
            both.step_end(time + self.config.dt);
        }
        self.state.impact_log = log;
    }

    /// With the exact integrator, flight is event-driven: a particle skips the steps in which it
    /// certainly meets nothing, up to the step of its next event (see
    /// [`crate::particles::Swarm::wake`]); on by default. Turning it off steps every particle
    /// through every step, for comparison: results agree to rounding.
    pub fn set_lazy_flight(&mut self, on: bool) {
        self.lazy_flight = on;
        if !on {
            watch::wake_all(&self.config, &mut self.state);
        }
    }

    /// Chooses the instruction set of the free-flight kernel (see [`crate::motion::lanes`]): by
    /// default the widest this processor runs. Results are bit-identical on every one; this is
    /// for measuring what the lanes are worth.
    pub fn set_lanes(&mut self, lanes: Lanes) {
        self.lanes = lanes;
    }

    /// The instruction set the free-flight kernel runs on, on this processor.
    pub fn lanes(&self) -> Lanes {
        self.lanes.effective()
    }

    /// Heap memory (bytes) of what the event-driven flight keeps beside the swarm: the layer
    /// nodes that sleeping particles watch (0 with the explicit integrators).
    pub fn watch_bytes(&self) -> usize {
        self.state.watches.heap_bytes()
    }

    fn lazy(&self) -> bool {
        self.lazy_flight && self.config.motion.integrator == Integrator::Exact
    }
}
