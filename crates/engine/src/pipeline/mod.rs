//! The simulation pipeline. A [`Simulation`] holds its resolved parameters (a
//! [`SimulationConfig`], shared and immutable) and plain data sets (swarm, scene, targets,
//! obstacles, tallies), and advances them in **layer epochs** of
//! [`SimulationConfig::layer_epoch`] steps:
//!
//! - Within an epoch, particles see every deposit surface as it stood at the epoch's start,
//!   so they are independent of each other: each is flown through all the steps a call covers
//!   in one go (`kernel.rs`), in one parallel region per call (`epoch.rs`), after the serial
//!   schedule of the steps' births (`emit.rs`).
//! - Deposits, impact counts and wear gather during the epoch in each target's integer
//!   counters, and take effect at its end, with the layer stages (cohesion, drip, slump) that
//!   fall due and the broad phase's layer allowances (`settle.rs`).
//! - Totals are booked in integer quanta, added up in any order to the same sums; events are
//!   sorted by step, particle and impact before they are passed on.
//!
//! So results are bit-identical for any number of threads, and for any split of a run into
//! calls: [`Simulation::step`] one step at a time gives what [`Simulation::advance`] gives an
//! epoch at a time. An epoch of one step couples particles and layers step by step.

mod emit;
mod epoch;
mod kernel;
mod persist;
mod settle;
mod setup;
mod stage;

pub use emit::Births;
pub use stage::{CellBook, FlightJob, FlightReport, FlightStage};

use crate::collision::Scene;
use crate::config::{ConfigError, MAX_COORD, SimulationConfig};
use crate::emission::NozzlePath;
use crate::events::{Both, EventHandler, FailureEvent, ImpactEvent, ImpactLog};
use crate::motion::Integrator;
use crate::particles::{StreamKey, Swarm};
use crate::process::{ImpactModel, LayerStage};
use crate::tally::{PathTally, Tally};
use crate::world::{Obstacle, Target};
use glam::DVec3;
use std::sync::Arc;

/// The swarm is compacted at an epoch's end once more slots than this have retired (and a
/// quarter of them): its serial cost, spread over the particles retired, stays small.
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
    /// Steps per layer epoch.
    epoch: u64,
    key: StreamKey,
    /// Impact model of each surface owner (targets, then obstacles); surfaces index it.
    models: Vec<ImpactModel>,
    /// Layer stages with their period in steps.
    stages: Vec<(u64, Arc<dyn LayerStage>)>,
    /// The emitter's droplet sizes, tabulated, where the gun's air needs them.
    sizes: Option<crate::emission::DropletSizes>,
}

