//! One submission of the kernels over the members of a batch (one simulation's call each; one
//! member for a single run): the members' words, particles, layers and counters laid out one
//! after the other, `restore`, `born` (the newborns sampled in their slots), then per epoch
//! `fly` (one dispatch over every member's particles), `census`, `settle` and `census` again,
//! and `gather`; then each member's part of what was read back.

use crate::GpuError;
use crate::device::Gpu;
use crate::kernels::{Groups, Kernels, PARAMS_BYTES, params_stride, record};
use crate::pack::{
    self, BYTES_PER_SLOT, GLOBAL_COUNTER_WORDS, GpuParticle, MEMBER_WORDS, OBSTACLE_COUNTER_WORDS, Place,
    TABLE_WORDS, TALLY_WORDS, TARGET_COUNTER_WORDS, WORKGROUP,
};
use crate::timing::{KernelTimes, Stamps, Timing};
use rayon::prelude::*;
use std::time::{Duration, Instant};
use wgpu::util::DeviceExt;

/// Storage that grows as dispatches need, and the layers it holds.
#[derive(Debug, Default)]
pub(crate) struct Buffers {
    particles: Option<wgpu::Buffer>,
    scene: Option<wgpu::Buffer>,
    thickness: Option<wgpu::Buffer>,
    counters: Option<wgpu::Buffer>,
    cells: Option<wgpu::Buffer>,
    listed: Option<wgpu::Buffer>,
    plan: Option<wgpu::Buffer>,
    wear: Option<wgpu::Buffer>,
    readback: Option<wgpu::Buffer>,
    /// The kernels' timestamps, where the device writes them.
    stamps: Option<Stamps>,
    /// The size of the dispatches over the listed cells (see `Kernels::census_layout`).
    listed_groups: Option<wgpu::Buffer>,
    /// Cells listed that a dispatch reads back with the kernels' results (those past them take
    /// a second copy): twice what the last dispatch listed, at least [`LEAST_LISTED`].
    listed_guess: u32,
    /// Cells of all grids the layers' buffer is laid out for (each half: these and a spare).
    pub layer_cells: Option<u32>,
}

/// How a member's layers reach the GPU's copy, as the call finds them: spans of cells, each
/// from its first cell (over the member's grids).
#[derive(Debug)]
pub(crate) enum Layers {
    /// Every cell of its grids anew (the copy holds nothing known of them): zero, filled on the
    /// GPU, but for these spans.
    Whole(Vec<(u32, Vec<f32>)>),
    /// Only these spans: the copy holds the rest as the call finds it.
    Spans(Vec<(u32, Vec<f32>)>),
}

/// One member's call laid out for the kernels.
#[derive(Debug)]
pub(crate) struct MemberCall {
    /// Its own words.
    pub scene: pack::SceneWords,
    /// The particles of its swarm; its newborns (`scene.births`) take the slots after them.
    pub slots: Vec<GpuParticle>,
    /// Its words at the start of the scene, but for where it lies (filled in by `dispatch`).
    pub words: [u32; MEMBER_WORDS],
    /// Its counter block at the call's start.
    pub counters: Vec<u32>,
    /// Its layers as the call finds them.
    pub layers: Layers,
    /// Its first cell in the layers' buffer.
    pub cell: u32,
    /// The call's layer epochs, each as (first step, step after its last).
    pub epochs: Vec<(u64, u64)>,
}

impl MemberCall {
    /// Its particles: the swarm's, then the newborns' (`scene.births`).
    pub fn particles(&self) -> usize {
        self.slots.len() + self.scene.births.newborns as usize
    }

    /// Its particle slots, padded to whole workgroups.
    pub fn padded_slots(&self) -> u64 {
        (self.particles() as u64).next_multiple_of(u64::from(WORKGROUP))
    }
}

/// What a dispatch read back for one member.
#[derive(Debug)]
pub(crate) struct Raw {
    /// Its particles as the call leaves them, the swarm's then the newborns', in id order.
    pub slots: Vec<GpuParticle>,
    /// Its counter block.
    pub counters: Vec<u32>,
    /// The cells it listed, each as (cell over its own grids, quanta low, quanta high, impacts).
    pub listed: Vec<[u32; 4]>,
    /// Their wear (coating low, high, substrate low, high), where a target erodes.
    pub wear: Vec<[u32; 4]>,
}

/// Bytes a cell of the layers takes in the largest binding of a dispatch: its counters (16), or
/// its wear (32) where a target `erodes`.
pub(crate) fn bytes_per_cell(erodes: bool) -> u64 {
    if erodes { 32 } else { 16 }
}

