//! [`GpuFlight`]: the engine's flight stage on the GPU, for one simulation's calls at a time
//! (simulations that share it take turns). Each call is laid out (its particles, its scene's
//! words, the spans of its layers that changed since the GPU's copy was made) and run as a
//! dispatch of one member (see `dispatch.rs`); [`crate::GpuBatch`] runs many simulations' calls
//! in one.

use crate::GpuError;
use crate::batch::BatchMember;
use crate::births;
use crate::device::{Gpu, GpuOptions};
use crate::dispatch::{self, Buffers, Layers, MemberCall, Raw};
use crate::kernels::Kernels;
use crate::pack::{self, BYTES_PER_SLOT, GpuParticle, Place, WORKGROUP};
use crate::report::report;
use crate::scope;
use crate::timing::{Profile, Timing};
use rayon::prelude::*;
use spraysim_engine::deposit::DepositSurface;
use spraysim_engine::particles::Particle;
use spraysim_engine::pipeline::{FlightJob, FlightReport, FlightStage};
use std::sync::{Arc, Mutex, PoisonError, Weak};
use std::time::Instant;

/// The engine's flight stage on the GPU (see the crate's docs).
#[derive(Debug)]
pub struct GpuFlight {
    pub(crate) gpu: Gpu,
    pub(crate) kernels: Kernels,
    /// The most epochs a call takes (see [`GpuOptions::max_epochs_per_call`]).
    pub(crate) max_epochs: u64,
    state: Mutex<Single>,
    profile: Mutex<Profile>,
    /// The batch members made on this stage (see [`GpuFlight::member`]).
    members: Mutex<Vec<Weak<BatchMember>>>,
}

/// The storage of single calls, and what its copy of the layers holds.
#[derive(Debug, Default)]
struct Single {
    buffers: Buffers,
    /// Per target, the identity of the layer the GPU's copy holds and its first cell there
    /// (None: the copy holds nothing known).
    mirror: Option<Vec<(u64, u32)>>,
}