/// The data sets the stages work on.
#[derive(Clone, Debug)]
struct State {
    step: u64,
    swarm: Swarm,
    /// Slots of the swarm whose particles have left flight since the last compaction.
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
    /// Per target, the cells the epoch under way has touched (see [`crate::deposit::Pending`]).
    touched: Vec<Vec<u32>>,
    /// The step at which the last epoch ended (0 at the start).
    settled: u64,
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
    /// See [`Simulation::set_coasting`].
    coasting: bool,
    /// Another backend's flight stage (see [`Simulation::set_flight_stage`]).
    stage: Option<Arc<dyn FlightStage>>,
    /// The first error of the flight stage, which declined a call (see
    /// [`Simulation::flight_stage_error`]).
    stage_error: Option<String>,
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
    /// (calibration, trajectory optimisation, seeds) the index is built once. The thread
    /// setting is kept. On an error nothing changes.
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
        self.stage_error = None;
        Ok(())
    }

    /// Flies the particles on at most `threads` threads (0: rayon's global pool, one thread
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

    /// Particle updates so far: the particle-steps flown as full steps (an exact search for
    /// hits), where the others coasted through open space. The work done, where particle-steps
    /// are the work simulated.
    pub fn particle_updates(&self) -> u64 {
        self.state.particle_updates
    }

    /// Steps the configured duration takes (the last one may end past the duration).
    pub fn total_steps(&self) -> u64 {
        self.plan.total_steps
    }

    /// The step reached `steps` steps from now, or the run's end where that comes first: the
    /// goal of a vectorised step.
    pub fn steps_ahead(&self, steps: u64) -> u64 {
        self.state.step.saturating_add(steps).min(self.plan.total_steps)
    }

    /// True once the configured duration has been simulated.
    pub fn is_finished(&self) -> bool {
        self.state.step >= self.plan.total_steps
    }

    /// The particles, in flight and recently retired (see [`crate::particles::flags`]). One
    /// retired in a call of a flight stage keeps its state from the call's start (the stage hands
    /// back only the particles still in flight); one retired on the engine's own flight, where
    /// it left flight.
    pub fn swarm(&self) -> &Swarm {
        &self.state.swarm
    }

    /// Position (m), velocity (m/s) and age (s) of the particle in swarm slot `i` at the present
    /// time ([`Simulation::time`]), from its anchor (see [`crate::particles::Particle`]).
    /// Panics if `i` is not a slot of the swarm.
    pub fn particle_now(&self, i: usize) -> (DVec3, DVec3, f64) {
        let p = &self.state.swarm.particles[i];
        let age = self.state.step.saturating_sub(u64::from(p.born)) as f64 * self.config.dt;
        let (x, v) = match self.config.motion.integrator {
            Integrator::Exact => p.now(self.config.dt, self.config.motion.gravity),
            Integrator::Euler | Integrator::SemiImplicitEuler => (p.anchor, p.anchor_velocity()),
        };
        (x, v, age)
    }

    /// Position (m), velocity (m/s) and age (s) at the present time of every particle in
    /// flight, in id order (see [`Simulation::particle_now`]).
    pub fn in_flight(&self) -> impl Iterator<Item = (DVec3, DVec3, f64)> + '_ {
        let particles = &self.state.swarm.particles;
        (0..particles.len()).filter(|&i| particles[i].is_alive()).map(|i| self.particle_now(i))
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

    /// The run's totals so far: particles and volume per fate, first substrate impacts.
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

    /// Advances the simulation by one time step Δt (also past the configured duration).
    pub fn step(&mut self) {
        self.advance_with(1, &mut ());
    }

    /// [`Simulation::step`], reporting what happens to `events`.
    pub fn step_with(&mut self, events: &mut dyn EventHandler) {
        self.advance_with(1, events);
    }

    /// Advances the simulation by `steps` time steps (also past the configured duration): an
    /// epoch at a time, each in one parallel region (or, on a flight stage, in calls of one or
    /// more epochs). On the engine's own flight, the same, to the bit, as `steps` calls of
    /// [`Simulation::step`].
    pub fn advance(&mut self, steps: u64) {
        self.advance_with(steps, &mut ());
    }

    /// [`Simulation::advance`], reporting what happens to `events`, step by step: each step's
    /// emission and impacts (in particle order), the failures found at an epoch's end, and the
    /// step's end.
    pub fn advance_with(&mut self, steps: u64, events: &mut dyn EventHandler) {
        let mut left = steps;
        while left > 0 {
            left -= self.call(left, events);
        }
    }

    /// Runs to the end of the configured duration, a call at a time (an epoch, or several on a
    /// flight stage that takes them), calling `progress` after each.
    pub fn run(&mut self, mut progress: impl FnMut(&Simulation)) {
        while !self.is_finished() {
            self.call(self.steps_to_call_end(), &mut ());
            progress(self);
        }
    }

    /// Advances by one call of at most `steps` steps, and returns the steps it took: an epoch
    /// (to its end), or, on a flight stage that takes several, the epochs up to the first at
    /// whose end a layer stage falls due. For loops that check on the simulation between calls
    /// (a progress bar, an interrupt) without splitting a GPU's calls into epochs.
    pub fn advance_call(&mut self, steps: u64) -> u64 {
        self.call(steps, &mut ())
    }

    /// Runs one call of at most `steps` steps (see `epoch::run`), reporting to `events`; returns
    /// the steps it took.
    fn call(&mut self, steps: u64, events: &mut dyn EventHandler) -> u64 {
        if steps == 0 {
            return 0;
        }
        let mut log = self.state.impact_log.take();
        // Impacts are gathered in the parallel region only as far as someone wants them.
        let capture = match &log {
            _ if events.wants_impacts() => kernel::Capture::All,
            Some(l) if l.wants_impacts() => kernel::Capture::Sampled { fraction: l.fraction, salt: l.salt },
            _ => kernel::Capture::Nothing,
        };
        let mut none = ();
        let log_handler: &mut dyn EventHandler = match &mut log {
            Some(l) => l,
            None => &mut none,
        };
        let mut both = Both(log_handler, events);
        let how = epoch::How {
            workers: &self.workers,
            capture,
            coasting: self.coasting,
            stage: self.stage.as_deref(),
        };
        let (done, declined) = epoch::run(&self.config, &self.plan, &mut self.state, &how, steps, &mut both);
        if self.stage_error.is_none() {
            self.stage_error = declined;
        }
        self.state.impact_log = log;
        done
    }

    /// Steps that one call may cover from now, at most: to the end of the epoch under way
    /// ([`Simulation::steps_to_epoch_end`]), or, with a flight stage that takes several epochs
    /// ([`FlightStage::epochs_per_call`]), to the run's end, of which a call takes the epochs up
    /// to the first at whose end a layer stage falls due. A loop that advances by this (and
    /// checks on the simulation in between) lets a GPU fly many epochs per call.
    pub fn steps_to_call_end(&self) -> u64 {
        match &self.stage {
            Some(stage) if stage.epochs_per_call() > 1 && !self.is_finished() => {
                self.plan.total_steps - self.state.step
            }
            _ => self.steps_to_epoch_end(),
        }
    }

    /// Steps from now to the end of the epoch under way: the next multiple of
    /// [`SimulationConfig::layer_epoch`], or the run's last step if that comes first (at least
    /// one).
    pub fn steps_to_epoch_end(&self) -> u64 {
        epoch::epoch_end(&self.plan, self.state.step) - self.state.step
    }

    /// Steps per layer epoch.
    pub fn epoch_steps(&self) -> u64 {
        self.plan.epoch
    }

    /// Flies the particles on another backend's flight stage (`None`: the engine's own), such
    /// as the GPU's (`spraysim-gpu`); kept by [`Simulation::restart`]. Calls whose impacts are
    /// gathered as events fly on the engine's own flight, as does a call the stage declines
    /// (see [`Simulation::flight_stage_error`]).
    pub fn set_flight_stage(&mut self, stage: Option<Arc<dyn FlightStage>>) {
        // The layers' changes from now on go to the new stage alone: a copy another stage made
        // (and may meet again) no longer follows them, so each layer takes a new identity.
        for t in &mut self.state.targets {
            t.surface.forget_copies();
        }
        self.stage = stage;
    }

    /// The flight stage set by [`Simulation::set_flight_stage`], if any.
    pub fn flight_stage(&self) -> Option<&Arc<dyn FlightStage>> {
        self.stage.as_ref()
    }

    /// The first error with which the flight stage declined a call, which then flew on the
    /// engine's own flight; `None` if it flew every call given to it.
    pub fn flight_stage_error(&self) -> Option<&str> {
        self.stage_error.as_deref()
    }

    /// Lets particles coast through the steps in which they certainly meet nothing (on by
    /// default), or searches every step of every particle in full. Results are the same to the
    /// bit either way: this is for verifying that, and for measuring what coasting saves.
    pub fn set_coasting(&mut self, on: bool) {
        self.coasting = on;
    }
}
