//! The flight stage's seam: another backend (the GPU's kernels, `spraysim-gpu`) may fly the
//! particles of a call in place of the engine's parallel region, given the same inputs, and
//! hand back what they did as plain data: the particles still in flight at the call's end, the
//! fates and impacts in integer quanta, and per target the cells whose deposits and impacts
//! changed.
//!
//! The engine schedules the births (how many in each step, their ids, the nozzle's pose) and
//! the stage samples each newborn's start from the emitter's laws, as the engine's own flight
//! does in its parallel region: a stage on a GPU draws them there, so that no newborn crosses
//! to it, and only the particles still in flight at the call's end come back.
//!
//! A stage may take several layer epochs in one call ([`FlightStage::epochs_per_call`]): then it
//! adds each epoch's deposits to its own copy of the layers at that epoch's end, as the engine
//! would, and the engine hands it the epochs up to the next one at whose end a layer stage falls
//! due (or the run ends), so that nothing on the CPU must see the layers in between. A run whose
//! targets erode settles their wear at every epoch's end (the coating first), so its calls take
//! one epoch each.
//!
//! The rest is the engine's either way: the schedule of the births, the booking, the settling of
//! the layers and the layer stages at their intervals. A call whose impacts must be gathered as
//! events (an impact log, an observer that wants impacts) flies on the engine's own flight,
//! which alone gathers them, as does a call the stage declines (then epoch by epoch).

use super::emit::Births;
use super::kernel::Books;
use super::{Plan, State};
use crate::config::SimulationConfig;
use crate::deposit::DepositSurface;
use crate::particles::{Particle, StreamKey, flags};
use crate::tally::Tally;
use crate::world::{ObstacleTally, Target, TargetTally};

/// A backend that flies the particles of a call (see the module's docs).
///
/// Implementations must be deterministic: the same job gives the same report. They sample each
/// newborn's start from the configuration's emitter (its laws, in the nozzle's pose of its
/// batch, with the velocity the batch carries) and fly each particle through the job's steps
/// against the layers as they stood at its epoch's start, with the configuration's motion,
/// impact models and domain; what they do not model they must decline (an error) rather than
/// approximate silently.
pub trait FlightStage: Send + Sync + std::fmt::Debug {
    /// Flies `job`; an error leaves the call to the engine's own flight, and the simulation
    /// keeps the message (see [`crate::Simulation::flight_stage_error`]).
    fn fly(&self, job: &FlightJob<'_>) -> Result<FlightReport, String>;

    /// What runs the flights, for summaries: for a GPU, the adapter's name and driver.
    fn describe(&self) -> String;

    /// Where the calls' time went since this was last asked, in words, for benchmarks; `None`
    /// (the default) where the stage does not keep track.
    fn profile(&self) -> Option<String> {
        None
    }

    /// The most layer epochs one call may span: 1 (the default), a call per epoch. A stage that
    /// takes more must settle its own copy of the layers at each epoch's end within the call
    /// (see [`FlightJob::epoch`]).
    fn epochs_per_call(&self) -> u64 {
        1
    }

    /// The most particles one call may hold, those in flight at its start and those born in it
    /// (no limit by default): the engine ends a call of several epochs early to stay under it.
    fn particles_per_call(&self) -> usize {
        usize::MAX
    }
}

/// The particles of one call and what they fly through.
#[derive(Clone, Copy, Debug)]
pub struct FlightJob<'a> {
    /// The run's resolved parameters.
    pub config: &'a SimulationConfig,
    /// The call's first step.
    pub from: u64,
    /// The step after its last: every particle flies to the start of step `to`.
    pub to: u64,
    /// Steps per layer epoch: epochs end at the multiples of this between `from` and `to`. A
    /// call of several epochs ends at an epoch's end (a multiple, or the run's last step); a
    /// call of one may end within it. A particle sees the layers as they stood at the start of
    /// the epoch it flies in: at a multiple within the call, the stage adds what the epoch
    /// deposited on each cell (quanta × [`SimulationConfig::volume_quantum`] / the cell's area,
    /// m) to its copy of the layers before the next epoch flies. A call of one epoch needs none
    /// of this.
    pub epoch: u64,
    /// The particles of the swarm in flight at step `from`, by increasing id.
    pub particles: &'a [Particle],
    /// The volume each of them carries, quanta of [`SimulationConfig::volume_quantum`], in
    /// the same order.
    pub quanta: &'a [u64],
    /// The nozzle's births in the call's steps, in step order, their ids above every id of
    /// `particles` and increasing: the stage samples each newborn's start (see
    /// [`FlightJob::newborns`] for the engine's draws) and flies it from its birth step, in
    /// whichever of the call's epochs that falls.
    pub births: &'a [Births],
    /// The volume each newborn carries, quanta of [`SimulationConfig::volume_quantum`].
    pub nozzle_quanta: u64,
    /// The run's key of random streams, from which the engine draws the newborns' starts.
    pub key: StreamKey,
    /// The targets, with their layers as they stood at the call's start.
    pub targets: &'a [Target],
    /// Per target, the identity of its layer and the cells whose thickness changed since the
    /// previous call given to a stage (see [`crate::deposit::HeightField::take_revised`]);
    /// `None` for a mesh. A stage that keeps a copy of the layers brings it up to date from
    /// these where it holds the same identity, and copies the whole layer otherwise; a stage
    /// that fails a call must forget its copy, whose changes are lost with the call.
    pub revised: &'a [Option<(u64, Vec<u32>)>],
}

