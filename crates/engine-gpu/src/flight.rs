//! [`GpuFlight`]: the engine's flight stage on the GPU. Each call uploads what changed (the
//! particles, the scene's words, the rows of the layers that moved) and submits, in one go,
//! `restore` (the layers the epochs read reset to those the call is handed), then for each
//! layer epoch of the call the `fly` kernel over the particles and `settle` (the layers brought
//! up to date with the call's deposits), each followed by `census`, then `gather` over the cells
//! they listed; it reads back the particles, the counters and the listed cells once.

use crate::device::{Gpu, GpuOptions};
use crate::pack::{
    self, BYTES_PER_SLOT, GpuParticle, OBSTACLE_COUNTER_WORDS, ROW_GROUPS, TALLY_WORDS, TARGET_COUNTER_WORDS,
    WORKGROUP,
};
use crate::{GpuError, scope};
use rayon::prelude::*;
use spraysim_engine::deposit::DepositSurface;
use spraysim_engine::pipeline::{CellBook, FlightJob, FlightReport, FlightStage};
use spraysim_engine::tally::{Quanta, Tallied, Tally};
use spraysim_engine::world::{ObstacleTally, TargetTally};
use std::sync::Mutex;
use std::time::{Duration, Instant};
use wgpu::util::DeviceExt;

/// The kernels' source.
const SOURCE: &str = include_str!("flight.wgsl");

/// The engine's flight stage on the GPU (see the crate's docs).
#[derive(Debug)]
pub struct GpuFlight {
    gpu: Gpu,
    layout: wgpu::BindGroupLayout,
    fly: wgpu::ComputePipeline,
    restore: wgpu::ComputePipeline,
    settle: wgpu::ComputePipeline,
    census: wgpu::ComputePipeline,
    gather: wgpu::ComputePipeline,
    /// The most epochs a call takes (see [`GpuOptions::max_epochs_per_call`]).
    max_epochs: u64,
    buffers: Mutex<Buffers>,
    profile: Mutex<Profile>,
}

/// Where the calls' time went, s, summed over the calls since the last
/// [`GpuFlight::take_profile`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Profile {
    /// Calls.
    pub calls: u64,
    /// Layer epochs flown, in all calls.
    pub epochs: u64,
    /// Particles flown.
    pub particles: u64,
    /// Laying the job out and uploading it (particles, scene, changed layers).
    pub upload: f64,
    /// From submitting the kernels (every epoch's) to their counters and particles read back:
    /// the kernels' time, with the copies and the wait.
    pub kernels: f64,
    /// Reading back the cells listed (a second submission and wait).
    pub cells: f64,
    /// Turning what was read back into the engine's report.
    pub report: f64,
}

/// Storage that grows as calls need.
#[derive(Debug, Default)]
struct Buffers {
    particles: Option<wgpu::Buffer>,
    scene: Option<wgpu::Buffer>,
    thickness: Option<wgpu::Buffer>,
    counters: Option<wgpu::Buffer>,
    cells: Option<wgpu::Buffer>,
    listed: Option<wgpu::Buffer>,
    plan: Option<wgpu::Buffer>,
    wear: Option<wgpu::Buffer>,
    readback: Option<wgpu::Buffer>,
    /// Per target, the identity of the layer the GPU's copy holds and its first cell there
    /// (empty: the copy holds nothing known).
    mirror: Vec<(u64, u32)>,
    /// Words of each half of `thickness` (the cells of all grids, and a spare).
    layer_words: u64,
}

