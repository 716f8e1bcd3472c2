//! A call's steps: within one layer epoch on the engine's own flight, or several epochs on a
//! flight stage that takes them (see [`super::stage`]).
//!
//! 1. **schedule** (serial, per step: a spawn count, ids, a pose): the births of the steps;
//! 2. **fly** (one parallel region): every particle in flight, and every one born in these
//!    steps from its birth, flies to the call's last step ([`super::kernel`]), each worker
//!    booking what its particles do in integer quanta;
//! 3. **book** (serial, in proportion to what changed): the workers' books merged by integer
//!    addition (so in any order), the newborns still in flight appended in id order, the
//!    impacts gathered as events sorted by step, particle and impact, and the events passed on
//!    step by step;
//! 4. at the epoch's end, **settle** ([`super::settle`]): the targets take what the epoch left
//!    on them, and the layer stages that fall due run.
//!
//! Nothing in step 2 reads what another particle writes, and nothing in step 3 depends on the
//! order the workers finished in: the result is the same to the bit for any number of threads,
//! and for any split of an epoch into calls.

use super::emit::{self, Births};
use super::kernel::{Air, Books, Capture, Kernel};
use super::stage::{self, FlightStage};
use super::{Plan, State, Workers};
use crate::collision::Scene;
use crate::config::SimulationConfig;
use crate::events::{EmissionEvent, EventHandler, ImpactEvent};
use crate::motion::JetFrame;
use crate::particles::Particle;
use crate::particles::Volumes;
use crate::world::Target;
use rayon::prelude::*;

/// Particles per task of the parallel region: small enough that idle workers can take over the
/// costly ones (near surfaces) from the others.
const CHUNK: usize = 256;

/// The particles of one task of newborns still in flight at the call's end, in id order, and
/// what the task's particles left behind.
type Newborns = (Vec<Particle>, Books);

/// How a call runs its particles.
pub(super) struct How<'a> {
    /// Where the parallel region runs.
    pub workers: &'a Workers,
    /// Which impacts to gather as events.
    pub capture: Capture,
    /// Whether particles coast (see `Simulation::set_coasting`).
    pub coasting: bool,
    /// Another backend's flight stage, if one flies the particles (see [`super::stage`]).
    pub stage: Option<&'a dyn FlightStage>,
}

/// Runs one call from `state.step` of at most `steps` steps, and settles each epoch that ends
/// within it. On the engine's own flight a call stays within one epoch. A flight stage that
/// takes several epochs is handed, from an epoch's start, the epochs up to the first at whose
/// end a layer stage falls due, the run ends, `steps` run out, or the stage's limits are
/// reached; if it declines them, they fly on the engine's own flight, an epoch at a time.
/// Returns the steps taken and the error of a flight stage that declined the call.
pub(super) fn run(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    how: &How<'_>,
    steps: u64,
    events: &mut dyn EventHandler,
) -> (u64, Option<String>) {
    // Only the engine's own flight gathers impacts as events.
    let stage = how.stage.filter(|_| how.capture == Capture::Nothing);
    let (from, to, births, emissions) = schedule(config, plan, state, stage, steps);
    let jets = emit::jets(config, state, from, to);
    let mut declined = None;
    if let Some(stage) = stage {
        match stage::fly(stage, config, plan, state, (from, to), &births) {
            Ok(flown) => {
                finish(config, plan, state, (from, to), flown, &emissions, events);
                return (to - from, None);
            }
            Err(e) => declined = Some(e),
        }
    }
    // The engine's own flight, an epoch at a time.
    let mut a = from;
    while a < to {
        let b = epoch_end(plan, a).min(to);
        let (lo, hi) = (births.partition_point(|x| x.step < a), births.partition_point(|x| x.step < b));
        let (e0, e1) = (emissions.partition_point(|x| x.0 < a), emissions.partition_point(|x| x.0 < b));
        let frames =
            if jets.is_empty() { &jets[..] } else { &jets[(a - from) as usize..(b - from) as usize] };
        let flown = fly(config, plan, state, how, (a, b), &births[lo..hi], frames);
        finish(config, plan, state, (a, b), flown, &emissions[e0..e1], events);
        a = b;
    }
    (to - from, declined)
}

