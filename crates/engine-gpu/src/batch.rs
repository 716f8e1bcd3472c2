//! [`GpuBatch`]: the calls of many simulations (the variants of a study: other seeds, emitter
//! and process parameters, nozzle paths) flown together, one dispatch covering every member's
//! particles, so that a GPU too large for one short run is filled by many.
//!
//! Each member is a flight stage of its own ([`BatchMember`]) set on its simulation, whose
//! thread advances it as usual. A member's call waits until every member still flying has
//! handed in its call; the last to arrive flies them all (members whose calls span other
//! epochs in dispatches of their own) and wakes the others. A member leaves when its run ends
//! ([`BatchMember::leave`], also on drop), so the others do not wait for it; one that has left
//! flies its calls with whoever is flying then, or alone. Each member keeps its own region of
//! the layers' buffer, so only the spans of its layers that changed are uploaded; a batch's
//! grids must fit one binding of cells, and [`run_together`] splits larger sets into batches
//! that run side by side. A member's results do not depend on the others: each invocation
//! reads only its own member's words, and each member books into its own counters, so a run
//! gives the same bits in a batch as alone. [`run_together`] runs a set of simulations so;
//! [`step_together`] steps a set, its members staying in their batches between two calls (the
//! vectorised environments' steps), so that a batch's storage and its copy of the layers last.

use crate::GpuError;
use crate::dispatch::{self, Buffers, MemberCall, Raw};
use crate::flight::{self, GpuFlight};
use spraysim_engine::Simulation;
use spraysim_engine::deposit::{DepositSurface, Surface};
use spraysim_engine::pipeline::{FlightJob, FlightReport, FlightStage};
use std::borrow::BorrowMut;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};

/// Simulations whose calls fly in shared dispatches (see the module's docs).
#[derive(Debug)]
pub struct GpuBatch {
    flight: Arc<GpuFlight>,
    /// Each member's first cell in the layers' buffer.
    regions: Vec<u32>,
    /// The cells of each region, and whether a target of its member erodes (see
    /// [`BatchMember::fits`]).
    grids: Vec<(u64, bool)>,
    /// Cells of all members' grids.
    cells: u32,
    state: Mutex<State>,
    /// Signalled when a dispatch has answered the calls waiting for it.
    answered: Condvar,
}

/// What the members share, under the batch's lock.
#[derive(Debug)]
struct State {
    buffers: Buffers,
    /// Members still flying.
    active: usize,
    /// Calls handed in for the next dispatch, each with its member.
    waiting: Vec<(usize, MemberCall)>,
    /// Per member, what its last dispatch gave it, until it takes it.
    answers: Vec<Option<Answer>>,
}

/// What a dispatch gives a member: what it read back, with the member's call; or why it failed.
type Answer = Result<(Raw, MemberCall), String>;

/// One simulation's flight stage in a [`GpuBatch`].
#[derive(Debug)]
pub struct BatchMember {
    batch: Arc<GpuBatch>,
    id: usize,
    /// The cells of its simulation's grids its region holds, and whether a target erodes.
    grids: (u64, bool),
    /// The identity of each of its targets' layers, with its first cell, as the batch's copy
    /// holds them (None: nothing known).
    mirror: Mutex<Option<Vec<(u64, u32)>>>,
    left: AtomicBool,
}

impl GpuBatch {
    /// A batch of `sims` on `flight`'s device: a member for each, to set as its flight stage.
    /// Every member must fly (its simulation advanced) or leave: the others wait for it.
    pub fn members(flight: Arc<GpuFlight>, sims: &[&Simulation]) -> Result<Vec<Arc<BatchMember>>, GpuError> {
        let mut regions = Vec::with_capacity(sims.len());
        let grids: Vec<(u64, bool)> = sims.iter().map(|s| (grid_cells(s), erodes(s))).collect();
        let mut cells = 0u32;
        for sim in sims {
            regions.push(cells);
            cells = u32::try_from(grid_cells(sim))
                .ok()
                .and_then(|n| cells.checked_add(n))
                .ok_or_else(|| GpuError::TooLarge("the cells of a batch's grids".into()))?;
        }
        let state = State {
            buffers: Buffers::default(),
            active: sims.len(),
            waiting: Vec::new(),
            answers: (0..sims.len()).map(|_| None).collect(),
        };
        let batch = Arc::new(GpuBatch {
            flight: flight.clone(),
            regions,
            grids,
            cells,
            state: Mutex::new(state),
            answered: Condvar::new(),
        });
        let members: Vec<Arc<BatchMember>> =
            (0..sims.len()).map(|id| BatchMember::new(&batch, id, false)).collect();
        flight.register(&members);
        Ok(members)
    }