/// What a [`FlightJob`]'s particles did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FlightReport {
    /// The particles of the job, of the swarm or newborn, still in flight at the call's end, by
    /// increasing id; the others retired (stuck, left, expired), each counted in one fate.
    pub particles: Vec<Particle>,
    /// Fates and first substrate impacts (its `emitted`, `released`, `dripped` and `ran_off`
    /// stay zero: the engine books those).
    pub tally: Tally,
    /// What struck each target, in the configuration's order.
    pub targets: Vec<TargetTally>,
    /// What struck each obstacle, in the configuration's order.
    pub obstacles: Vec<ObstacleTally>,
    /// Per target, the cells that gathered deposit or impacts, each once, with their sums over
    /// the call's epochs.
    pub cells: Vec<Vec<CellBook>>,
    /// Particle-steps flown.
    pub steps: u64,
    /// Of those, steps searched in full for hits.
    pub updates: u64,
}

/// What one cell of a target gathered in a call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CellBook {
    /// The cell's index in its target's grid.
    pub cell: u32,
    /// Deposited volume, quanta.
    pub quanta: u64,
    /// Impacts on it, stuck or rebounded.
    pub hits: u32,
    /// Under its target's erosion law, the coating and substrate its impacts would wear away,
    /// [`WEAR_QUANTUM`](crate::deposit::WEAR_QUANTUM)s (each impact's volume rounded to the
    /// nearest first, as [`wear_quanta`](crate::deposit::wear_quanta) does); zero elsewhere.
    pub wear: [u64; 2],
}

/// What a call flown by a stage hands to booking: the books, the newborns still in flight (in
/// id order) and how many particles of the swarm left flight.
pub(super) type Flown = (Books, Vec<Vec<Particle>>, usize);

impl FlightJob<'_> {
    /// The newborns of [`FlightJob::births`], in id order, their starts drawn as the engine's
    /// own flight draws them (each from its own stream of [`FlightJob::key`]).
    pub fn newborns(&self) -> Vec<Particle> {
        let sampler = self.config.emitter.sampler();
        self.births
            .iter()
            .flat_map(|b| (0..b.count).map(move |k| b.particle(k, &sampler, self.key)))
            .collect()
    }

    /// How many particles the nozzle spawns in the call.
    pub fn newborn_count(&self) -> u64 {
        self.births.iter().map(|b| b.count).sum()
    }
}

