//! Where the GPU stage's time goes: the wall-clock phases of each dispatch (laying out and
//! uploading, the kernels with their read-back, the listed cells' read-back), the GPU's own
//! timestamps of each kernel where the adapter writes them inside a pass, and the [`Profile`]
//! that sums them over calls for benchmarks.

use crate::GpuError;
use std::fmt::Write as _;

/// The kernels of a dispatch, as its timestamps tell them apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kernel {
    /// The layers as the call found them, copied into the half the epochs read.
    Restore,
    /// The newborns sampled in their slots.
    Born,
    /// An epoch's flight of every slot.
    Fly,
    /// The listed cells' count and the targets' bands copied into plain memory.
    Census,
    /// An epoch's deposits added to the listed cells' layers.
    Settle,
    /// The listed cells' sums copied out and their counters cleared.
    Gather,
}

/// GPU time of each kernel, s, from the timestamps written between the kernels of a dispatch
/// (each one the time from the previous kernel's end to its own: with the barriers between
/// them, its run and its wait for the one before).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KernelTimes {
    /// `restore`: the layers as the call found them copied into the half the epochs read, once
    /// a call, over every cell.
    pub restore: f64,
    /// `born`: the newborns sampled in their slots, once a call.
    pub born: f64,
    /// `fly`: every slot flown through an epoch, once an epoch.
    pub fly: f64,
    /// `census`: the count of listed cells and the targets' bands copied into plain memory,
    /// twice an epoch (one workgroup).
    pub census: f64,
    /// `settle`: an epoch's deposits added to the listed cells' layers, once an epoch.
    pub settle: f64,
    /// `gather`: the listed cells' sums copied out and their counters cleared, once a call.
    pub gather: f64,
}

impl KernelTimes {
    /// The sum over every kernel, s.
    pub fn total(&self) -> f64 {
        self.restore + self.born + self.fly + self.census + self.settle + self.gather
    }

    fn add(&mut self, kernel: Kernel, seconds: f64) {
        *match kernel {
            Kernel::Restore => &mut self.restore,
            Kernel::Born => &mut self.born,
            Kernel::Fly => &mut self.fly,
            Kernel::Census => &mut self.census,
            Kernel::Settle => &mut self.settle,
            Kernel::Gather => &mut self.gather,
        } += seconds;
    }

    fn sum(&mut self, other: &KernelTimes) {
        self.restore += other.restore;
        self.born += other.born;
        self.fly += other.fly;
        self.census += other.census;
        self.settle += other.settle;
        self.gather += other.gather;
    }
}

/// Where a dispatch's time went, s.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Timing {
    /// Laying the members out and uploading them.
    pub upload: f64,
    /// From submitting the kernels to their counters and particles read back.
    pub kernels: f64,
    /// Reading back the listed cells past those read with the kernels' results.
    pub cells: f64,
    /// Whether it took that second copy.
    pub second_copy: bool,
    /// Members, and of those the ones whose layers were uploaded whole.
    pub members: (u64, u64),
    /// The GPU's time of each kernel, where the adapter wrote timestamps.
    pub gpu: Option<KernelTimes>,
}

/// Timestamps written between the kernels of a dispatch, on an adapter that writes them inside
/// a compute pass: the query set, the buffer they are resolved into, and which kernel ran
/// before each (after the first, written at the pass's start).
#[derive(Debug)]
pub(crate) struct Stamps {
    set: wgpu::QuerySet,
    /// Where the set is resolved, to be copied into the read-back buffer.
    pub resolved: wgpu::Buffer,
    /// The kernel that ran before each timestamp after the first, in order.
    kernels: Vec<Kernel>,
}

/// Timestamps a query set holds: a dispatch of more epochs goes untimed.
const MAX_STAMPS: u32 = wgpu::QUERY_SET_MAX_QUERIES;

impl Stamps {
    /// Timestamps for the dispatches of `device`, or `None` where it does not write them inside
    /// passes (see [`crate::Gpu::open`], which asks for them where the adapter offers them).
    pub fn new(device: &wgpu::Device) -> Option<Stamps> {
        if !device.features().contains(TIMESTAMPS) {
            return None;
        }
        let set = device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("kernel timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: MAX_STAMPS,
        });
        let resolved = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("resolved timestamps"),
            size: u64::from(MAX_STAMPS) * wgpu::QUERY_SIZE as u64,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        Some(Stamps { set, resolved, kernels: Vec::new() })
    }

    /// Whether a dispatch of `epochs` epochs fits the set: a timestamp at the start, then one
    /// after each of `restore`, `born`, each epoch's four kernels and `gather`.
    pub fn fit(epochs: usize) -> bool {
        4 + 4 * epochs as u64 <= u64::from(MAX_STAMPS)
    }

    /// Starts a dispatch's timestamps at the start of `pass`.
    pub fn start(&mut self, pass: &mut wgpu::ComputePass<'_>) {
        self.kernels.clear();
        pass.write_timestamp(&self.set, 0);
    }

    /// Writes a timestamp after `kernel`, the last dispatched on `pass`.
    pub fn after(&mut self, pass: &mut wgpu::ComputePass<'_>, kernel: Kernel) {
        self.kernels.push(kernel);
        pass.write_timestamp(&self.set, self.kernels.len() as u32);
    }

    /// Bytes of the dispatch's resolved timestamps.
    pub fn bytes(&self) -> u64 {
        (self.kernels.len() as u64 + 1) * wgpu::QUERY_SIZE as u64
    }

    /// Resolves the dispatch's timestamps into [`Stamps::resolved`].
    pub fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.set, 0..self.kernels.len() as u32 + 1, &self.resolved, 0);
    }

    /// Each kernel's time from the resolved timestamps `bytes` (ticks of `period` ns).
    pub fn times(&self, bytes: &[u8], period: f32) -> Result<KernelTimes, GpuError> {
        let ticks: &[u64] = bytemuck::try_cast_slice(bytes).map_err(|e| GpuError::Readback(e.to_string()))?;
        let mut out = KernelTimes::default();
        for (&kernel, pair) in self.kernels.iter().zip(ticks.windows(2)) {
            // A clock that steps back (some drivers, between two queues' timestamps) counts none.
            out.add(kernel, 1e-9 * f64::from(period) * pair[1].saturating_sub(pair[0]) as f64);
        }
        Ok(out)
    }
}