    /// A new member for region `id`, whose member has gone (dropped with its simulation), for a
    /// simulation whose grids fit the region: it joins the batch, and its first call rebuilds the
    /// region's copy of the layers.
    fn adopt(self: &Arc<GpuBatch>, id: usize) -> Arc<BatchMember> {
        let member = BatchMember::new(self, id, true);
        member.rejoin();
        self.flight.register(std::slice::from_ref(&member));
        member
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Hands in member `id`'s call and waits for its answer; the last member to arrive flies
    /// every call waiting.
    fn submit(&self, id: usize, call: MemberCall) -> Answer {
        let mut state = self.lock();
        state.waiting.push((id, call));
        if state.waiting.len() >= state.active {
            self.fly_waiting(&mut state);
        }
        loop {
            if let Some(answer) = state.answers[id].take() {
                return answer;
            }
            state = self.answered.wait(state).unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// Flies the calls waiting, in member order: those of the same epochs together, in as few
    /// dispatches as one binding's particle slots allow; answers each and wakes the members.
    fn fly_waiting(&self, state: &mut State) {
        let mut waiting = std::mem::take(&mut state.waiting);
        waiting.sort_by_key(|(id, _)| *id);
        let room = self.flight.slots_per_dispatch();
        let mut groups: Vec<(usize, Vec<(usize, MemberCall)>)> = Vec::new();
        for (id, call) in waiting {
            let slots = usize::try_from(call.padded_slots()).unwrap_or(usize::MAX);
            let fits = |g: &&mut (usize, Vec<(usize, MemberCall)>)| {
                g.1[0].1.epochs == call.epochs && g.0 + slots <= room
            };
            match groups.iter_mut().find(fits) {
                Some(group) => {
                    group.0 += slots;
                    group.1.push((id, call));
                }
                None => groups.push((slots, vec![(id, call)])),
            }
        }
        for (_, group) in groups {
            let (ids, calls): (Vec<usize>, Vec<MemberCall>) = group.into_iter().unzip();
            let (flight, buffers) = (&self.flight, &mut state.buffers);
            // A panic (a device error wgpu raises so) answers every member of the dispatch with
            // an error, rather than leave them waiting for an answer that never comes.
            let dispatched = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                dispatch::dispatch(&flight.gpu, &flight.kernels, buffers, self.cells, &calls)
            }))
            .unwrap_or_else(|_| Err(GpuError::Device("the dispatch failed (a panic)".into())));
            match dispatched {
                Ok((raw, timing)) => {
                    let particles = calls.iter().map(MemberCall::particles).sum();
                    flight.note(calls[0].epochs.len(), particles, timing);
                    for ((id, raw), call) in ids.into_iter().zip(raw).zip(calls) {
                        state.answers[id] = Some(Ok((raw, call)));
                    }
                }
                Err(e) => {
                    for id in ids {
                        state.answers[id] = Some(Err(e.to_string()));
                    }
                }
            }
        }
        self.answered.notify_all();
    }
}

impl BatchMember {
    /// Member `id` of `batch`, its region's copy of the layers unknown to it; one that has
    /// `left` is not waited for until it rejoins.
    fn new(batch: &Arc<GpuBatch>, id: usize, left: bool) -> Arc<BatchMember> {
        Arc::new(BatchMember {
            batch: batch.clone(),
            id,
            grids: batch.grids[id],
            mirror: Mutex::new(None),
            left: AtomicBool::new(left),
        })
    }