/// Counter words of a member with `targets` targets and `obstacles` obstacles.
pub(crate) fn counter_words(targets: usize, obstacles: usize) -> usize {
    TALLY_WORDS + TARGET_COUNTER_WORDS * targets + OBSTACLE_COUNTER_WORDS * obstacles
}

/// Runs `members` (whose calls span the same epochs) in one submission over `cells` cells of
/// layers (every member's region within them); returns what each read back, in their order.
/// Where `b` holds no layers laid out for `cells` cells, every member must bring them whole.
pub(crate) fn dispatch(
    gpu: &Gpu,
    kernels: &Kernels,
    b: &mut Buffers,
    cells: u32,
    members: &[MemberCall],
) -> Result<(Vec<Raw>, Timing), GpuError> {
    let start = Instant::now();
    let epochs = members.first().map(|m| m.epochs.clone()).unwrap_or_default();
    if epochs.is_empty() || members.iter().any(|m| m.epochs != epochs) {
        return Err(GpuError::Device("a dispatch of no steps, or of members of other steps".into()));
    }
    let whole_members = members.iter().filter(|m| matches!(m.layers, Layers::Whole(_))).count() as u64;
    let whole = whole_members == members.len() as u64;
    if b.layer_cells != Some(cells) && !whole {
        return Err(GpuError::Device("the GPU's copy of the layers is not laid out for this call".into()));
    }
    let limit = gpu.binding_bytes();
    // Each member's slots fill whole workgroups.
    let slots: u64 = members.iter().map(MemberCall::padded_slots).sum();
    let per_cell = bytes_per_cell(members.iter().any(|m| m.scene.erodes));
    if per_cell * (u64::from(cells) + 1) > limit || BYTES_PER_SLOT as u64 * slots > limit {
        return Err(GpuError::TooLarge(format!(
            "{cells} cells or {slots} particle slots in one call (one binding holds at most {limit} bytes)"
        )));
    }
    let laid = lay_out(members, cells);
    if 4 * laid.words.len() as u64 > limit {
        return Err(GpuError::TooLarge(format!(
            "{} words of scene and births in one call (one binding holds at most {limit} bytes)",
            laid.words.len()
        )));
    }
    let erodes = members.iter().any(|m| m.scene.erodes);
    let bind = upload(gpu, kernels, b, (&laid, members), (cells, erodes), &epochs)?;
    let uploaded = Instant::now();
    // Each member's slots (its swarm's and its newborns'), copied out of the read-back apart.
    let member_slots: Vec<_> = members
        .iter()
        .zip(&laid.places)
        .map(|(m, p)| p.slot as usize..p.slot as usize + m.particles())
        .collect();
    let read = submit(gpu, kernels, b, &bind, (&laid, epochs.len(), &member_slots), (cells, erodes))?;
    let flew = Instant::now();
    let ReadBack { slots, counters: words, mut listed, mut wear, gpu: gpu_times } = read;
    // The cells listed past those read back with the kernels' results: a second copy.
    let count = words[0];
    let second_copy = count as usize > listed.len();
    if second_copy {
        let from = listed.len() as u32;
        let source = some(&b.listed)?.clone();
        let rest = copy_out(gpu, b, &source, 16 * u64::from(from), 16 * u64::from(count - from))?;
        listed.extend_from_slice(bytemuck::cast_slice(&rest));
        if erodes {
            wear.extend(listed_wear(gpu, b, cells, (from, count))?);
        }
    }
    listed.truncate(count as usize);
    wear.truncate(count as usize);
    b.listed_guess = expected_listed(count);
    let raw = split(members, &laid.places, (slots, &words), (&listed, &wear));
    let timing = Timing {
        upload: (uploaded - start).as_secs_f64(),
        kernels: (flew - uploaded).as_secs_f64(),
        cells: flew.elapsed().as_secs_f64(),
        second_copy,
        members: (members.len() as u64, whole_members),
        gpu: gpu_times,
    };
    Ok((raw, timing))
}

/// Cells a dispatch reads back with the kernels' results, after one that listed `count`: as
/// many again, for a call that touches more than the last (and at least [`LEAST_LISTED`]).
fn expected_listed(count: u32) -> u32 {
    count.saturating_mul(2)
}

/// The fewest listed cells a dispatch reads back with the kernels' results (4 KB), so that a
/// run's first call and one after a call that listed none seldom take a second copy.
const LEAST_LISTED: u32 = 256;