impl GpuFlight {
    /// Opens a device as `options` asks and builds the kernels.
    pub fn new(options: &GpuOptions) -> Result<GpuFlight, GpuError> {
        let gpu = Gpu::open(options)?;
        let kernels = Kernels::build(&gpu)?;
        let max_epochs = match options.max_epochs_per_call {
            0 => crate::device::EPOCHS_PER_CALL,
            n => n,
        };
        Ok(GpuFlight {
            gpu,
            kernels,
            max_epochs,
            state: Mutex::new(Single::default()),
            profile: Mutex::new(Profile::default()),
            members: Mutex::new(Vec::new()),
        })
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

    fn read_thickness(&self, found: bool) -> Result<Vec<f32>, GpuError> {
        let mut s = self.state.lock().map_err(|_| poisoned())?;
        s.buffers.read_thickness(&self.gpu, found)
    }

    /// Where the calls' time went since the last call of this, which starts the sums afresh.
    pub fn take_profile(&self) -> Profile {
        self.profile.lock().map(|mut p| std::mem::take(&mut *p)).unwrap_or_default()
    }

    /// Adds a dispatch to the profile.
    pub(crate) fn note(&self, epochs: usize, particles: usize, timing: Timing) {
        if let Ok(mut p) = self.profile.lock() {
            p.add(epochs, particles, timing);
        }
    }

    /// Keeps track of `members`, batch members made on this stage (forgetting those dropped).
    pub(crate) fn register(&self, members: &[Arc<BatchMember>]) {
        let mut held = self.members.lock().unwrap_or_else(PoisonError::into_inner);
        held.retain(|m| m.strong_count() > 0);
        held.extend(members.iter().map(Arc::downgrade));
    }

    /// The batch members made on this stage that are still held (by their simulations).
    pub(crate) fn live_members(&self) -> Vec<Arc<BatchMember>> {
        let held = self.members.lock().unwrap_or_else(PoisonError::into_inner);
        held.iter().filter_map(Weak::upgrade).collect()
    }

    /// The batch member made on this stage that `stage` is, if it is one.
    pub(crate) fn member(&self, stage: &Arc<dyn FlightStage>) -> Option<Arc<BatchMember>> {
        let at = Arc::as_ptr(stage).cast::<()>();
        let held = self.members.lock().unwrap_or_else(PoisonError::into_inner);
        held.iter().filter_map(Weak::upgrade).find(|m| Arc::as_ptr(m).cast::<()>() == at)
    }

    /// Particle slots one dispatch holds at most: one binding's worth, less the workgroup of
    /// padding a member's slots may take.
    pub(crate) fn slots_per_dispatch(&self) -> usize {
        let limit = self.gpu.binding_bytes();
        usize::try_from(limit / BYTES_PER_SLOT as u64)
            .unwrap_or(usize::MAX)
            .saturating_sub(WORKGROUP as usize)
    }

    /// Flies `job` as [`FlightStage::fly`] does, and hands back beside its report every
    /// particle of the job as the call left it, retired or not (the swarm's, then the
    /// newborns', in id order), to check the kernels against the engine's closed forms.
    pub fn fly_traced(&self, job: &FlightJob<'_>) -> Result<(FlightReport, Vec<Particle>), GpuError> {
        let (call, raw) = self.dispatch_one(job)?;
        Ok((self.report(job, &call, &raw), raw.slots.iter().map(GpuParticle::particle).collect()))
    }

    /// Runs `job` on the GPU, as a dispatch of one member.
    fn run(&self, job: &FlightJob<'_>) -> Result<FlightReport, GpuError> {
        let (call, raw) = self.dispatch_one(job)?;
        Ok(self.report(job, &call, &raw))
    }

    /// The report of `job`, laid out as `call`, from what its member read back (`raw`), its
    /// time added to the profile.
    pub(crate) fn report(&self, job: &FlightJob<'_>, call: &MemberCall, raw: &Raw) -> FlightReport {
        let reported = Instant::now();
        let out = report(job, &call.scene, raw);
        if let Ok(mut p) = self.profile.lock() {
            p.report += reported.elapsed().as_secs_f64();
        }
        out
    }

    /// Lays `job` out and dispatches it alone; returns its call and what it read back.
    fn dispatch_one(&self, job: &FlightJob<'_>) -> Result<(MemberCall, Raw), GpuError> {
        // Laid out before the lock is taken: the conversions run on rayon's workers, and a worker
        // that waits for them while holding the lock could take up another simulation's call,
        // which would wait for the lock on the same thread.
        let (mut call, layout) = lay_out(job)?;
        let mut s = self.state.lock().map_err(|_| poisoned())?;
        // Forgotten until the call succeeds: a call that fails, or is refused, loses the layers'
        // changes the engine handed it.
        let held = s.mirror.take().filter(|_| s.buffers.layer_cells == Some(call.scene.cells));
        call.layers = layers(job, &call.scene, held.as_deref(), &layout);
        let calls = std::slice::from_ref(&call);
        let (mut raw, timing) =
            dispatch::dispatch(&self.gpu, &self.kernels, &mut s.buffers, call.scene.cells, calls)?;
        s.mirror = Some(layout);
        drop(s);
        self.note(call.epochs.len(), call.particles(), timing);
        let raw = raw.pop().ok_or_else(|| GpuError::Readback("no member read back".into()))?;
        Ok((call, raw))
    }
}

fn poisoned() -> GpuError {
    GpuError::Device("a previous call failed".into())
}

/// `job` laid out as one member of a dispatch, its layers left for the caller to choose (empty
/// spans), and the identity of each of its targets' layers with its first cell.
pub(crate) fn lay_out(job: &FlightJob<'_>) -> Result<(MemberCall, Vec<(u64, u32)>), GpuError> {
    scope::check(job.config)?;
    let mut scene = pack::scene_words(job);
    let nozzle = u32::try_from(job.nozzle_quanta)
        .map_err(|_| GpuError::TooLarge("a nozzle particle's quanta".into()))?;
    let slots: Vec<GpuParticle> = job.particles.par_iter().map(|p| GpuParticle::of(p, job)).collect();
    // The births after the scene's own words; the newborns are sampled on the GPU.
    let born = births::words(job)?;
    scene.births = pack::BirthPlace {
        emitter: scene.words.len() as u32,
        batches: born.batches,
        swarm: slots.len() as u32,
        newborns: born.newborns,
    };
    scene.words.extend(born.words);
    let counters = pack::counters(
        &scene,
        job.targets.len(),
        dispatch::counter_words(job.targets.len(), job.config.obstacles.len()),
    );
    let words = pack::member_words(job, &scene, nozzle, Place::default());
    let layout = job
        .revised
        .iter()
        .zip(&scene.first_cells)
        .map(|(r, &first)| (r.as_ref().map_or(0, |r| r.0), first))
        .collect();
    let epochs = pack::epochs(job);
    let call =
        MemberCall { scene, slots, words, counters, layers: Layers::Spans(Vec::new()), cell: 0, epochs };
    Ok((call, layout))
}

/// How `job`'s layers (laid out as `scene`, their identities and first cells `layout`) reach a
/// GPU copy that holds the layers `held` (None: nothing known): only the spans that changed
/// since it was made, each from its first cell over the member's grids, where it holds these
/// very layers and the engine kept track of every change; else whole (zero on the GPU, and
/// each layer's span of non-zero cells written over it).
pub(crate) fn layers(
    job: &FlightJob<'_>,
    scene: &pack::SceneWords,
    held: Option<&[(u64, u32)]>,
    layout: &[(u64, u32)],
) -> Layers {
    if held != Some(layout) || job.revised.iter().any(Option::is_none) {
        return Layers::Whole(pack::nonzero_spans(job, &scene.first_cells));
    }
    let mut out = Vec::new();
    for ((target, revised), &first) in job.targets.iter().zip(job.revised).zip(&scene.first_cells) {
        let Some((_, changed)) = revised else { continue };
        let (Some(&lo), Some(&hi)) = (changed.first(), changed.last()) else { continue };
        let span = target.surface.thickness()[lo as usize..=hi as usize].iter().map(|&t| t as f32).collect();
        out.push((first + lo, span));
    }
    Layers::Spans(out)
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
        self.slots_per_dispatch()
    }

    fn profile(&self) -> Option<String> {
        Some(self.take_profile().describe())
    }
}