impl GpuFlight {
    /// Opens a device as `options` asks and builds the kernels.
    pub fn new(options: &GpuOptions) -> Result<GpuFlight, GpuError> {
        let gpu = Gpu::open(options)?;
        let device = &gpu.device;
        // A kernel the driver cannot build is an error, not a panic.
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("flight.wgsl"),
            source: wgpu::ShaderSource::Wgsl(SOURCE.into()),
        });
        let entry = |binding: u32, ty: wgpu::BufferBindingType| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
            count: None,
        };
        let rw = wgpu::BufferBindingType::Storage { read_only: false };
        let ro = wgpu::BufferBindingType::Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("flight"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Uniform,
                        // Each epoch's parameters at their own offset.
                        has_dynamic_offset: true,
                        min_binding_size: Some(PARAMS_BYTES),
                    },
                    count: None,
                },
                entry(1, rw),
                entry(2, ro),
                entry(3, rw),
                entry(4, rw),
                entry(5, rw),
                entry(6, rw),
                entry(7, rw),
                entry(8, rw),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("flight"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                cache: None,
            })
        };
        let (fly, restore, settle) = (pipeline("fly"), pipeline("restore"), pipeline("settle"));
        let (census, gather) = (pipeline("census"), pipeline("gather"));
        if let Some(e) = pollster::block_on(scope.pop()) {
            return Err(GpuError::Device(format!("the flight kernels do not build: {e}")));
        }
        let (buffers, profile) = (Mutex::new(Buffers::default()), Mutex::new(Profile::default()));
        let max_epochs = match options.max_epochs_per_call {
            0 => crate::device::EPOCHS_PER_CALL,
            n => n,
        };
        Ok(GpuFlight { gpu, layout, fly, restore, settle, census, gather, max_epochs, buffers, profile })
    }

    /// The adapter the kernels run on.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// The GPU's copy of the layers, m, every target's cells one after the other, as the last
    /// call found it: the layers as they stood at that call's start.
    pub fn read_layers(&self) -> Result<Vec<f32>, GpuError> {
        self.read_thickness(true)
    }

    /// The GPU's own layers, m, as the last call left them: the layers it was handed with what
    /// that call deposited added at each of its epochs' ends, in f32, as the engine adds them.
    pub fn read_settled_layers(&self) -> Result<Vec<f32>, GpuError> {
        self.read_thickness(false)
    }

    /// One half of the layers' buffer: as the last call found them (`found`), or left them.
    fn read_thickness(&self, found: bool) -> Result<Vec<f32>, GpuError> {
        let mut b = self.buffers.lock().map_err(|_| GpuError::Device("a previous call failed".into()))?;
        let layer = some(&b.thickness)?.clone();
        let half = b.layer_words * 4;
        let at = if found { half } else { 0 };
        Ok(bytemuck::cast_slice(&self.copy_out(&mut b, &layer, at, half)?).to_vec())
    }

    /// Where the calls' time went since the last call of this, which starts the sums afresh.
    pub fn take_profile(&self) -> Profile {
        self.profile.lock().map(|mut p| std::mem::take(&mut *p)).unwrap_or_default()
    }

    /// Runs `job` on the GPU.
    fn run(&self, job: &FlightJob<'_>) -> Result<FlightReport, GpuError> {
        let start = Instant::now();
        // Laid out before the lock is taken: the conversions run on rayon's workers, and a worker
        // that waits for them while holding the lock could take up another simulation's call,
        // which would wait for the lock on the same thread.
        let prepared = prepare(job);
        let mut b = self.buffers.lock().map_err(|_| GpuError::Device("a previous call failed".into()))?;
        // Forgotten until the call succeeds: a call that fails, or is refused, loses the layers'
        // changes the engine handed it.
        let held = std::mem::take(&mut b.mirror);
        let Prepared { scene, slots, nozzle } = prepared?;
        let n =
            u32::try_from(slots.len()).map_err(|_| GpuError::TooLarge("the particles of a call".into()))?;
        let limit = self.gpu.device.limits().max_storage_buffer_binding_size;
        let cell_bytes = 16 * (u64::from(scene.cells) + 1);
        if cell_bytes > limit || (BYTES_PER_SLOT * slots.len()) as u64 > limit {
            return Err(GpuError::TooLarge(format!(
                "{} cells or {n} particles in one call (one binding holds at most {limit} bytes)",
                scene.cells
            )));
        }
        let epochs = pack::epochs(job);
        if epochs.is_empty() {
            return Err(GpuError::Device("a call of no steps".into()));
        }
        let counter_words = TALLY_WORDS
            + TARGET_COUNTER_WORDS * job.targets.len()
            + OBSTACLE_COUNTER_WORDS * job.config.obstacles.len();
        let mirror = self.upload(&mut b, job, (&scene, &held), &slots, counter_words);
        let params = self.params(job, &scene, (n, nozzle), &epochs);
        let bind = self.bind_group(&b, &params)?;
        let particle_bytes = (BYTES_PER_SLOT * slots.len().max(1)) as u64;
        let counter_bytes = 4 * counter_words as u64;
        let readback = grow(&self.gpu.device, &mut b.readback, particle_bytes + counter_bytes, READBACK);
        let uploaded = Instant::now();
        let mut encoder =
            self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor::default());
            let stride = self.params_stride();
            let cells = groups(scene.cells + 1);
            pass.set_bind_group(0, &bind, &[0]);
            pass.set_pipeline(&self.restore);
            pass.dispatch_workgroups(cells.0, cells.1, 1);
            for e in 0..epochs.len() {
                pass.set_bind_group(0, &bind, &[(e as u64 * stride) as u32]);
                pass.set_pipeline(&self.fly);
                let (x, y) = groups(n);
                pass.dispatch_workgroups(x, y, 1);
                pass.set_pipeline(&self.census);
                pass.dispatch_workgroups(1, 1, 1);
                // After every epoch: between two, for the next one; after the last, for
                // `read_settled_layers` (the next call starts from the layers it is handed).
                pass.set_pipeline(&self.settle);
                pass.dispatch_workgroups(cells.0, cells.1, 1);
                pass.set_pipeline(&self.census);
                pass.dispatch_workgroups(1, 1, 1);
            }
            pass.set_pipeline(&self.gather);
            pass.dispatch_workgroups(cells.0, cells.1, 1);
        }
        let (particles, counters) = (some(&b.particles)?, some(&b.counters)?);
        encoder.copy_buffer_to_buffer(particles, 0, &readback, 0, particle_bytes);
        encoder.copy_buffer_to_buffer(counters, 0, &readback, particle_bytes, counter_bytes);
        self.gpu.queue.submit([encoder.finish()]);
        let bytes = self.read(&readback, particle_bytes + counter_bytes)?;
        let words: &[u32] = bytemuck::cast_slice(&bytes[particle_bytes as usize..]);
        let flew = Instant::now();
        let listed = self.listed(&mut b, words[2])?;
        let wear = if scene.erodes { self.listed_wear(&mut b, scene.cells, words[2])? } else { Vec::new() };
        let gathered = Instant::now();
        b.mirror = mirror;
        // Turned into the engine's report without the lock (on rayon's workers, as above).
        drop(b);
        let flown: &[GpuParticle] = bytemuck::cast_slice(&bytes[..BYTES_PER_SLOT * slots.len()]);
        let report = report(job, &scene, flown, words, (&listed, &wear));
        if let Ok(mut p) = self.profile.lock() {
            p.calls += 1;
            p.epochs += epochs.len() as u64;
            p.particles += u64::from(n);
            p.upload += (uploaded - start).as_secs_f64();
            p.kernels += (flew - uploaded).as_secs_f64();
            p.cells += (gathered - flew).as_secs_f64();
            p.report += gathered.elapsed().as_secs_f64();
        }
        Ok(report)
    }

    /// Bytes between two epochs' parameters: the adapter's alignment of uniform offsets.
    fn params_stride(&self) -> u64 {
        let align = u64::from(self.gpu.device.limits().min_uniform_buffer_offset_alignment);
        PARAMS_BYTES.get().next_multiple_of(align.max(1))
    }

    /// The parameters of each of `epochs`, one after the other at [`GpuFlight::params_stride`].
    fn params(
        &self,
        job: &FlightJob<'_>,
        scene: &pack::SceneWords,
        sizes: (u32, u32),
        epochs: &[(u64, u64)],
    ) -> wgpu::Buffer {
        let stride = self.params_stride() as usize;
        let mut bytes = vec![0u8; stride * epochs.len().max(1)];
        for (k, &range) in epochs.iter().enumerate() {
            let p = pack::params(job, scene, sizes, range);
            bytes[k * stride..k * stride + PARAMS_BYTES.get() as usize]
                .copy_from_slice(bytemuck::bytes_of(&p));
        }
        self.gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: &bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        })
    }

    /// Uploads the call's particles, scene and layers (only the spans that changed where the
    /// GPU's copy, `held`, holds the same layers; as the call finds them, into the second half
    /// of the layers' buffer), and the counters at their start; returns what the copy holds
    /// now.
    fn upload(
        &self,
        b: &mut Buffers,
        job: &FlightJob<'_>,
        (scene, held): (&pack::SceneWords, &[(u64, u32)]),
        slots: &[GpuParticle],
        counters: usize,
    ) -> Vec<(u64, u32)> {
        let (device, queue) = (&self.gpu.device, &self.gpu.queue);
        let storage =
            wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        let particles = grow(device, &mut b.particles, (BYTES_PER_SLOT * slots.len().max(1)) as u64, storage);
        queue.write_buffer(&particles, 0, bytemuck::cast_slice(slots));
        let words = grow(device, &mut b.scene, 4 * scene.words.len() as u64, storage);
        queue.write_buffer(&words, 0, bytemuck::cast_slice(&scene.words));
        let layout: Vec<(u64, u32)> = job
            .revised
            .iter()
            .zip(&scene.first_cells)
            .map(|(r, &first)| (r.as_ref().map_or(0, |r| r.0), first))
            .collect();
        let cells = u64::from(scene.cells) + 1;
        let fresh = b.thickness.as_ref().is_none_or(|t| t.size() < 8 * cells)
            || b.layer_words != cells
            || held != layout.as_slice()
            || job.revised.iter().any(Option::is_none);
        let layer = grow(device, &mut b.thickness, 8 * cells, storage);
        b.layer_words = cells;
        // Into the second half, as the call finds the layers; `restore` copies it into the first.
        if fresh {
            queue.write_buffer(&layer, 4 * cells, bytemuck::cast_slice(&pack::thicknesses(job)));
        } else {
            for ((target, revised), &first) in job.targets.iter().zip(job.revised).zip(&scene.first_cells) {
                let Some((_, changed)) = revised else { continue };
                let (Some(&lo), Some(&hi)) = (changed.first(), changed.last()) else { continue };
                let span: Vec<f32> =
                    target.surface.thickness()[lo as usize..=hi as usize].iter().map(|&t| t as f32).collect();
                queue.write_buffer(&layer, 4 * (cells + u64::from(first + lo)), bytemuck::cast_slice(&span));
            }
        }
        let start = pack::counters(scene, job.targets.len(), counters);
        let c = grow(device, &mut b.counters, 4 * counters as u64, storage);
        queue.write_buffer(&c, 0, bytemuck::cast_slice(&start));
        let plan = pack::plan(scene, job.targets.len());
        let p = grow(device, &mut b.plan, 4 * plan.len() as u64, storage);
        queue.write_buffer(&p, 0, bytemuck::cast_slice(&plan));
        // New cell counters start at zero; `gather` leaves them so.
        let cells = 16 * (u64::from(scene.cells) + 1);
        grow(device, &mut b.cells, cells, storage);
        grow(device, &mut b.listed, cells, storage);
        // Where a target erodes: the cells' wear counters, then the listed cells' copies.
        grow(device, &mut b.wear, if scene.erodes { 2 * cells } else { 16 }, storage);
        layout
    }

    fn bind_group(&self, b: &Buffers, params: &wgpu::Buffer) -> Result<wgpu::BindGroup, GpuError> {
        let buffers = [
            params,
            some(&b.particles)?,
            some(&b.scene)?,
            some(&b.thickness)?,
            some(&b.counters)?,
            some(&b.cells)?,
            some(&b.listed)?,
            some(&b.plan)?,
            some(&b.wear)?,
        ];
        let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
            .iter()
            .enumerate()
            .map(|(k, buffer)| wgpu::BindGroupEntry {
                binding: k as u32,
                // The parameters: one epoch's, at the offset each dispatch gives.
                resource: if k == 0 {
                    wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer,
                        offset: 0,
                        size: Some(PARAMS_BYTES),
                    })
                } else {
                    buffer.as_entire_binding()
                },
            })
            .collect();
        Ok(self.gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: None,
            layout: &self.layout,
            entries: &entries,
        }))
    }

    /// The `count` cells listed, each as (cell, quanta low, quanta high, impacts).
    fn listed(&self, b: &mut Buffers, count: u32) -> Result<Vec<[u32; 4]>, GpuError> {
        if count == 0 {
            return Ok(Vec::new());
        }
        let listed = some(&b.listed)?.clone();
        let data = self.copy_out(b, &listed, 0, 16 * u64::from(count))?;
        Ok(bytemuck::cast_slice::<u8, [u32; 4]>(&data).to_vec())
    }

    /// The wear of the `count` cells listed (after the `cells` cells' counters), each as coating
    /// (low, high) and substrate (low, high), WEAR_QUANTUMs; the copies are cleared once read,
    /// so that a later call's counters, which may lie there, start at zero.
    fn listed_wear(&self, b: &mut Buffers, cells: u32, count: u32) -> Result<Vec<[u32; 4]>, GpuError> {
        if count == 0 {
            return Ok(Vec::new());
        }
        let wear = some(&b.wear)?.clone();
        let (at, bytes) = (16 * (u64::from(cells) + 1), 16 * u64::from(count));
        let data = self.copy_out(b, &wear, at, bytes)?;
        let mut encoder =
            self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encoder.clear_buffer(&wear, at, Some(bytes));
        self.gpu.queue.submit([encoder.finish()]);
        Ok(bytemuck::cast_slice::<u8, [u32; 4]>(&data).to_vec())
    }

    /// `bytes` of `source` from byte `at`, copied through the read-back buffer.
    fn copy_out(
        &self,
        b: &mut Buffers,
        source: &wgpu::Buffer,
        at: u64,
        bytes: u64,
    ) -> Result<Vec<u8>, GpuError> {
        let readback = grow(&self.gpu.device, &mut b.readback, bytes, READBACK);
        let mut encoder =
            self.gpu.device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encoder.copy_buffer_to_buffer(source, at, &readback, 0, bytes);
        self.gpu.queue.submit([encoder.finish()]);
        self.read(&readback, bytes)
    }

    /// Waits for the queue and copies the first `bytes` of `readback` out.
    fn read(&self, readback: &wgpu::Buffer, bytes: u64) -> Result<Vec<u8>, GpuError> {
        let slice = readback.slice(..bytes);
        let (tx, rx) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        let err = |e: &dyn std::fmt::Display| GpuError::Readback(e.to_string());
        self.gpu
            .device
            .poll(wgpu::PollType::Wait { submission_index: None, timeout: Some(Duration::from_secs(600)) })
            .map_err(|e| err(&e))?;
        rx.recv().map_err(|e| err(&e))?.map_err(|e| err(&e))?;
        let out = slice.get_mapped_range().map_err(|e| GpuError::Readback(format!("{e:?}")))?.to_vec();
        readback.unmap();
        Ok(out)
    }
}

