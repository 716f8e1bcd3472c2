//! A call's steps within one layer epoch.
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

/// Runs steps `state.step .. state.step + steps`, all within one epoch, and settles the epoch if
/// it ends with them. Returns the error of a flight stage that declined the call (which then
/// flew on the engine's own flight).
pub(super) fn run(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    how: &How<'_>,
    steps: u64,
    events: &mut dyn EventHandler,
) -> Option<String> {
    let (from, to) = (state.step, state.step + steps);
    let (births, emissions) = emit::schedule(config, state, from, to);
    let jets = emit::jets(config, state, from, to);
    // Only the engine's own flight gathers impacts as events.
    let elsewhere = how.stage.filter(|_| how.capture == Capture::Nothing);
    let (flown, declined) =
        match elsewhere.map(|s| stage::fly(s, config, plan, state, how.workers, (from, to), &births)) {
            Some(Ok(flown)) => (flown, None),
            other => (fly(config, plan, state, how, (from, to), &births, &jets), other.and_then(Result::err)),
        };
    let (books, born, retired) = flown;
    state.retired += retired;
    let mut impacts = book(state, books);
    for p in born.into_iter().flatten() {
        state.swarm.push(p);
    }
    impacts.sort_unstable_by_key(|(s, e)| (*s, e.particle, e.impact));
    let ends = to % plan.epoch == 0 || to == plan.total_steps;
    dispatch(config, plan, state, (from, to), ends, &emissions, &impacts, events);
    state.step = to;
    declined
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

/// Passes the steps' events on in step order: each step's emission and impacts, then, at the
/// epoch's end, its settling (with the failures it finds), and the step's end.
#[allow(clippy::too_many_arguments)]
fn dispatch(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    (from, to): (u64, u64),
    ends: bool,
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
        if ends && step + 1 == to {
            super::settle::run(config, plan, state, to, events);
        }
        events.step_end(time + config.dt);
    }
}
