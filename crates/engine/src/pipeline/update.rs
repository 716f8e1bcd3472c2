//! Update stage: advances every particle in flight by one step, in parallel. Each particle
//! moves, collides and resolves its impacts using only its own state, the read-only scene and
//! its own random stream; what it does to shared state (deposits, hit counts) is returned as
//! [`ImpactRecord`]s for the apply stage.

use super::watch::Watch;
use super::{CHUNK, Plan, State, Workers};
use crate::collision::{Aabb, Flight, Hit, SURFACE_OFFSET, Scene, SurfaceId, SurfaceKind};
use crate::config::SimulationConfig;
use crate::deposit::{Clearance, DepositSurface, LayerContact};
use crate::events::{ImpactEvent, sampled};
use crate::motion::lanes::{BLOCK, Drift, Limits, drift};
use crate::motion::{Integrator, Lanes, Motion};
use crate::particles::{MATERIAL_EVENT, StreamKey, Volumes, flags};
use crate::process::{ImpactModel, ImpactSite, Outcome};
use crate::tally::Amount;
use crate::world::{Role, Target};
use glam::DVec3;
use rand::Rng;
use rayon::prelude::*;

/// Advances every particle in flight by one step, in parallel over fixed chunks; returns what
/// each chunk produced, in chunk order.
pub(super) fn run(
    config: &SimulationConfig,
    plan: &Plan,
    state: &mut State,
    workers: &Workers,
    lazy: bool,
    lanes: Lanes,
    capture: Capture,
) -> Vec<ChunkOutcome> {
    let ctx = UpdateContext {
        config,
        scene: &state.scene,
        models: &plan.models,
        targets: &state.targets,
        motion: config.motion,
        domain: config.domain,
        dt: config.dt,
        key: plan.key,
        max_impacts: config.max_impacts_per_step,
        max_lifetime: config.material.max_lifetime,
        density: config.material.density,
        time: state.step as f64 * config.dt,
        capture,
        step: state.step,
        lazy,
        lanes,
    };
    let s = &mut state.swarm;
    state.particle_steps += (s.len() - state.retired) as u64;
    let chunks: Vec<SwarmChunk<'_>> = s
        .pos
        .chunks_mut(CHUNK)
        .zip(s.vel.chunks_mut(CHUNK))
        .zip(s.age.chunks_mut(CHUNK))
        .zip(s.id.chunks(CHUNK))
        .zip(s.impacts.chunks_mut(CHUNK))
        .zip(s.flags.chunks_mut(CHUNK))
        .zip(s.wake.chunks_mut(CHUNK))
        .map(|((((((pos, vel), age), id), impacts), flags), wake)| SwarmChunk {
            pos,
            vel,
            age,
            volumes: &s.volumes,
            id,
            impacts,
            flags,
            wake,
        })
        .collect();
    // One task per chunk: their costs differ widely (old rebounds near surfaces against young
    // particles in free flight), so idle threads must be able to take any of them.
    if workers.parallel() {
        workers.install(|| chunks.into_par_iter().with_max_len(1).map(|c| ctx.run_chunk(c)).collect())
    } else {
        chunks.into_iter().map(|c| ctx.run_chunk(c)).collect()
    }
}

/// The indices of the set bits of `mask`, ascending.
#[inline]
fn set_bits(mut mask: u64) -> impl Iterator<Item = usize> {
    std::iter::from_fn(move || {
        (mask != 0).then(|| {
            let j = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            j
        })
    })
}

/// Longest stretch of flight one prediction solves, s: its bounding box, and with it the
/// surfaces solved and the layer nodes watched, stays small.
const PREDICT_SPAN: f64 = 0.064;

/// Fewest steps that [`PREDICT_SPAN`] must hold for predictions to be made: one costs about
/// what several steps near surfaces do, so with longer steps they are stepped.
const PREDICT_MIN_STEPS: f64 = 8.0;