/// What a dispatch's submission read back in one copy: each member's particle slots, the
/// counters, the kernels' timestamps, and the first of the cells listed with their wear.
struct ReadBack {
    /// Each member's particle slots, in the order of the ranges asked for.
    slots: Vec<Vec<GpuParticle>>,
    /// Every counter word.
    counters: Vec<u32>,
    /// The first cells listed (as many as were read back).
    listed: Vec<[u32; 4]>,
    /// Their wear (none where no target erodes).
    wear: Vec<[u32; 4]>,
    /// The kernels' GPU times, where they were timed.
    gpu: Option<KernelTimes>,
}

/// Records the kernels of a dispatch laid out as `laid` over `epochs` epochs and `cells` cells
/// (bound as `bind`), submits them, and reads back in one copy its particles (those of each
/// member's range of slots, copied out of the mapped buffer on rayon's workers), counters and
/// timestamps, with the cells listed up to [`Buffers::listed_guess`] and their wear (where a
/// target `erodes`: the copies of the wear are cleared once copied, so that a later call's
/// counters, which may lie there, start at zero).
fn submit(
    gpu: &Gpu,
    kernels: &Kernels,
    b: &mut Buffers,
    bind: &Groups,
    (laid, epochs, member_slots): (&LaidOut, usize, &[std::ops::Range<usize>]),
    (cells, erodes): (u32, bool),
) -> Result<ReadBack, GpuError> {
    if b.stamps.is_none() {
        b.stamps = Stamps::new(&gpu.device);
    }
    let listed = some(&b.listed_groups)?.clone();
    let mut stamps = b.stamps.as_mut().filter(|_| Stamps::fit(epochs));
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    let groups = (bind, &listed);
    record(
        &mut encoder,
        kernels,
        groups,
        (params_stride(gpu), epochs),
        (laid.slots, cells),
        stamps.as_deref_mut(),
    );
    let particle_bytes = BYTES_PER_SLOT as u64 * u64::from(laid.slots);
    let counted = particle_bytes + 4 * laid.counters.len() as u64;
    let stamp_bytes = stamps.as_ref().map_or(0, |s| s.bytes());
    let at_listed = counted + stamp_bytes;
    // The listed cells expected, within the largest buffer the device makes.
    let most = gpu.device.limits().max_buffer_size;
    if at_listed > most {
        return Err(GpuError::TooLarge(format!(
            "{at_listed} bytes to read back (a buffer holds at most {most})"
        )));
    }
    let per_cell = if erodes { 32 } else { 16 };
    let expected =
        u64::from(b.listed_guess.max(LEAST_LISTED).min(cells + 1)).min((most - at_listed) / per_cell);
    let listed_bytes = 16 * expected;
    let wear_bytes = if erodes { listed_bytes } else { 0 };
    let total = at_listed + listed_bytes + wear_bytes;
    let readback = grow(gpu, &mut b.readback, total, READBACK);
    encoder.copy_buffer_to_buffer(some(&b.particles)?, 0, &readback, 0, particle_bytes);
    encoder.copy_buffer_to_buffer(some(&b.counters)?, 0, &readback, particle_bytes, counted - particle_bytes);
    if let Some(s) = &stamps {
        s.resolve(&mut encoder);
        encoder.copy_buffer_to_buffer(&s.resolved, 0, &readback, counted, stamp_bytes);
    }
    if listed_bytes > 0 {
        encoder.copy_buffer_to_buffer(some(&b.listed)?, 0, &readback, at_listed, listed_bytes);
    }
    if wear_bytes > 0 {
        let (wear, at) = (some(&b.wear)?, 16 * (u64::from(cells) + 1));
        encoder.copy_buffer_to_buffer(wear, at, &readback, at_listed + listed_bytes, wear_bytes);
        encoder.clear_buffer(wear, at, Some(wear_bytes));
    }
    gpu.queue.submit([encoder.finish()]);
    let [counters, stamped, listed, wear] =
        [particle_bytes, counted, at_listed, at_listed + listed_bytes].map(|a| a as usize);
    let period = gpu.queue.get_timestamp_period();
    let (slots, counters, listed, wear, times) = read_with(gpu, &readback, total, |bytes| {
        let flown: &[GpuParticle] = bytemuck::cast_slice(&bytes[..counters]);
        let cells = |b: &[u8]| bytemuck::cast_slice::<u8, [u32; 4]>(b).to_vec();
        // A single run's call copies on its own thread: its caller holds the stage's lock, and
        // a rayon worker waiting on other workers could take up another simulation's call, which
        // would wait for that lock on the same thread (see `GpuFlight::dispatch_one`). A batch's
        // dispatch runs on a thread of its own, outside rayon's pool, which only waits.
        let copy = |r: &std::ops::Range<usize>| flown[r.clone()].to_vec();
        (
            if member_slots.len() > 1 {
                member_slots.par_iter().map(copy).collect()
            } else {
                member_slots.iter().map(copy).collect()
            },
            bytemuck::cast_slice::<u8, u32>(&bytes[counters..stamped]).to_vec(),
            cells(&bytes[listed..wear]),
            cells(&bytes[wear..]),
            stamps.as_ref().map(|s| s.times(&bytes[stamped..listed], period)),
        )
    })?;
    Ok(ReadBack { slots, counters, listed, wear, gpu: times.transpose()? })
}