/// A call laid out for the kernels: its scene's words, its particle slots and a nozzle
/// particle's quanta.
struct Prepared {
    scene: pack::SceneWords,
    slots: Vec<GpuParticle>,
    nozzle: u32,
}

/// Lays `job` out for the kernels, once the scope allows it.
fn prepare(job: &FlightJob<'_>) -> Result<Prepared, GpuError> {
    scope::check(job.config)?;
    let scene = pack::scene_words(job);
    let nozzle = job
        .particles
        .iter()
        .zip(job.quanta)
        .find(|(p, _)| p.flags() & spraysim_engine::particles::flags::RELEASED == 0)
        .map_or(0, |(_, &q)| q);
    let nozzle =
        u32::try_from(nozzle).map_err(|_| GpuError::TooLarge("a nozzle particle's quanta".into()))?;
    let slots = job.particles.par_iter().map(|p| GpuParticle::of(p, job)).collect();
    Ok(Prepared { scene, slots, nozzle })
}

/// Bytes of one epoch's parameters.
const PARAMS_BYTES: wgpu::BufferSize = match wgpu::BufferSize::new(std::mem::size_of::<pack::Params>() as u64)
{
    Some(n) => n,
    None => panic!("the parameters take bytes"),
};

/// Usage of the readback buffer.
const READBACK: wgpu::BufferUsages = wgpu::BufferUsages::MAP_READ.union(wgpu::BufferUsages::COPY_DST);