/// Stretches of a predicted flight whose boxes select the surfaces it is solved against.
const PIECES: usize = 4;

/// Least clearance a sleeping flight keeps above the bound of the layer under it, m: far above
/// the rounding of positions recomputed in closed form.
const LAYER_MARGIN: f64 = 1e-9;

/// Safety margin of a predicted event time, s (relative for long flights).
const EVENT_MARGIN: f64 = 1e-9;

/// Bits of [`ImpactRecord::flags`].
pub(crate) mod record {
    /// The particle stuck.
    pub const STUCK: u8 = 1;
    /// The particle's first impact on the front of a substrate target.
    pub const FIRST_SUBSTRATE: u8 = 2;
    /// The impact was on the back of a target.
    pub const BACK: u8 = 4;
    /// The particle is released material (see [`crate::particles::flags::RELEASED`]).
    pub const RELEASED: u8 = 8;
    /// The particle came to rest loose (a slow rebound), not adhering: with `STUCK`.
    pub const LOOSE: u8 = 16;
    /// The particle had rebounded before this impact.
    pub const REBOUND: u8 = 32;
}

/// One impact, to be applied to shared state in particle order.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ImpactRecord {
    pub surface: SurfaceId,
    pub cell: u32,
    pub volume: f32,
    /// Volume of coating the impact would remove, m³.
    pub eroded_coat: f32,
    /// Volume of substrate the impact would remove, m³.
    pub eroded_sub: f32,
    pub flags: u8,
}

/// What one chunk of particles produced in a step.
#[derive(Debug, Default)]
pub(crate) struct ChunkOutcome {
    pub impacts: Vec<ImpactRecord>,
    pub left_domain: Amount,
    pub expired: Amount,
    /// Released material that left the domain.
    pub released_left: Amount,
    /// Released material that expired.
    pub released_expired: Amount,
    pub retired: usize,
    /// Particles updated (not asleep).
    pub updated: u64,
    /// Impacts captured for event handlers, in particle order.
    pub events: Vec<ImpactEvent>,
    /// Layer nodes the particles put to sleep watch, in particle order.
    pub watch: Vec<Watch>,
}

/// Which impacts the update stage gathers as events.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Capture {
    /// No impact (no handler wants them).
    Nothing,
    /// Those the impact log samples.
    Sampled {
        /// Share of the impacts kept, 0..1.
        fraction: f64,
        /// Salt of the sampling hash (the run's seed), as [`crate::events::ImpactLog::salt`].
        salt: u64,
    },
    /// Every impact.
    All,
}

impl Capture {
    #[inline]
    fn wants(self, id: u32, impact: u16) -> bool {
        match self {
            Capture::Nothing => false,
            Capture::Sampled { fraction, salt } => sampled(salt, id, impact, fraction),
            Capture::All => true,
        }
    }
}

/// Read-only inputs of the update stage.
pub(crate) struct UpdateContext<'a> {
    pub config: &'a SimulationConfig,
    pub scene: &'a Scene,
    pub models: &'a [ImpactModel],
    pub targets: &'a [Target],
    pub motion: Motion,
    pub domain: Aabb,
    pub dt: f64,
    pub key: StreamKey,
    pub max_impacts: u32,
    pub max_lifetime: f64,
    pub density: f64,
    /// Time at the start of the step, s.
    pub time: f64,
    /// Which impacts to gather as events.
    pub capture: Capture,
    /// This step's index.
    pub step: u64,
    /// Particles in free flight skip steps (exact integrator only).
    pub lazy: bool,
    /// Instruction set of the free-flight kernel.
    pub lanes: Lanes,
}

/// Mutable views of one chunk of the swarm's arrays.
pub(crate) struct SwarmChunk<'a> {
    pub pos: &'a mut [DVec3],
    pub vel: &'a mut [DVec3],
    pub age: &'a mut [f32],
    pub volumes: &'a Volumes,
    pub id: &'a [u32],
    pub impacts: &'a mut [u16],
    pub flags: &'a mut [u8],
    pub wake: &'a mut [u32],
}