/// Uploads a dispatch laid out as `laid` (its members' layers into their regions of the second
/// half of the layers' buffer, which `restore` copies into the first), sizes the cells' storage
/// for `cells` cells (and their wear, where a target `erodes`), writes each epoch's parameters,
/// and binds it all.
fn upload(
    gpu: &Gpu,
    kernels: &Kernels,
    b: &mut Buffers,
    (laid, members): (&LaidOut, &[MemberCall]),
    (cells, erodes): (u32, bool),
    epochs: &[(u64, u64)],
) -> Result<Groups, GpuError> {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
    // Each member's swarm; `born` fills the slots after it.
    let particles = grow(gpu, &mut b.particles, BYTES_PER_SLOT as u64 * u64::from(laid.slots), storage);
    for (m, place) in members.iter().zip(&laid.places) {
        let at = BYTES_PER_SLOT as u64 * u64::from(place.slot);
        queue.write_buffer(&particles, at, bytemuck::cast_slice(&m.slots));
    }
    let scene = grow(gpu, &mut b.scene, 4 * laid.words.len() as u64, storage);
    queue.write_buffer(&scene, 0, bytemuck::cast_slice(&laid.words));
    let half = u64::from(cells) + 1;
    let layers = grow(gpu, &mut b.thickness, 8 * half, storage);
    b.layer_cells = Some(cells);
    // The regions rebuilt whole are zeroed in a submission of their own, before the writes
    // (which the queue makes at the start of the next submission) put their spans over them.
    let mut zeroed =
        members.iter().filter(|m| matches!(m.layers, Layers::Whole(_)) && m.scene.cells > 0).peekable();
    if zeroed.peek().is_some() {
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        for m in zeroed {
            encoder.clear_buffer(&layers, 4 * (half + u64::from(m.cell)), Some(4 * u64::from(m.scene.cells)));
        }
        queue.submit([encoder.finish()]);
    }
    for m in members {
        let at = half + u64::from(m.cell);
        let (Layers::Whole(spans) | Layers::Spans(spans)) = &m.layers;
        for (first, span) in spans {
            queue.write_buffer(&layers, 4 * (at + u64::from(*first)), bytemuck::cast_slice(span));
        }
    }
    let counters = grow(gpu, &mut b.counters, 4 * laid.counters.len() as u64, storage);
    queue.write_buffer(&counters, 0, bytemuck::cast_slice(&laid.counters));
    let plan = grow(gpu, &mut b.plan, 4 * laid.plan.len() as u64, storage);
    queue.write_buffer(&plan, 0, bytemuck::cast_slice(&laid.plan));
    // New cell counters start at zero; `gather` leaves them so.
    grow(gpu, &mut b.cells, 16 * half, storage);
    grow(gpu, &mut b.listed, 16 * half, storage);
    // Where a target erodes: the cells' wear counters, then the listed cells' copies.
    grow(gpu, &mut b.wear, if erodes { 32 * half } else { 16 }, storage);
    let indirect = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::INDIRECT;
    grow(gpu, &mut b.listed_groups, 16, indirect);
    let sizes = [members.len() as u32, laid.targets, cells, u32::from(erodes)];
    let stride = params_stride(gpu) as usize;
    let mut bytes = vec![0u8; stride * epochs.len()];
    for (k, &range) in epochs.iter().enumerate() {
        let p = pack::params(range, laid.slots, sizes);
        bytes[k * stride..k * stride + PARAMS_BYTES.get() as usize].copy_from_slice(bytemuck::bytes_of(&p));
    }
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("params"),
        contents: &bytes,
        usage: wgpu::BufferUsages::UNIFORM,
    });
    bind_group(gpu, kernels, b, &params)
}