    /// Joins the batch again after leaving it: the others wait for this member's calls again.
    pub fn rejoin(&self) {
        if self.left.swap(false, Ordering::SeqCst) {
            self.batch.lock().active += 1;
        }
    }

    /// Whether this member still fits `sim`: a region of its grids' cells, as wide a cell.
    fn fits(&self, sim: &Simulation) -> bool {
        self.grids == (grid_cells(sim), erodes(sim))
    }

    /// Leaves the batch (once; also on drop): the others no longer wait for this member.
    pub fn leave(&self) {
        if self.left.swap(true, Ordering::SeqCst) {
            return;
        }
        let mut state = self.batch.lock();
        state.active = state.active.saturating_sub(1);
        if !state.waiting.is_empty() && state.waiting.len() >= state.active {
            self.batch.fly_waiting(&mut state);
        }
    }

    /// Runs `job` in the batch's next dispatch (at once, if no member flies: one that has left
    /// is not waited for).
    fn run(&self, job: &FlightJob<'_>) -> Result<FlightReport, GpuError> {
        let (mut call, layout) = flight::lay_out(job)?;
        call.cell = self.batch.regions[self.id];
        let mut mirror = self.mirror.lock().unwrap_or_else(PoisonError::into_inner);
        // Only this member writes its region of the batch's layers; what it holds is forgotten
        // until the call succeeds, as for a single run.
        call.layers = flight::layers(job, &call.scene, mirror.take().as_deref(), &layout);
        let (raw, call) = self.batch.submit(self.id, call).map_err(GpuError::Device)?;
        *mirror = Some(layout);
        drop(mirror);
        Ok(self.batch.flight.report(job, &call, &raw))
    }
}

impl Drop for BatchMember {
    fn drop(&mut self) {
        self.leave();
    }
}

impl FlightStage for BatchMember {
    fn fly(&self, job: &FlightJob<'_>) -> Result<FlightReport, String> {
        self.run(job).map_err(|e| e.to_string())
    }

    fn describe(&self) -> String {
        format!("{}, in a batch of {}", self.batch.flight.describe(), self.batch.regions.len())
    }

    fn epochs_per_call(&self) -> u64 {
        self.batch.flight.max_epochs
    }

    fn particles_per_call(&self) -> usize {
        // As alone, so that a run's calls end where they would alone (the GPU's bits depend on
        // it): members whose calls do not fit one dispatch together fly in several.
        self.batch.flight.slots_per_dispatch()
    }

    fn profile(&self) -> Option<String> {
        self.batch.flight.profile()
    }
}

/// Leaves its member's batch when dropped.
struct Leaving(Option<Arc<BatchMember>>);

impl Drop for Leaving {
    fn drop(&mut self) {
        if let Some(member) = &self.0 {
            member.leave();
        }
    }
}

/// Whether a target of `sim` erodes (its cells then take wear counters too).
fn erodes(sim: &Simulation) -> bool {
    sim.config().targets.iter().any(|t| t.erosion.is_some())
}

/// Cells of `sim`'s grids (the GPU's share of its layers).
fn grid_cells(sim: &Simulation) -> u64 {
    let cells: usize = sim
        .targets()
        .iter()
        .filter(|t| !matches!(t.surface, Surface::Mesh(_)))
        .map(|t| t.surface.thickness().len())
        .sum();
    cells as u64
}