/// The features timestamps between kernels need.
pub(crate) const TIMESTAMPS: wgpu::Features =
    wgpu::Features::TIMESTAMP_QUERY.union(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);

/// Where the calls' time went, s, summed over the calls since the last
/// [`crate::GpuFlight::take_profile`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Profile {
    /// Calls (dispatches; a batch's members share one).
    pub calls: u64,
    /// Layer epochs flown, in all calls.
    pub epochs: u64,
    /// Particles flown.
    pub particles: u64,
    /// Laying the calls out and uploading them (particles, scene, changed layers).
    pub upload: f64,
    /// From submitting the kernels (every epoch's) to their counters and particles read back:
    /// the kernels' time, with the copies and the wait.
    pub kernels: f64,
    /// Reading back the cells listed past those read back with the kernels' results (as many
    /// as the last call listed, twice over): a second submission and wait.
    pub cells: f64,
    /// Calls that took that second copy: those that listed more than twice as many cells as the
    /// call before, or 256 (a run's first, more than 256).
    pub second_copies: u64,
    /// Turning what was read back into the engine's reports.
    pub report: f64,
    /// Members flown (simulations' calls: one a dispatch for a single run).
    pub members: u64,
    /// Of those, the ones whose layers were uploaded whole (the GPU's copy held nothing known of
    /// them); the others uploaded only the cells changed since their last call.
    pub whole: u64,
    /// The GPU's time of each kernel, summed over the calls timed.
    pub gpu: KernelTimes,
    /// Calls whose kernels the GPU timed: all of them on an adapter that writes timestamps
    /// inside passes (and at most 1 023 epochs a call), none elsewhere.
    pub timed: u64,
    /// Layer epochs of the calls timed.
    pub timed_epochs: u64,
}

impl Profile {
    /// Where the time went, per call, in words (for benchmarks).
    pub fn describe(&self) -> String {
        let calls = self.calls.max(1) as f64;
        let per_call = |s: f64| 1e6 * s / calls;
        let mut out = format!(
            "{} calls of {:.1} epochs and {:.0} particles: per call, upload {:.0} µs, kernels with counters and \
             particles read back {:.0} µs, listed cells read back {:.0} µs (a second copy in {} calls), report \
             {:.0} µs; layers uploaded whole for {} of {} members flown",
            self.calls,
            self.epochs as f64 / calls,
            self.particles as f64 / calls,
            per_call(self.upload),
            per_call(self.kernels),
            per_call(self.cells),
            self.second_copies,
            per_call(self.report),
            self.whole,
            self.members
        );
        if self.timed == 0 {
            out.push_str("; no kernel timestamps (the adapter does not write them inside passes)");
            return out;
        }
        let g = &self.gpu;
        let timed = self.timed as f64;
        let per = |s: f64| 1e6 * s / timed;
        let per_epoch = |s: f64| 1e6 * s / self.timed_epochs.max(1) as f64;
        let _ = write!(
            out,
            "; GPU time per call {:.0} µs ({} of {} calls timed): restore {:.0}, born {:.0}, fly {:.0} \
             ({:.1} an epoch), census {:.0} ({:.1} an epoch), settle {:.0} ({:.1} an epoch), gather {:.0}",
            per(g.total()),
            self.timed,
            self.calls,
            per(g.restore),
            per(g.born),
            per(g.fly),
            per_epoch(g.fly),
            per(g.census),
            per_epoch(g.census),
            per(g.settle),
            per_epoch(g.settle),
            per(g.gather)
        );
        out
    }

    /// Adds a dispatch of `epochs` epochs and `particles` particles that took `timing`.
    pub(crate) fn add(&mut self, epochs: usize, particles: usize, timing: Timing) {
        self.calls += 1;
        self.epochs += epochs as u64;
        self.particles += particles as u64;
        self.upload += timing.upload;
        self.kernels += timing.kernels;
        self.cells += timing.cells;
        self.second_copies += u64::from(timing.second_copy);
        self.members += timing.members.0;
        self.whole += timing.members.1;
        if let Some(g) = &timing.gpu {
            self.gpu.sum(g);
            self.timed += 1;
            self.timed_epochs += epochs as u64;
        }
    }
}