/// The groups of a dispatch's storage, as `upload` left it, with the parameters `params`.
fn bind_group(gpu: &Gpu, kernels: &Kernels, b: &Buffers, params: &wgpu::Buffer) -> Result<Groups, GpuError> {
    Ok(kernels.groups(
        gpu,
        [
            params,
            some(&b.particles)?,
            some(&b.scene)?,
            some(&b.thickness)?,
            some(&b.counters)?,
            some(&b.cells)?,
            some(&b.listed)?,
            some(&b.plan)?,
            some(&b.wear)?,
            some(&b.listed_groups)?,
        ],
    ))
}

/// Each member's part of what a dispatch read back: its particles (`slots`, one set a member),
/// its counter block (of `words`), and the cells it listed (of `listed`, with their `wear`),
/// counted over its own grids.
fn split(
    members: &[MemberCall],
    places: &[Place],
    (slots, words): (Vec<Vec<GpuParticle>>, &[u32]),
    (listed, wear): (&[[u32; 4]], &[[u32; 4]]),
) -> Vec<Raw> {
    // The listed cells in cell order: each member's are one run of them.
    let mut order: Vec<usize> = (0..listed.len()).collect();
    order.sort_unstable_by_key(|&k| listed[k][0]);
    let from = |cell: u32| order.partition_point(|&k| listed[k][0] < cell);
    members
        .iter()
        .zip(places)
        .zip(slots)
        .map(|((m, place), slots)| {
            let (first, end) = (m.cell, m.cell + m.scene.cells);
            let own = &order[from(first)..from(end)];
            let counter = place.counters as usize;
            Raw {
                slots,
                counters: words[counter..counter + m.counters.len()].to_vec(),
                listed: own
                    .iter()
                    .map(|&k| [listed[k][0] - first, listed[k][1], listed[k][2], listed[k][3]])
                    .collect(),
                wear: own.iter().filter_map(|&k| wear.get(k).copied()).collect(),
            }
        })
        .collect()
}

/// A dispatch's words, particle slots, counters and plan, with where each member lies.
struct LaidOut {
    words: Vec<u32>,
    /// Particle slots of all members.
    slots: u32,
    counters: Vec<u32>,
    plan: Vec<u32>,
    places: Vec<Place>,
    /// Targets of all members.
    targets: u32,
}

/// Lays `members` out one after the other (their slots padded to whole workgroups): the
/// members' words, then the table of all their targets, then each member's own words; the
/// global counters, then each member's block; the plan (no cell listed, each target's band).
fn lay_out(members: &[MemberCall], cells: u32) -> LaidOut {
    let targets: usize = members.iter().map(|m| m.scene.first_cells.len()).sum();
    let table = MEMBER_WORDS * members.len();
    let mut words = vec![0u32; table + TABLE_WORDS * targets];
    let mut slots = 0u32;
    let mut counters = vec![0u32; GLOBAL_COUNTER_WORDS];
    let mut plan = vec![0u32];
    let mut places = Vec::with_capacity(members.len());
    for (m, member) in members.iter().enumerate() {
        let scene = &member.scene;
        let place = Place {
            words: words.len() as u32,
            slot: slots,
            target: (plan.len() - 1) as u32,
            cell: member.cell,
            counters: counters.len() as u32,
        };
        for (t, &first) in scene.first_cells.iter().enumerate() {
            let row = table + TABLE_WORDS * (place.target as usize + t);
            words[row] = member.cell + first;
            words[row + 1] = pack::quantum_thickness(scene, t);
            words[row + 2] = place.counters + (TALLY_WORDS + TARGET_COUNTER_WORDS * t + 3) as u32;
            plan.push(pack::band(scene, t));
        }
        let mut head = member.words;
        pack::place_member(&mut head, scene, place);
        words[MEMBER_WORDS * m..MEMBER_WORDS * (m + 1)].copy_from_slice(&head);
        words.extend_from_slice(&scene.words);
        // Within one binding's slots (checked by `dispatch`), so within u32.
        slots += member.padded_slots() as u32;
        counters.extend_from_slice(&member.counters);
        places.push(place);
    }
    debug_assert!(members.iter().all(|m| m.cell + m.scene.cells <= cells));
    LaidOut { words, slots, counters, plan, places, targets: targets as u32 }
}