/// `slot`'s buffer, replaced by a larger one (a power of two of bytes) if it holds fewer than
/// `bytes`.
fn grow(
    device: &wgpu::Device,
    slot: &mut Option<wgpu::Buffer>,
    bytes: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let bytes = bytes.max(16).next_multiple_of(16);
    match slot {
        Some(b) if b.size() >= bytes => b.clone(),
        _ => {
            let b = device.create_buffer(&wgpu::BufferDescriptor {
                label: None,
                size: bytes.next_power_of_two(),
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

/// Workgroups (across, rows) covering `n` invocations.
fn groups(n: u32) -> (u32, u32) {
    let g = n.div_ceil(WORKGROUP).max(1);
    (g.min(ROW_GROUPS), g.div_ceil(ROW_GROUPS))
}

/// A Tallied from a counter slot (count, quanta low, quanta high).
fn tallied(w: &[u32], at: usize) -> Tallied {
    Tallied { count: u64::from(w[at]), quanta: Quanta::from(w[at + 1]) | (Quanta::from(w[at + 2]) << 32) }
}

/// The report of `job` from the particles flown, the counter words, and the listed cells with
/// their wear (none where no target erodes).
fn report(
    job: &FlightJob<'_>,
    scene: &pack::SceneWords,
    flown: &[GpuParticle],
    w: &[u32],
    (listed, wear): (&[[u32; 4]], &[[u32; 4]]),
) -> FlightReport {
    let particles = flown.par_iter().zip(job.particles).map(|(g, p)| g.update(p)).collect();
    let slot = |k: usize| tallied(w, 4 + 4 * k);
    let tally = Tally {
        left_domain: slot(0),
        expired: slot(1),
        overspray: slot(2),
        substrate_first_impacts: slot(3),
        substrate_first_rebounds: slot(4),
        released_left: slot(5),
        released_expired: slot(6),
        ..Tally::default()
    };
    let targets = (0..job.targets.len())
        .map(|t| {
            let at = TALLY_WORDS + TARGET_COUNTER_WORDS * t;
            let s = |k: usize| tallied(w, at + 4 * k);
            TargetTally {
                hits: u64::from(w[at]),
                stuck: s(1),
                loose: s(2),
                trapped: s(3),
                delivered: s(4),
                stuck_back: s(5),
                received: s(6),
                // A volume alone: its low and high words start the slot.
                received_back: Quanta::from(w[at + 28]) | (Quanta::from(w[at + 29]) << 32),
                detached: Tallied::default(),
            }
        })
        .collect();
    let base = TALLY_WORDS + TARGET_COUNTER_WORDS * job.targets.len();
    let obstacles = (0..job.config.obstacles.len())
        .map(|o| {
            let at = base + OBSTACLE_COUNTER_WORDS * o;
            ObstacleTally { hits: u64::from(w[at]), stuck: tallied(w, at + 4), received: tallied(w, at + 8) }
        })
        .collect();
    let mut cells: Vec<Vec<CellBook>> = vec![Vec::new(); job.targets.len()];
    let pair = |lo: u32, hi: u32| u64::from(lo) | (u64::from(hi) << 32);
    for (k, &[cell, lo, hi, hits]) in listed.iter().enumerate() {
        // The target whose grid holds the cell: the last whose first cell is not past it.
        let t = scene.first_cells.partition_point(|&f| f <= cell).saturating_sub(1);
        let wear = wear.get(k).map_or([0, 0], |w| [pair(w[0], w[1]), pair(w[2], w[3])]);
        cells[t].push(CellBook { cell: cell - scene.first_cells[t], quanta: pair(lo, hi), hits, wear });
    }
    // In cell order, whatever order the invocations listed them in.
    cells.iter_mut().for_each(|c| c.sort_unstable_by_key(|b| b.cell));
    let steps = u64::from(w[0]) | (u64::from(w[1]) << 32);
    FlightReport { particles, tally, targets, obstacles, cells, steps, updates: steps }
}

impl FlightStage for GpuFlight {
    fn fly(&self, job: &FlightJob<'_>) -> Result<FlightReport, String> {
        self.run(job).map_err(|e| e.to_string())
    }

    fn describe(&self) -> String {
        self.gpu.describe()
    }

    fn epochs_per_call(&self) -> u64 {
        self.max_epochs
    }

    fn particles_per_call(&self) -> usize {
        let limit = self.gpu.device.limits().max_storage_buffer_binding_size;
        usize::try_from(limit / BYTES_PER_SLOT as u64).unwrap_or(usize::MAX)
    }

    fn profile(&self) -> Option<String> {
        let p = self.take_profile();
        let per_call = |s: f64| 1e6 * s / p.calls.max(1) as f64;
        Some(format!(
            "{} calls of {:.1} epochs and {:.0} particles: per call, upload {:.0} µs, kernels with counters and \
             particles read back {:.0} µs, listed cells read back {:.0} µs, report {:.0} µs",
            p.calls,
            p.epochs as f64 / p.calls.max(1) as f64,
            p.particles as f64 / p.calls.max(1) as f64,
            per_call(p.upload),
            per_call(p.kernels),
            per_call(p.cells),
            per_call(p.report)
        ))
    }
}