/// Flies the call's particles on `stage`: on success the swarm's particles take their new
/// states (those not handed back have retired) and the flight's books are returned, with the
/// newborns still in flight; on an error nothing has changed.
pub(super) fn fly(
    stage: &dyn FlightStage,
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    (from, to): (u64, u64),
    births: &[Births],
) -> Result<Flown, String> {
    let particles: Vec<Particle> = state.swarm.particles.iter().filter(|p| p.is_alive()).copied().collect();
    let volumes = &state.swarm.volumes;
    let quanta: Vec<u64> = particles.iter().map(|p| volumes.of(p.id, p.flags())).collect();
    let revised: Vec<Option<(u64, Vec<u32>)>> =
        state.targets.iter_mut().map(|t| t.surface.take_revised()).collect();
    let job = FlightJob {
        config,
        from,
        to,
        epoch: plan.epoch,
        particles: &particles,
        quanta: &quanta,
        births,
        nozzle_quanta: volumes.nozzle,
        key: plan.key,
        targets: &state.targets,
        revised: &revised,
    };
    let report = stage.fly(&job)?;
    check(&report, &job)?;
    let (nt, no) = (state.targets.len(), state.obstacles.len());
    let mut books = Books::new(nt, no);
    books.tally = report.tally;
    books.targets = report.targets;
    books.obstacles = report.obstacles;
    books.steps = report.steps;
    books.updates = report.updates;
    for ((target, cells), touched) in state.targets.iter().zip(&report.cells).zip(&mut books.touched) {
        for c in cells {
            target.pending.deposit(c.cell, c.quanta, touched);
            target.pending.impacts(c.cell, c.hits, touched);
            target.pending.wear(c.cell, c.wear, touched);
        }
    }
    // Both in id order: a particle of the swarm not handed back has retired (its state the
    // call's start's, its status no longer alive).
    let mut flown = report.particles.into_iter().peekable();
    let mut retired = 0;
    for p in state.swarm.particles.iter_mut().filter(|p| p.is_alive()) {
        match flown.next_if(|q| q.id == p.id) {
            Some(q) => *p = q,
            None => {
                p.set_flags(p.flags() & !flags::ALIVE);
                retired += 1;
            }
        }
    }
    Ok((books, vec![flown.collect()], retired))
}

/// Refuses a report that does not answer its job: a particle it was not given, out of order or
/// retired, fates that do not account for the particles that left flight, a cell outside its
/// grid, or tallies for other targets and obstacles.
fn check(report: &FlightReport, job: &FlightJob<'_>) -> Result<(), String> {
    // The job's ids in increasing order: the swarm's, then each batch of births'.
    let mut given = job.particles.iter().map(|p| u64::from(p.id)).peekable();
    let mut batches = job.births.iter().map(|b| b.first..b.first + b.count).peekable();
    let mut last = None;
    for p in &report.particles {
        let id = u64::from(p.id);
        let known = loop {
            if let Some(&g) = given.peek() {
                if g < id {
                    given.next();
                    continue;
                }
                break g == id;
            }
            match batches.peek() {
                Some(r) if r.end <= id => {
                    batches.next();
                }
                Some(r) => break r.contains(&id),
                None => break false,
            }
        };
        if !known || last.is_some_and(|l| l >= id) || !p.is_alive() {
            return Err("the flight stage handed back other particles than it was given".into());
        }
        last = Some(id);
    }
    let (nt, no) = (job.targets.len(), job.config.obstacles.len());
    if report.targets.len() != nt || report.obstacles.len() != no || report.cells.len() != nt {
        return Err("the flight stage handed back tallies for other targets or obstacles".into());
    }
    let given = job.particles.len() as u64 + job.newborn_count();
    if given - report.particles.len() as u64 != retired(report) {
        return Err(format!(
            "the flight stage's fates count {} particles retired, not the {} it did not hand back",
            retired(report),
            given - report.particles.len() as u64
        ));
    }
    for (target, cells) in job.targets.iter().zip(&report.cells) {
        let n = target.surface.thickness().len();
        if cells.iter().any(|c| c.cell as usize >= n) {
            return Err(format!("the flight stage booked a cell outside target `{}`", target.name));
        }
    }
    Ok(())
}

/// The particles a report's fates count as retired: stuck on a target (front or back, sprayed
/// or released) or an obstacle, out of the domain, expired, overspray.
fn retired(report: &FlightReport) -> u64 {
    let t = &report.tally;
    let fates = [t.left_domain, t.expired, t.overspray, t.released_left, t.released_expired];
    let on_targets = report.targets.iter().map(|g| g.stuck.count + g.stuck_back.count + g.received.count);
    let on_obstacles = report.obstacles.iter().map(|o| o.stuck.count + o.received.count);
    fates.iter().map(|f| f.count).chain(on_targets).chain(on_obstacles).sum()
}