/// The wear of the cells listed `from` up to `to` (their copies lie after the `cells` cells'
/// counters), each as coating (low, high) and substrate (low, high), WEAR_QUANTUMs; the copies
/// are cleared once read, so that a later call's counters, which may lie there, start at zero.
fn listed_wear(
    gpu: &Gpu,
    b: &mut Buffers,
    cells: u32,
    (from, to): (u32, u32),
) -> Result<Vec<[u32; 4]>, GpuError> {
    if to <= from {
        return Ok(Vec::new());
    }
    let wear = some(&b.wear)?.clone();
    let (at, bytes) = (16 * (u64::from(cells) + 1 + u64::from(from)), 16 * u64::from(to - from));
    let data = copy_out(gpu, b, &wear, at, bytes)?;
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    encoder.clear_buffer(&wear, at, Some(bytes));
    gpu.queue.submit([encoder.finish()]);
    Ok(bytemuck::cast_slice::<u8, [u32; 4]>(&data).to_vec())
}

impl Buffers {
    /// One half of the layers' buffer, m: as the last dispatch found them (`found`), or left
    /// them.
    pub fn read_thickness(&mut self, gpu: &Gpu, found: bool) -> Result<Vec<f32>, GpuError> {
        let layer = some(&self.thickness)?.clone();
        let half = 4 * (u64::from(self.layer_cells.unwrap_or(0)) + 1);
        let at = if found { half } else { 0 };
        Ok(bytemuck::cast_slice(&copy_out(gpu, self, &layer, at, half)?).to_vec())
    }
}

/// `bytes` of `source` from byte `at`, copied through the read-back buffer.
fn copy_out(
    gpu: &Gpu,
    b: &mut Buffers,
    source: &wgpu::Buffer,
    at: u64,
    bytes: u64,
) -> Result<Vec<u8>, GpuError> {
    let readback = grow(gpu, &mut b.readback, bytes, READBACK);
    let mut encoder = gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    encoder.copy_buffer_to_buffer(source, at, &readback, 0, bytes);
    gpu.queue.submit([encoder.finish()]);
    read(gpu, &readback, bytes)
}

/// Waits for the queue and copies the first `bytes` of `readback` out.
fn read(gpu: &Gpu, readback: &wgpu::Buffer, bytes: u64) -> Result<Vec<u8>, GpuError> {
    read_with(gpu, readback, bytes, <[u8]>::to_vec)
}

/// Waits for the queue, and hands the first `bytes` of `readback`, mapped, to `take`: what it
/// copies out is copied once.
fn read_with<T>(
    gpu: &Gpu,
    readback: &wgpu::Buffer,
    bytes: u64,
    take: impl FnOnce(&[u8]) -> T,
) -> Result<T, GpuError> {
    let slice = readback.slice(..bytes);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    let err = |e: &dyn std::fmt::Display| GpuError::Readback(e.to_string());
    gpu.device
        .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(Duration::from_secs(600)) })
        .map_err(|e| err(&e))?;
    rx.recv().map_err(|e| err(&e))?.map_err(|e| err(&e))?;
    let out = take(&slice.get_mapped_range().map_err(|e| GpuError::Readback(format!("{e:?}")))?);
    readback.unmap();
    Ok(out)
}

/// Usage of the readback buffer.
const READBACK: wgpu::BufferUsages = wgpu::BufferUsages::MAP_READ.union(wgpu::BufferUsages::COPY_DST);

/// `slot`'s buffer, replaced by a larger one if it holds fewer than `bytes`: `bytes` and a
/// sixteenth more (within one binding's limit), so that a run whose calls grow a little at a
/// time does not allocate at each, while a particle slot takes at most 36 × 17/16 = 38.3 bytes
/// of the particles' buffer (the read-back buffer, in host-visible memory, holds as much again).
fn grow(gpu: &Gpu, slot: &mut Option<wgpu::Buffer>, bytes: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    let bytes = bytes.max(16).next_multiple_of(16);
    match slot {
        Some(b) if b.size() >= bytes => b.clone(),
        _ => {
            // The read-back buffer, never bound, may hold more than a binding.
            let limit = gpu.binding_bytes().max(bytes);
            let b = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: (bytes + bytes / 16).next_multiple_of(16).min(limit),
                usage,
                mapped_at_creation: false,
            });
            *slot = Some(b.clone());
            b
        }
    }
}

fn some(b: &Option<wgpu::Buffer>) -> Result<&wgpu::Buffer, GpuError> {
    b.as_ref().ok_or_else(|| GpuError::Device("a buffer was not allocated".into()))
}