/// The births and emission events of a call from `state.step`, and the step it ends at: the end
/// of the epoch under way (at most `steps` on), or, for a stage that takes several epochs and
/// from an epoch's start, further whole epochs (a call of several ends at an epoch's end) while
/// none ends with a layer stage due or the run's end, `steps` last, and the stage's epochs and
/// particles per call allow; a run whose targets erode takes one epoch a call.
fn schedule(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    stage: Option<&dyn FlightStage>,
    steps: u64,
) -> (u64, u64, Vec<Births>, Vec<(u64, EmissionEvent)>) {
    let from = state.step;
    let last = from + steps;
    let mut to = epoch_end(plan, from).min(last);
    let (mut births, mut emissions) = emit::schedule(config, state, from, to);
    let Some(stage) = stage.filter(|_| state.step == state.settled) else {
        return (from, to, births, emissions);
    };
    // Wear settles at every epoch's end, the coating first (a stage books a call's wear summed
    // over its epochs, which would wear the coating as one impact): calls of one epoch.
    let erodes = config.targets.iter().any(|t| t.erosion.is_some());
    let max_epochs = if erodes { 1 } else { stage.epochs_per_call() };
    let max_particles = stage.particles_per_call();
    // The particles a call holds: at most the swarm's slots and the births so far, and an epoch
    // adds at most `rate × its length` births and one (the carried fraction).
    let per_epoch = (config.emitter.spawn_rate * plan.epoch as f64 * config.dt).floor() as usize + 1;
    let mut held = state.swarm.len() + births.iter().map(|b| b.count as usize).sum::<usize>();
    let (mut start, mut epochs) = (from, 1);
    let due = |a: u64, b: u64| plan.stages.iter().any(|(every, _)| *every > 0 && b / every > a / every);
    while to < last
        && to != plan.total_steps
        && epoch_end(plan, to) <= last
        && epochs < max_epochs
        && !due(start, to)
        && held.saturating_add(per_epoch) <= max_particles
    {
        let next = epoch_end(plan, to);
        let (more, events) = emit::schedule(config, state, to, next);
        held += more.iter().map(|b| b.count as usize).sum::<usize>();
        births.extend(more);
        emissions.extend(events);
        (start, to, epochs) = (to, next, epochs + 1);
    }
    (from, to, births, emissions)
}

/// The end of the epoch under way at step `s` (exclusive): the next multiple of the epoch, or
/// the run's last step if that comes first.
pub(super) fn epoch_end(plan: &Plan, s: u64) -> u64 {
    let next = (s / plan.epoch + 1) * plan.epoch;
    if s < plan.total_steps { next.min(plan.total_steps) } else { next }
}

/// Books what the steps `from..to` flew, adds the newborns still in flight to the swarm, and
/// passes the steps' events on, settling each epoch that ends within them.
fn finish(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    (from, to): (u64, u64),
    (books, born, retired): (Books, Vec<Vec<Particle>>, usize),
    emissions: &[(u64, EmissionEvent)],
    events: &mut dyn EventHandler,
) {
    state.retired += retired;
    let mut impacts = book(state, books);
    for p in born.into_iter().flatten() {
        state.swarm.push(p);
    }
    impacts.sort_unstable_by_key(|(s, e)| (*s, e.particle, e.impact));
    dispatch(config, plan, state, (from, to), emissions, &impacts, events);
    state.step = to;
}