/// Advances `sims` together, each on a thread of its own by `advance(k, sim)` (called until it
/// returns false or `stop` is set), those with a flight stage with their calls flown in shared
/// dispatches on `flight`, the others on the engine's own flight; each leaves its batch when
/// done. Where `reuse` is set and every one with a stage is a member of a batch on `flight`
/// that still fits it, or can take a gone member's region in those batches, they rejoin their
/// batches; else they go in new ones. Hands the
/// simulations back, their stages their batch members.
fn together<S: BorrowMut<Simulation> + Send>(
    flight: &Arc<GpuFlight>,
    mut sims: Vec<S>,
    stop: &AtomicBool,
    reuse: bool,
    advance: impl Fn(usize, &mut Simulation) -> bool + Sync,
) -> Result<Vec<S>, GpuError> {
    let on_gpu: Vec<usize> = (0..sims.len()).filter(|&k| sims[k].borrow().flight_stage().is_some()).collect();
    let held = reuse.then(|| rejoined(flight, &mut sims, &on_gpu)).flatten();
    let members = match held {
        Some(members) => members,
        None => {
            let members = batched(flight, &sims, &on_gpu)?;
            for (sim, member) in sims.iter_mut().zip(&members) {
                if let Some(m) = member {
                    sim.borrow_mut().set_flight_stage(Some(m.clone() as Arc<dyn FlightStage>));
                }
            }
            members
        }
    };
    let advance = &advance;
    Ok(std::thread::scope(|scope| {
        let handles: Vec<_> = sims
            .into_iter()
            .zip(members)
            .enumerate()
            .map(|(k, (mut sim, member))| {
                scope.spawn(move || {
                    // Leaves the batch however the thread ends (a panic included), so that the
                    // others do not wait for it.
                    let _leaving = Leaving(member);
                    while !stop.load(Ordering::Relaxed) && advance(k, sim.borrow_mut()) {}
                    sim
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e))).collect()
    }))
}

/// The batch members that the simulations `on_gpu` of `sims` have as their stages, each
/// rejoined to its batch, where every one has one of its own on `flight` that still fits it (a
/// copy of a simulation shares its stage, and needs a member of its own) or can take the region
/// of one that has gone in those batches (an environment reset into a new simulation, whose
/// region alone is rebuilt); else `None`. Those that took a region get its member as their stage.
fn rejoined<S: BorrowMut<Simulation>>(
    flight: &GpuFlight,
    sims: &mut [S],
    on_gpu: &[usize],
) -> Option<Vec<Option<Arc<BatchMember>>>> {
    let mut members: Vec<Option<Arc<BatchMember>>> = (0..sims.len()).map(|_| None).collect();
    let mut seen = std::collections::HashSet::new();
    let mut newcomers = Vec::new();
    for &k in on_gpu {
        let sim = sims[k].borrow();
        match sim.flight_stage().and_then(|s| flight.member(s)).filter(|m| m.fits(sim)) {
            Some(m) if seen.insert(Arc::as_ptr(&m)) => members[k] = Some(m),
            _ => newcomers.push(k),
        }
    }
    // The regions of those batches whose members have gone.
    let live = flight.live_members();
    let mut free: Vec<(Arc<GpuBatch>, usize)> = Vec::new();
    for m in members.iter().flatten() {
        if free.iter().any(|(b, _)| Arc::ptr_eq(b, &m.batch)) || newcomers.is_empty() {
            continue;
        }
        let taken = |id: usize| live.iter().any(|l| Arc::ptr_eq(&l.batch, &m.batch) && l.id == id);
        free.extend((0..m.batch.regions.len()).filter(|&id| !taken(id)).map(|id| (m.batch.clone(), id)));
    }
    let mut places = Vec::with_capacity(newcomers.len());
    for &k in &newcomers {
        let grids = (grid_cells(sims[k].borrow()), erodes(sims[k].borrow()));
        let at = free.iter().position(|(b, id)| b.grids[*id] == grids)?;
        places.push(free.swap_remove(at));
    }
    members.iter().flatten().for_each(|m| m.rejoin());
    for (k, (batch, id)) in newcomers.into_iter().zip(places) {
        let member = batch.adopt(id);
        sims[k].borrow_mut().set_flight_stage(Some(member.clone() as Arc<dyn FlightStage>));
        members[k] = Some(member);
    }
    Some(members)
}

/// New batch members for the simulations `on_gpu` of `sims`: batches whose grids fit one
/// binding of cells (16 bytes a cell, 32 where a target erodes), side by side.
fn batched<S: BorrowMut<Simulation>>(
    flight: &Arc<GpuFlight>,
    sims: &[S],
    on_gpu: &[usize],
) -> Result<Vec<Option<Arc<BatchMember>>>, GpuError> {
    let limit = flight.gpu.binding_bytes();
    let mut members: Vec<Option<Arc<BatchMember>>> = (0..sims.len()).map(|_| None).collect();
    let mut start = 0;
    while start < on_gpu.len() {
        let (mut end, mut cells, mut widest) = (start, 0, dispatch::bytes_per_cell(false));
        while end < on_gpu.len() {
            let sim = sims[on_gpu[end]].borrow();
            let (more, wide) = (cells + grid_cells(sim), dispatch::bytes_per_cell(erodes(sim)).max(widest));
            if end > start && (more + 1) * wide > limit {
                break;
            }
            (cells, widest, end) = (more, wide, end + 1);
        }
        let batch: Vec<&Simulation> = on_gpu[start..end].iter().map(|&k| sims[k].borrow()).collect();
        for (&k, member) in on_gpu[start..end].iter().zip(GpuBatch::members(flight.clone(), &batch)?) {
            members[k] = Some(member);
        }
        start = end;
    }
    Ok(members)
}

/// Runs `sims` (each with a flight stage) to their ends together, each on a thread of its own,
/// their calls flown in shared dispatches on `flight` (see [`GpuBatch`]; a set whose grids
/// outgrow one binding of cells is split into batches that run side by side), and returns
/// `done(k, sim)` of each in their order. Each stops early, after the call under way, once
/// `stop` is set, and is handed to `done` with `flight` as its stage. Each one's results equal
/// its run alone.
pub fn run_together<T: Send>(
    flight: &Arc<GpuFlight>,
    mut sims: Vec<Simulation>,
    stop: &AtomicBool,
    done: impl Fn(usize, Simulation) -> T + Sync,
) -> Result<Vec<T>, GpuError> {
    for sim in sims.iter_mut().filter(|s| s.flight_stage().is_none()) {
        sim.set_flight_stage(Some(flight.clone()));
    }
    let finished = together(flight, sims, stop, false, |_, sim| {
        if !sim.is_finished() {
            sim.advance_call(sim.steps_to_call_end());
        }
        !sim.is_finished()
    })?;
    // Handed back on `flight` alone: one stopped early goes on as a single run.
    Ok(finished
        .into_iter()
        .enumerate()
        .map(|(k, mut sim)| {
            sim.set_flight_stage(Some(flight.clone()));
            done(k, sim)
        })
        .collect())
}

/// Advances each of `sims` by `steps` steps (or to its run's end), together: each on a thread
/// of its own, the calls of those with a flight stage flown in shared dispatches on `flight`
/// (as [`run_together`]), the others on the engine's own flight. Each stops early, after the
/// call under way, once `stop` is set. Each one's results equal its steps alone: the
/// vectorised step of a set of environments.
///
/// Those on the GPU keep their batch members as their stages, so that the next call with the
/// same simulations (or some of them) finds its batches again: their storage, and their copies
/// of the layers, which only the cells changed since then need to reach. A simulation whose
/// stage is no member of a batch on `flight` (an environment reset into a new one) takes the
/// region of a member of those batches that has gone (dropped with its simulation) whose grids
/// it fits, so that only that region is rebuilt; one that finds none, or whose grids no longer
/// fit its member's region (a rebuild on another scene), puts all of them in new batches. A
/// member stepped on its own in between flies alone.
pub fn step_together(
    flight: &Arc<GpuFlight>,
    sims: &mut [&mut Simulation],
    steps: u64,
    stop: &AtomicBool,
) -> Result<(), GpuError> {
    let goals: Vec<u64> = sims.iter().map(|s| s.steps_ahead(steps)).collect();
    let borrowed: Vec<&mut Simulation> = sims.iter_mut().map(|s| &mut **s).collect();
    together(flight, borrowed, stop, true, |k, sim| {
        // A call ends by itself at its epoch's (or its stage's) end.
        sim.advance_call(goals[k].saturating_sub(sim.steps_done()));
        sim.steps_done() < goals[k]
    })?;
    Ok(())
}