impl UpdateContext<'_> {
    /// Advances every live particle of `chunk` by one step: the free-flight kernel steps a
    /// block of slots in f64 lanes, then a scalar pass keeps its answer for each particle whose
    /// step is clear in the broad phase and works out the others in full.
    pub fn run_chunk(&self, mut chunk: SwarmChunk<'_>) -> ChunkOutcome {
        let mut out = ChunkOutcome::default();
        let mut next = Drift::default();
        let limits = Limits { domain: self.domain, max_age: self.max_lifetime };
        for start in (0..chunk.pos.len()).step_by(BLOCK) {
            let end = (start + BLOCK).min(chunk.pos.len());
            // The awake slots as bits, tested without a branch (so that the test runs over the
            // block in lanes) and visited in order without a branch per slot (which sleepers
            // scattered through the block would mispredict).
            const { assert!(BLOCK <= 64) };
            let (alive, wake) = (&chunk.flags[start..end], &chunk.wake[start..end]);
            let mask = alive.iter().zip(wake).enumerate().fold(0u64, |m, (j, (&a, &w))| {
                m | (u64::from((a & flags::ALIVE != 0) & (u64::from(w) <= self.step)) << j)
            });
            let awake = mask.count_ones() as usize;
            // Event-driven flight leaves most slots asleep: a sparse block is stepped slot by
            // slot (with identical results), a dense one in lanes.
            if awake * 4 >= end - start {
                let slots = (&chunk.pos[start..end], &chunk.vel[start..end], &chunk.age[start..end]);
                drift(self.lanes, &self.motion, self.dt, &limits, slots, &mut next);
            } else if awake > 0 {
                for j in set_bits(mask) {
                    let i = start + j;
                    next.step_one(
                        j,
                        &self.motion,
                        self.dt,
                        &limits,
                        (chunk.pos[i], chunk.vel[i], chunk.age[i]),
                    );
                }
            } else {
                continue;
            }
            for j in set_bits(mask) {
                let i = start + j;
                out.updated += 1;
                let age = f64::from(chunk.age[i]) + self.dt;
                chunk.age[i] = next.age[j];
                // Free flight, the common case: nothing to hit, nothing to retire.
                if next.stays[j] && self.is_clear(chunk.pos[i], chunk.vel[i], next.pos[j]) {
                    chunk.pos[i] = next.pos[j];
                    chunk.vel[i] = next.vel[j];
                } else {
                    self.advance_slow(&mut chunk, i, age, &mut out);
                }
                if self.lazy && chunk.flags[i] & flags::ALIVE != 0 {
                    self.doze(&mut chunk, i, &mut out.watch);
                }
            }
        }
        out
    }

    /// Lets particle `i` skip the coming steps in which its flight certainly meets nothing,
    /// inside the domain and within its lifetime: it moves to the start of the step of its
    /// next event (an impact, or a stretch that may touch a layer), in closed form, and sleeps
    /// until then. In open space the broad phase's distance map says how long it may sleep;
    /// near surfaces its flight is solved against them (see [`UpdateContext::predict`]), and
    /// it watches the layers it passes over (see `watch.rs`). What a step would find is found
    /// at the step where it happens, so a particle costs work per event, not per step.
    #[inline]
    fn doze(&self, chunk: &mut SwarmChunk<'_>, i: usize, watch: &mut Vec<Watch>) {
        let (x, v, age) = (chunk.pos[i], chunk.vel[i], f64::from(chunk.age[i]));
        let g = self.motion.gravity;
        let flight = Flight { x0: x, v0: v, g, duration: 0.0 };
        // Every skipped step must keep the particle young enough, clear of every surface and
        // inside the domain.
        let horizon = (self.max_lifetime - age).min(flight.exit_time(&self.domain));
        let mut open = self.scene.free_flight(x, v, g, horizon);
        let first = watch.len();
        if open < 2.0 * self.dt && PREDICT_SPAN >= PREDICT_MIN_STEPS * self.dt {
            open = self.predict(x, v, horizon, chunk.id[i], watch);
        }
        let steps = (open.min(horizon) / self.dt).floor();
        if steps < 2.0 {
            watch.truncate(first);
            return;
        }
        let tau = steps * self.dt;
        chunk.pos[i] = flight.at(tau);
        chunk.vel[i] = flight.velocity(tau);
        chunk.age[i] = (age + tau) as f32;
        chunk.wake[i] = u32::try_from(self.step + 1 + steps as u64).unwrap_or(u32::MAX);
        for w in &mut watch[first..] {
            w.wake = chunk.wake[i];
        }
    }

    /// How long (s, at most `horizon`) the flight of particle `id` from `x` with velocity `v`
    /// certainly meets nothing: the exact time of its first hit on a bare surface, over a
    /// stretch of at most [`PREDICT_SPAN`] that halves until its bounding box clears every
    /// deposited layer as it stands; 0 if none does. The layers' nodes under the box are
    /// pushed to `watch`, to wake the particle if a layer grows into it.
    #[inline(never)]
    fn predict(&self, x: DVec3, v: DVec3, horizon: f64, id: u32, watch: &mut Vec<Watch>) -> f64 {
        let g = self.motion.gravity;
        let (shortest, first) = (2.0 * self.dt, watch.len());
        let arc = |duration: f64| Flight { x0: x, v0: v, g, duration };
        // Most flights that cannot sleep start against a layer: the shortest stretch first.
        let mut span = horizon.min(PREDICT_SPAN);
        if span < shortest || !self.clears_layers(&arc(shortest).aabb(), id, watch) {
            return 0.0;
        }
        watch.truncate(first);
        while span >= shortest {
            let flight = arc(span);
            if self.clears_layers(&flight.aabb(), id, watch) {
                let pieces = flight.piece_boxes::<PIECES>();
                let t = self.scene.first_hit_within(&flight, &pieces).map_or(span, |(_, h)| h.t * span);
                // The step that holds the event is stepped in full: a margin far above the
                // rounding of closed-form positions keeps the event inside it.
                return (t - EVENT_MARGIN * (1.0 + t)).max(0.0);
            }
            watch.truncate(first);
            span *= 0.5;
        }
        0.0
    }

    /// True if the box `b` clears every target's layer by [`LAYER_MARGIN`]; pushes to `watch`
    /// the nodes under it, with its least height, where the layer might grow into it.
    fn clears_layers(&self, b: &Aabb, id: u32, watch: &mut Vec<Watch>) -> bool {
        for (t, target) in self.targets.iter().enumerate() {
            let allowance = self.scene.surface(target.surface_id).layer;
            match target.surface.layer_clearance(b, allowance) {
                Clearance::Free => {}
                // Above the layer's allowance in the broad phase, the box needs no watch: a
                // layer that outgrows its allowance wakes every sleeper whose flight comes near
                // the grown zone.
                Clearance::Above { height, top } => {
                    if height - top <= LAYER_MARGIN {
                        return false;
                    }
                }
                // A surface that cannot bound its layer is cleared only by its whole box, layer
                // allowance included (a few pieces at most: a mesh's are too many to test).
                Clearance::Unknown => {
                    let far = target.pieces <= 4
                        && (0..target.pieces)
                            .all(|k| !self.scene.reaches(SurfaceId(target.surface_id.0 + k), b));
                    if !far {
                        return false;
                    }
                }
                Clearance::Over { nodes, height, top } => {
                    if height - top <= LAYER_MARGIN {
                        return false;
                    }
                    // As `Above` (a surface may not tell the two apart).
                    if height > allowance {
                        continue;
                    }
                    // Rounded down, so that the watch wakes the flight no later than needed.
                    let low = height as f32;
                    let low = if f64::from(low) > height { low.next_down() } else { low };
                    watch.push(Watch { id, wake: 0, target: t as u32, nodes, height: low });
                }
            }
        }
        true
    }

    /// The full step of particle `i`: impacts, then retirement checks.
    #[inline(never)]
    #[cold]
    fn advance_slow(&self, chunk: &mut SwarmChunk<'_>, i: usize, age: f64, out: &mut ChunkOutcome) {
        let mut p = Particle {
            pos: chunk.pos[i],
            vel: chunk.vel[i],
            volume: chunk.volumes.of(chunk.id[i], chunk.flags[i]),
            id: chunk.id[i],
            impacts: chunk.impacts[i],
            flags: chunk.flags[i],
        };
        let stuck = self.advance(&mut p, out);
        let volume = f64::from(p.volume);
        let released = p.flags & flags::RELEASED != 0;
        if !stuck {
            if !self.domain.contains(p.pos) {
                p.flags &= !flags::ALIVE;
                if released { &mut out.released_left } else { &mut out.left_domain }.add(volume);
            } else if age > self.max_lifetime || p.impacts == u16::MAX {
                p.flags &= !flags::ALIVE;
                if released { &mut out.released_expired } else { &mut out.expired }.add(volume);
            }
        }
        if p.flags & flags::ALIVE == 0 {
            out.retired += 1;
        }
        chunk.pos[i] = p.pos;
        chunk.vel[i] = p.vel;
        chunk.impacts[i] = p.impacts;
        chunk.flags[i] = p.flags;
    }

    /// True if the flight from `x` with velocity `v` to `x1` over one step certainly hits nothing.
    #[inline]
    fn is_clear(&self, x: DVec3, v: DVec3, x1: DVec3) -> bool {
        match self.motion.integrator {
            Integrator::Exact => {
                self.scene.arc_is_clear(&Flight { x0: x, v0: v, g: self.motion.gravity, duration: self.dt })
            }
            Integrator::Euler | Integrator::SemiImplicitEuler => self.scene.is_clear(x, x1),
        }
    }

    /// Flies from `x` with velocity `v` for `dt`: the end position and velocity, and the first
    /// hit on the way. A deposited layer is struck on its top, found along the straight chord
    /// of the step (for the exact integrator, the arc's chord, which it leaves by at most
    /// g Δt²/8).
    fn fly(&self, x: DVec3, v: DVec3, dt: f64) -> (DVec3, DVec3, Option<Strike>) {
        let (x1, v1) = self.motion.advance(x, v, dt);
        let mut hit = self.fly_bare(x, v, x1, v1, dt).map(|(surface, hit, velocity)| Strike {
            surface,
            hit,
            velocity,
            cell: None,
        });
        for target in self.targets {
            if let Some(LayerContact { s, point, normal, cell }) = target.surface.layer_contact(x, x1)
                && hit.is_none_or(|h| s < h.hit.t)
            {
                let v_in = match self.motion.integrator {
                    Integrator::Exact => v + self.motion.gravity * (s * dt),
                    Integrator::Euler | Integrator::SemiImplicitEuler => v.lerp(v1, s),
                };
                // Entering a taller cell from the side meets the side of that step, not the
                // smoothed slope: its normal opposes the motion along the face.
                let normal = if v_in.dot(normal) < 0.0 {
                    normal
                } else {
                    let n = target.surface.normal(cell);
                    (-(v_in - n * v_in.dot(n))).try_normalize().unwrap_or(n)
                };
                hit = Some(Strike {
                    surface: SurfaceId(target.surface_id.0 + target.surface.piece_of(cell)),
                    hit: Hit { t: s, point, normal },
                    velocity: v_in,
                    cell: Some(cell),
                });
            }
        }
        (x1, v1, hit)
    }

    /// The first hit on the bare surfaces.
    fn fly_bare(&self, x: DVec3, v: DVec3, x1: DVec3, v1: DVec3, dt: f64) -> Option<(SurfaceId, Hit, DVec3)> {
        match self.motion.integrator {
            Integrator::Exact => {
                let arc = Flight { x0: x, v0: v, g: self.motion.gravity, duration: dt };
                self.scene.first_hit_arc(&arc).map(|(s, h)| (s, h, arc.velocity(h.t * dt)))
            }
            Integrator::Euler | Integrator::SemiImplicitEuler => self.scene.first_hit(x, x1).map(|(s, h)| {
                // Velocity at the hit, consistent with the straight segment that found it.
                let mut v_in = v.lerp(v1, h.t);
                if v_in.dot(h.normal) >= 0.0 {
                    v_in = (x1 - x).normalize_or_zero() * v_in.length();
                }
                (s, h, v_in)
            }),
        }
    }

    /// The record of an impact of `p` on surface `s`, struck at `hit` with velocity `v_in`;
    /// `front` is the target, its index and the cell, for a hit on a target's receiving side.
    /// Marks `p` as having hit a substrate.
    fn record(
        &self,
        p: &mut Particle,
        s: SurfaceId,
        front: Option<(&Target, usize, u32)>,
        hit: &Hit,
        v_in: DVec3,
    ) -> ImpactRecord {
        let mut rec = ImpactRecord {
            surface: s,
            cell: u32::MAX,
            volume: p.volume,
            eroded_coat: 0.0,
            eroded_sub: 0.0,
            flags: 0,
        };
        if p.flags & flags::RELEASED != 0 {
            rec.flags |= record::RELEASED;
        }
        match (self.scene.surface(s).kind, front) {
            (SurfaceKind::Target(_), Some((target, t, cell))) => {
                rec.cell = cell;
                if let Some(erosion) = &self.config.targets[t].erosion {
                    let speed = v_in.length();
                    // γ: the impact angle from the surface.
                    let gamma = (-v_in.dot(hit.normal) / speed.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0).asin();
                    let mass = f64::from(p.volume) * self.density;
                    rec.eroded_coat = erosion.coating_law.removed_volume(mass, speed, gamma) as f32;
                    rec.eroded_sub = erosion.substrate_law.removed_volume(mass, speed, gamma) as f32;
                }
                if target.role == Role::Substrate && p.flags & flags::HIT_SUBSTRATE == 0 {
                    p.flags |= flags::HIT_SUBSTRATE;
                    rec.flags |= record::FIRST_SUBSTRATE;
                }
            }
            (SurfaceKind::Target(_), None) => rec.flags |= record::BACK,
            (SurfaceKind::Obstacle(_), _) => {}
        }
        rec
    }

    /// Volume an impact erodes, m³: from the coating where the cell had some at the start of
    /// the step, else from the substrate (for event handlers; the apply stage wears the maps
    /// exactly, impact by impact).
    fn eroded(&self, rec: &ImpactRecord) -> f32 {
        let coated = match self.scene.surface(rec.surface).kind {
            SurfaceKind::Target(t) => self.targets[t]
                .erosion
                .as_ref()
                .is_some_and(|e| e.coating.get(rec.cell as usize).is_some_and(|&c| c > 0.0)),
            SurfaceKind::Obstacle(_) => false,
        };
        if coated { rec.eroded_coat } else { rec.eroded_sub }
    }

    /// The impact of `p` at `hit` with velocity `v_in` as the impact laws see it: on a target's
    /// front, over the layer averaged over the model's cushion radius, at an angle of incidence
    /// taken on the bare surface.
    fn site(
        &self,
        p: &Particle,
        model: &ImpactModel,
        front: Option<(&Target, usize, u32)>,
        hit: &Hit,
        v_in: DVec3,
    ) -> ImpactSite {
        let layer = front.map(|(target, _, cell)| target.surface.mean_thickness(cell, model.cushion_radius));
        let material = self.key.stream(p.id, MATERIAL_EVENT).random::<f64>();
        let site = ImpactModel::site(v_in, hit.normal, layer, material, p.flags & flags::BOUNCED != 0);
        match front {
            Some((target, _, cell)) => site.incidence_on(target.surface.normal(cell)),
            None => site,
        }
    }

    /// Moves one particle through one step, resolving up to `max_impacts` impacts. Returns true
    /// if it stuck (and clears its `ALIVE` bit).
    fn advance(&self, p: &mut Particle, out: &mut ChunkOutcome) -> bool {
        let mut x = p.pos;
        let mut v = p.vel;
        let mut remaining = self.dt;
        for _ in 0..self.max_impacts {
            let (x_end, v_end, hit) = self.fly(x, v, remaining);
            let Some(Strike { surface: s, hit, velocity: v_in, cell }) = hit else {
                p.pos = x_end;
                p.vel = v_end;
                return false;
            };
            p.impacts = p.impacts.saturating_add(1);
            let mut rng = self.key.stream(p.id, u32::from(p.impacts));
            let surface = self.scene.surface(s);
            // An impact on the front of a target: the target, its index and the cell struck. A
            // contact with the layer is on the front by construction, whatever its normal (a
            // particle entering a taller column through its side meets a normal in the face's
            // plane); a hit on the bare surface is on the front if it comes from that side.
            let piece = surface.piece;
            let front = match surface.kind {
                SurfaceKind::Target(t)
                    if cell.is_some() || self.targets[t].surface.receives(piece, hit.point, hit.normal) =>
                {
                    let target = &self.targets[t];
                    let cell = cell.unwrap_or_else(|| target.surface.cell_at(piece, hit.point));
                    Some((target, t, cell))
                }
                _ => None,
            };
            let model = &self.models[surface.impact];
            let bounced = p.flags & flags::BOUNCED != 0;
            let outcome = model.resolve(&self.site(p, model, front, &hit, v_in), &mut rng);
            let mut rec = self.record(p, s, front, &hit, v_in);
            if bounced {
                rec.flags |= record::REBOUND;
            }
            if self.capture.wants(p.id, p.impacts) {
                out.events.push(ImpactEvent {
                    time: self.time + (self.dt - remaining) + hit.t * remaining,
                    position: hit.point,
                    normal: hit.normal,
                    velocity: v_in,
                    surface: s,
                    stuck: matches!(outcome, Outcome::Stick | Outcome::Rest),
                    eroded: self.eroded(&rec),
                    particle: p.id,
                    impact: p.impacts,
                });
            }
            match outcome {
                Outcome::Stick | Outcome::Rest => {
                    rec.flags |= record::STUCK;
                    if outcome == Outcome::Rest {
                        rec.flags |= record::LOOSE;
                    }
                    out.impacts.push(rec);
                    p.pos = hit.point;
                    p.vel = DVec3::ZERO;
                    p.flags &= !flags::ALIVE;
                    return true;
                }
                Outcome::Rebound(v_out) => {
                    p.flags |= flags::BOUNCED;
                    out.impacts.push(rec);
                    x = hit.point + hit.normal * SURFACE_OFFSET;
                    v = v_out;
                    remaining *= 1.0 - hit.t;
                }
            }
        }
        // Out of impacts for this step: wait at the last impact point.
        p.pos = x;
        p.vel = v;
        false
    }
}

/// The first hit of a flight.
#[derive(Clone, Copy)]
struct Strike {
    /// The surface struck.
    surface: SurfaceId,
    hit: Hit,
    /// Velocity at impact, m/s.
    velocity: DVec3,
    /// For a hit on a deposited layer, the cell the material settles in.
    cell: Option<u32>,
}

/// Working copy of one particle's state.
struct Particle {
    pos: DVec3,
    vel: DVec3,
    volume: f32,
    id: u32,
    impacts: u16,
    flags: u8,
}