/// The parallel region: flies every particle of the swarm and every newborn of `births`
/// through `from..to`. Returns the merged books, the newborns still in flight (in id order)
/// and how many particles of the swarm left flight.
fn fly(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    how: &How<'_>,
    (from, to): (u64, u64),
    births: &[Births],
    jets: &[Option<JetFrame>],
) -> (Books, Vec<Vec<Particle>>, usize) {
    let workers = how.workers;
    let (nt, no) = (state.targets.len(), state.obstacles.len());
    let particles = &mut state.swarm.particles;
    let kernel =
        kernel(config, plan, (&state.scene, &state.targets, &state.swarm.volumes), how, (from, jets));
    let sampler = config.emitter.sampler();
    // The newborns in tasks of at most CHUNK particles, each within one step's batch.
    let tasks: Vec<(usize, u64, u64)> = births
        .iter()
        .enumerate()
        .flat_map(|(b, batch)| {
            (0..batch.count).step_by(CHUNK).map(move |k| (b, k, (k + CHUNK as u64).min(batch.count)))
        })
        .collect();
    let old = |chunk: &mut [Particle], books: &mut Books| {
        let mut retired = 0;
        for p in chunk.iter_mut().filter(|p| p.is_alive()) {
            kernel.fly(p, from, to, books);
            retired += usize::from(!p.is_alive());
        }
        retired
    };
    let newborn = |&(b, lo, hi): &(usize, u64, u64)| {
        let mut books = Books::new(nt, no);
        let batch = &births[b];
        let mut alive = Vec::with_capacity((hi - lo) as usize);
        for k in lo..hi {
            let mut p = batch.particle(k, &sampler, plan.key);
            kernel.fly(&mut p, batch.step, to, &mut books);
            if p.is_alive() {
                alive.push(p);
            }
        }
        (alive, books)
    };
    let ((mut books, retired), born): ((Books, usize), Vec<Newborns>) = if workers.parallel() {
        workers.install(|| {
            rayon::join(
                || {
                    particles
                        .par_chunks_mut(CHUNK)
                        .fold(
                            || (Books::new(nt, no), 0),
                            |(mut b, r), chunk| {
                                let n = old(chunk, &mut b);
                                (b, r + n)
                            },
                        )
                        .reduce(|| (Books::new(nt, no), 0), |(a, ra), (b, rb)| (a.merge(b), ra + rb))
                },
                || tasks.par_iter().with_max_len(1).map(newborn).collect(),
            )
        })
    } else {
        let mut books = Books::new(nt, no);
        let retired = particles.chunks_mut(CHUNK).map(|c| old(c, &mut books)).sum();
        ((books, retired), tasks.iter().map(newborn).collect())
    };
    let mut alive = Vec::with_capacity(born.len());
    for (a, b) in born {
        alive.push(a);
        books = books.merge(b);
    }
    (books, alive, retired)
}

/// The flight kernel of a call from step `from`, with the gun's jet in each of its steps.
fn kernel<'a>(
    config: &'a SimulationConfig,
    plan: &'a Plan,
    (scene, targets, volumes): (&'a Scene, &'a [Target], &'a Volumes),
    how: &How<'_>,
    (from, jets): (u64, &'a [Option<JetFrame>]),
) -> Kernel<'a> {
    Kernel {
        config,
        scene,
        models: &plan.models,
        targets,
        volumes,
        motion: config.motion,
        domain: config.domain,
        dt: config.dt,
        key: plan.key,
        max_impacts: config.max_impacts_per_step,
        lifetime_steps: config.material.max_lifetime / config.dt,
        g_len: config.motion.gravity.length(),
        density: config.material.density,
        capture: how.capture,
        coasting: how.coasting,
        air: config.motion.air.zip(plan.sizes.as_ref()).map(|(flow, sizes)| Air {
            flow,
            sizes,
            frames: jets,
            first: from,
            max_speed: jets.iter().flatten().map(|j| flow.max_speed(j)).fold(0.0, f64::max),
        }),
    }
}

/// Adds the merged books to the run's totals and to each target and obstacle, and keeps the
/// cells touched for the epoch's end; returns the impacts gathered as events, with their steps.
fn book(state: &mut State, books: Books) -> Vec<(u64, ImpactEvent)> {
    state.tally.merge(&books.tally);
    for (t, (tally, mut touched)) in books.targets.into_iter().zip(books.touched).enumerate() {
        state.targets[t].tally += tally;
        state.touched[t].append(&mut touched);
    }
    for (o, tally) in state.obstacles.iter_mut().zip(books.obstacles) {
        o.tally += tally;
    }
    state.particle_steps += books.steps;
    state.particle_updates += books.updates;
    books.events
}

/// Passes the steps' events on in step order: each step's emission and impacts, then, at an
/// epoch's end, its settling (with the failures it finds), and the step's end. A flight stage's
/// call of several epochs books their deposits together, so its first settling applies them
/// all: no layer stage falls due before its last.
fn dispatch(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    (from, to): (u64, u64),
    emissions: &[(u64, EmissionEvent)],
    impacts: &[(u64, ImpactEvent)],
    events: &mut dyn EventHandler,
) {
    let (mut e, mut i) = (0, 0);
    for step in from..to {
        let time = step as f64 * config.dt;
        while e < emissions.len() && emissions[e].0 == step {
            events.emission(&emissions[e].1);
            e += 1;
        }
        while i < impacts.len() && impacts[i].0 == step {
            events.impact(&impacts[i].1);
            i += 1;
        }
        if epoch_end(plan, step) == step + 1 {
            super::settle::run(config, plan, state, step + 1, events);
        }
        events.step_end(time + config.dt);
    }
}
