//! The flight of one particle through steps of a layer epoch.
//!
//! Within an epoch the layers stand still, so a particle needs nothing but its own state, the
//! read-only scene and its own random streams: [`Kernel::fly`] takes it through every step it
//! has left in the epoch in one call. Each step is one of two kinds:
//!
//! - **coasting**: the box that bounds its flight over the next steps stays inside the domain,
//!   touches no surface and clears every layer (with a margin), and it stays young enough, so
//!   those steps only move it: in closed form from its anchor (exact integrator), or by the
//!   integrator's own update per step (Euler);
//! - **a full step**: the exact search for the step's first hit on the bare surfaces and on the
//!   layers, the impact laws, and the checks for leaving the domain or expiring.
//!
//! A coasting step and a full step that finds nothing leave the particle in the same state, so
//! how many steps a call covers, and how they are split into coasts, never changes a result:
//! a run stepped one step at a time equals one advanced an epoch at a time, to the bit.
//!
//! What a particle does to shared state is gathered in [`Books`]: the run's totals and each
//! target's and obstacle's, in exact integer quanta, and the cells it touched, whose deposits
//! and wear go to the targets' atomic [`crate::deposit::Pending`] counters. Integer sums do not
//! depend on their order, so the results do not depend on the threads.

use crate::collision::{Aabb, Flight, Hit, SURFACE_OFFSET, Scene, SurfaceId, SurfaceKind};
use crate::config::SimulationConfig;
use crate::deposit::{Clearance, DepositSurface, LayerContact, share};
use crate::emission::DropletSizes;
use crate::events::{ImpactEvent, sampled};
use crate::motion::{AirFlow, Droplet, Integrator, JetFrame, Motion};
use crate::particles::{MATERIAL_EVENT, MAX_IMPACTS, Particle, StreamKey, Volumes, flags};
use crate::process::{ImpactModel, ImpactSite, Outcome};
use crate::tally::Tally;
use crate::world::{Impact, ObstacleTally, Role, Target, TargetTally};
use glam::DVec3;
use rand::Rng;

/// Least clearance a coasting flight keeps above the bound of the layer under it, m: far above
/// the rounding of positions computed in closed form.
const LAYER_MARGIN: f64 = 1e-9;

/// Margin by which the box of a coasting flight is grown, m, besides the integrator's own
/// allowance: keeps the proof conservative against rounding.
const BOX_MARGIN: f64 = 1e-9;

/// An exact-integrator particle re-anchors once this many steps have passed since its anchor,
/// so that its step count never overflows.
const MAX_SINCE: u16 = 60_000;

/// Which impacts a flight gathers as events.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Capture {
    /// No impact is gathered.
    Nothing,
    /// Those the impact log samples.
    Sampled {
        /// Share of impacts kept, in [0, 1].
        fraction: f64,
        /// Salt of the hash.
        salt: u64,
    },
    /// Every impact is gathered.
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

/// What the particles one worker flies leave behind, in exact integer quanta (see
/// [`crate::tally::Tallied`]): merged with the other workers' in any order, with the same sums.
#[derive(Debug, Default)]
pub(crate) struct Books {
    /// Fates and first substrate impacts.
    pub tally: Tally,
    /// What struck each target.
    pub targets: Vec<TargetTally>,
    /// What struck each obstacle.
    pub obstacles: Vec<ObstacleTally>,
    /// Per target, the cells this worker listed first in the epoch (see
    /// [`crate::deposit::Pending`]).
    pub touched: Vec<Vec<u32>>,
    /// Impacts gathered as events, with the step they happened in.
    pub events: Vec<(u64, ImpactEvent)>,
    /// Particle-steps flown.
    pub steps: u64,
    /// Of those, full steps (the work done).
    pub updates: u64,
}

impl Books {
    /// Empty books for `targets` targets and `obstacles` obstacles.
    pub fn new(targets: usize, obstacles: usize) -> Books {
        Books {
            targets: vec![TargetTally::default(); targets],
            obstacles: vec![ObstacleTally::default(); obstacles],
            touched: vec![Vec::new(); targets],
            ..Books::default()
        }
    }

    /// These books with `o`'s added.
    pub fn merge(mut self, mut o: Books) -> Books {
        self.tally.merge(&o.tally);
        self.targets.iter_mut().zip(&o.targets).for_each(|(a, b)| *a += *b);
        self.obstacles.iter_mut().zip(&o.obstacles).for_each(|(a, b)| *a += *b);
        self.touched.iter_mut().zip(&mut o.touched).for_each(|(a, b)| a.append(b));
        self.events.append(&mut o.events);
        self.steps += o.steps;
        self.updates += o.updates;
        self
    }
}

/// The gun's air over the steps of one call (see [`crate::motion::air`]).
pub(crate) struct Air<'a> {
    /// The jet's and the air's parameters.
    pub flow: AirFlow,
    /// The emitter's droplet sizes, found again by particle id.
    pub sizes: &'a DropletSizes,
    /// The jet in each step from `first` (`None`: the nozzle is not spraying; the air is still).
    pub frames: &'a [Option<JetFrame>],
    /// The step of `frames[0]`.
    pub first: u64,
    /// A bound of the air's speed anywhere in these steps, m/s.
    pub max_speed: f64,
}

/// Read-only inputs of a flight.
pub(crate) struct Kernel<'a> {
    pub config: &'a SimulationConfig,
    pub scene: &'a Scene,
    pub models: &'a [ImpactModel],
    pub targets: &'a [Target],
    pub volumes: &'a Volumes,
    pub motion: Motion,
    pub domain: Aabb,
    pub dt: f64,
    pub key: StreamKey,
    pub max_impacts: u32,
    /// A particle whose age at a step's end exceeds this many steps expires.
    pub lifetime_steps: f64,
    /// |g|, m/s².
    pub g_len: f64,
    pub density: f64,
    /// Which impacts to gather as events.
    pub capture: Capture,
    /// Whether particles coast through the steps their flight clears (see
    /// `Simulation::set_coasting`).
    pub coasting: bool,
    /// The gun's air, if the droplets feel it.
    pub air: Option<Air<'a>>,
}

/// A particle's state at the start of a step, in double precision.
#[derive(Clone, Copy)]
struct Now {
    x: DVec3,
    v: DVec3,
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

impl Kernel<'_> {
    /// Flies `p` through steps `from..to` (or until it stops being in flight), booking what it
    /// does in `books`. It first tries to coast all the steps left in one proof (again after
    /// each impact, which may have sent it into open space); failing that, it coasts the steps
    /// the broad phase clears one at a time, and takes the others in full.
    pub fn fly(&self, p: &mut Particle, from: u64, to: u64, books: &mut Books) {
        let drop = self.droplet(p);
        let drop = drop.as_ref();
        let mut s = from;
        let mut long = true;
        while s < to && p.is_alive() {
            let young = if self.coasting { self.steps_young(p, s) } else { 0 };
            if long {
                long = false;
                let k = (to - s).min(young);
                if k > 0 && self.coasts(p, k, s, drop) {
                    let done = self.coast(p, k, s, drop, books);
                    books.steps += done;
                    s += done;
                    continue;
                }
            }
            if young > 0 && self.step_is_clear(p, s, drop) {
                let done = self.coast(p, 1, s, drop, books);
                books.steps += done;
                s += done;
                continue;
            }
            let impacts = p.impacts();
            self.full_step(p, s, drop, books);
            books.steps += 1;
            books.updates += 1;
            s += 1;
            long = p.impacts() != impacts;
        }
    }

    /// Steps `p` may still coast from step `s` before the step in which it may expire (which is
    /// a full step); 0 once it has made its most impacts.
    #[inline]
    fn steps_young(&self, p: &Particle, s: u64) -> u64 {
        let age = (s - u64::from(p.born)) as f64;
        let young = (self.lifetime_steps - age).floor() - 1.0;
        if young < 1.0 || p.impacts() >= MAX_IMPACTS {
            return 0;
        }
        let young = young as u64;
        if self.motion.integrator == Integrator::Exact {
            young.min(u64::from(MAX_SINCE - p.since.min(MAX_SINCE)))
        } else {
            young
        }
    }

    /// True if `p`'s flight over its next `k` steps certainly stays inside the domain and meets
    /// nothing (see [`Kernel::box_clear`]).
    #[inline]
    fn coasts(&self, p: &Particle, k: u64, s: u64, drop: Option<&Droplet>) -> bool {
        let now = self.now(p);
        let air = drop.and_then(|_| self.air_bound(now, s, k));
        let b = self.flight_box(now, k, air);
        self.domain.contains(b.min) && self.domain.contains(b.max) && self.box_clear(&b)
    }

    /// True if `p`'s next step certainly stays inside the domain and meets nothing, by the broad
    /// phase's cells alone (whose marks cover the space the layers may take): the cheap test
    /// of a particle near surfaces.
    #[inline]
    fn step_is_clear(&self, p: &Particle, s: u64, drop: Option<&Droplet>) -> bool {
        let now = self.now(p);
        let air = drop.and_then(|_| self.air_bound(now, s, 1));
        let b = self.flight_box(now, 1, air);
        self.domain.contains(b.min) && self.domain.contains(b.max) && self.scene.box_is_clear(&b)
    }

    /// A bound of the air's speed (m/s) anywhere a droplet at `now` can reach in the `k` steps
    /// from step `s`: a speed U such that the jet of each of those steps is no faster than U
    /// within the distance a flight no faster than U (and gravity) covers. Found by raising U
    /// from the droplet's own speed, at most three times, else the bound over the whole jet.
    #[inline]
    fn air_bound(&self, now: Now, s: u64, k: u64) -> Option<f64> {
        let air = self.air.as_ref()?;
        let t = k as f64 * self.dt;
        let mut speed = now.v.abs().max_element() * 1.733;
        for _ in 0..3 {
            let reach =
                (speed + self.g_len * t) * t * (1.0 + k as f64 * f64::from(f32::EPSILON)) + BOX_MARGIN;
            let fastest = (s..s + k)
                .filter_map(|step| self.jet(step))
                .map(|frame| air.flow.speed_bound(frame, now.x, reach))
                .fold(0.0, f64::max);
            if fastest <= speed {
                return Some(speed);
            }
            speed = fastest;
        }
        Some(air.max_speed)
    }

    /// Position and velocity of `p` at the start of its next step.
    #[inline]
    fn now(&self, p: &Particle) -> Now {
        let (x, v) = match self.motion.integrator {
            Integrator::Exact => p.now(self.dt, self.motion.gravity),
            Integrator::Euler | Integrator::SemiImplicitEuler => (p.anchor, p.anchor_velocity()),
        };
        Now { x, v }
    }

    /// A box that holds every point of the flight from `now` over `k` steps; `air` bounds
    /// the speed of the air the particle flies through, m/s, if it feels any.
    #[inline]
    fn flight_box(&self, now: Now, k: u64, air: Option<f64>) -> Aabb {
        let t = k as f64 * self.dt;
        let g = self.motion.gravity;
        // A bound of the speed over the flight (the largest component times √3 bounds the
        // length), with no square root.
        let speed = now.v.abs().max_element() * 1.733 + self.g_len * t;
        if let Some(air) = air {
            // Each step moves the velocity towards the air's by a convex combination and adds
            // at most g Δt: no point lies farther than the larger speed and gravity allow; the
            // f32 rounding of each step's velocity adds as for Euler.
            let speed = speed.max(air + self.g_len * t);
            let reach = t * speed * (1.0 + k as f64 * f64::from(f32::EPSILON)) + BOX_MARGIN;
            return Aabb { min: now.x - reach, max: now.x + reach };
        }
        if self.motion.drag > 0.0 {
            // Drag only slows: no point lies farther than the speed now and gravity allow.
            let reach = t * speed + BOX_MARGIN;
            return Aabb { min: now.x - reach, max: now.x + reach };
        }
        let end = now.x + now.v * t + 0.5 * g * t * t;
        let mut b = Aabb::from_points(now.x, end);
        for a in 0..3 {
            if g[a] != 0.0 {
                let apex = -now.v[a] / g[a];
                if apex > 0.0 && apex < t {
                    let p = now.x[a] + now.v[a] * apex + 0.5 * g[a] * apex * apex;
                    b.min[a] = b.min[a].min(p);
                    b.max[a] = b.max[a].max(p);
                }
            }
        }
        let margin = match self.motion.integrator {
            Integrator::Exact => BOX_MARGIN,
            // The Euler points lie within |g| k Δt² / 2 of the parabola's, and a velocity
            // rounded to f32 at each step moves them by at most 2⁻²⁴ |v| Δt per step further
            // per step flown.
            Integrator::Euler | Integrator::SemiImplicitEuler => {
                self.g_len * t * self.dt + k as f64 * t * speed * f64::from(f32::EPSILON) + BOX_MARGIN
            }
        };
        b.inflate(margin)
    }

    /// True if nothing in the scene can be met inside `b`: the broad phase (whose cells also
    /// mark the space each layer may take) finds nothing near it; or every target's layer
    /// under it stays lower than its lowest point by [`LAYER_MARGIN`] (a target that cannot
    /// bound its layer, by the boxes of its few pieces), and it reaches no obstacle.
    fn box_clear(&self, b: &Aabb) -> bool {
        if !self.scene.unbounded_clear(b) {
            return false;
        }
        if self.scene.box_is_empty(b) || self.scene.box_is_clear(b) {
            return true;
        }
        for target in self.targets {
            let allowance = self.scene.surface(target.surface_id).layer;
            let clear = match target.surface.layer_clearance(b, allowance) {
                Clearance::Free => true,
                Clearance::Above { height, top } | Clearance::Over { height, top, .. } => {
                    height - top > LAYER_MARGIN
                }
                Clearance::Unknown => {
                    target.pieces <= 4
                        && (0..target.pieces)
                            .all(|k| !self.scene.reaches(SurfaceId(target.surface_id.0 + k), b))
                }
            };
            if !clear {
                return false;
            }
        }
        let mut clear = true;
        self.scene.surfaces_near(b, &mut |id| {
            if clear && matches!(self.scene.surface(id).kind, SurfaceKind::Obstacle(_)) {
                clear = !self.scene.reaches(id, b);
            }
        });
        clear
    }

    /// Moves `p` through `k` steps from step `s` in which it certainly meets nothing; returns
    /// the steps taken: `k`, or fewer where a droplet drifts out of the gun's air first (see
    /// [`Kernel::carried_off`]).
    #[inline]
    fn coast(&self, p: &mut Particle, k: u64, s: u64, drop: Option<&Droplet>, books: &mut Books) -> u64 {
        match self.motion.integrator {
            Integrator::Exact => {
                p.since += k as u16;
                k
            }
            Integrator::Euler | Integrator::SemiImplicitEuler => {
                if let (Some(d), Some(_)) = (drop, &self.air) {
                    return self.coast_in_air(p, k, s, d, books);
                }
                let (mut x, mut v) = (p.anchor, p.anchor_velocity());
                for _ in 0..k {
                    let (x1, v1) = self.motion.advance(x, v, self.dt);
                    x = x1;
                    v = v1.as_vec3().as_dvec3();
                }
                p.anchor = x;
                p.velocity = v.as_vec3();
                k
            }
        }
    }

    /// [`Kernel::coast`] for a droplet `d` in the gun's air: each step as a full step moves it,
    /// through the jet in its substeps; returns the steps taken, fewer where the air carries
    /// it off first.
    #[inline(never)]
    fn coast_in_air(&self, p: &mut Particle, k: u64, s: u64, d: &Droplet, books: &mut Books) -> u64 {
        let Some(air) = &self.air else { return 0 };
        let (mut x, mut v) = (p.anchor, p.anchor_velocity());
        let mut done = 0;
        while done < k {
            let u = self.air_at(s + done, x);
            if self.carried_off(p, s + done, d, (x, v, u), books) {
                break;
            }
            // The air at the step's start, found for the check above, starts the step too.
            let g = self.motion.gravity;
            let (x1, v1) = match self.jet(s + done) {
                Some(frame) => air.flow.step_in(frame, d, (x, v, u), g, self.dt),
                None => air.flow.step(None, d, x, v, g, self.dt),
            };
            x = x1;
            v = v1.as_vec3().as_dvec3();
            done += 1;
        }
        p.anchor = x;
        p.velocity = v.as_vec3();
        done
    }

    /// The droplet `p` is, if it feels the gun's air: a particle from the nozzle, with the
    /// diameter its id draws.
    #[inline]
    fn droplet(&self, p: &Particle) -> Option<Droplet> {
        let air = self.air.as_ref()?;
        (p.flags() & flags::RELEASED == 0)
            .then(|| air.flow.droplet(air.sizes.diameter(&self.key, p.id), self.density))
    }

    /// The gun's jet in step `s`, if it blows.
    #[inline]
    fn jet(&self, s: u64) -> Option<&JetFrame> {
        let air = self.air.as_ref()?;
        air.frames.get(s.wrapping_sub(air.first) as usize)?.as_ref()
    }

    /// The air's velocity at `x` (m) in step `s`, m/s: zero where it is still.
    #[inline]
    fn air_at(&self, s: u64, x: DVec3) -> DVec3 {
        match (&self.air, self.jet(s)) {
            (Some(air), Some(frame)) => air.flow.velocity(frame, x),
            _ => DVec3::ZERO,
        }
    }

    /// Advances a particle at `x` (m) with velocity `v` (m/s) by `h` (s) within step `s`: through
    /// the gun's air for a droplet, by the integrator otherwise.
    #[inline]
    fn advance(&self, x: DVec3, v: DVec3, h: f64, s: u64, drop: Option<&Droplet>) -> (DVec3, DVec3) {
        let (Some(d), Some(air)) = (drop, &self.air) else { return self.motion.advance(x, v, h) };
        air.flow.step(self.jet(s), d, x, v, self.motion.gravity, h)
    }

    /// True, and `p` retired as overspray, if at the start of step `s` the droplet `d` at `x`
    /// (m) moving at `v` (m/s) where the air moves at `u` (m/s) will strike nothing the jet aims
    /// at (see [`AirFlow::carried_off`]).
    #[inline]
    fn carried_off(
        &self,
        p: &mut Particle,
        s: u64,
        d: &Droplet,
        (x, v, u): (DVec3, DVec3, DVec3),
        books: &mut Books,
    ) -> bool {
        let Some(air) = &self.air else { return false };
        if !air.flow.carried_off(self.jet(s), d, x, v, u, self.motion.gravity) {
            return false;
        }
        books.tally.overspray.add(self.volumes.of(p.id, p.flags()));
        p.set_flags(p.flags() & !flags::ALIVE);
        true
    }

    /// The full step `s` of `p`: its impacts, then the checks for leaving the domain and for
    /// expiring.
    #[inline(never)]
    fn full_step(&self, p: &mut Particle, s: u64, drop: Option<&Droplet>, books: &mut Books) {
        let now = self.now(p);
        if let Some(d) = drop
            && self.carried_off(p, s, d, (now.x, now.v, self.air_at(s, now.x)), books)
        {
            p.anchor = now.x;
            p.velocity = now.v.as_vec3();
            return;
        }
        let quanta = self.volumes.of(p.id, p.flags());
        let (x, v, struck) = self.impacts(p, now, s, quanta, drop, books);
        if !p.is_alive() {
            // It stuck: it rests where it struck.
            p.anchor = x;
            p.velocity = glam::Vec3::ZERO;
            p.since = 0;
            return;
        }
        // The state at the step's end: re-anchored after an impact (and always with Euler);
        // otherwise one step further from the anchor, as a coast would leave it.
        let reanchor = struck || self.motion.integrator != Integrator::Exact || p.since >= MAX_SINCE;
        if reanchor {
            p.anchor = x;
            p.velocity = v.as_vec3();
            p.since = 0;
        } else {
            p.since += 1;
        }
        let end = self.now(p).x;
        let released = p.flags() & flags::RELEASED != 0;
        let age = (s + 1 - u64::from(p.born)) as f64;
        let left = !self.domain.contains(end);
        if !left && age <= self.lifetime_steps && p.impacts() < MAX_IMPACTS {
            return;
        }
        // Out of flight: left the domain or expired; a nozzle particle that never struck
        // anything is overspray either way.
        let t = &mut books.tally;
        let fate = match (released, left) {
            (true, true) => &mut t.released_left,
            (true, false) => &mut t.released_expired,
            (false, _) if p.impacts() == 0 => &mut t.overspray,
            (false, true) => &mut t.left_domain,
            (false, false) => &mut t.expired,
        };
        fate.add(quanta);
        p.set_flags(p.flags() & !flags::ALIVE);
    }

    /// Moves `p` from `now` through step `s`, resolving up to `max_impacts` impacts; returns the
    /// position and velocity it ends the step with, and whether it struck anything. A particle
    /// that sticks leaves flight.
    fn impacts(
        &self,
        p: &mut Particle,
        now: Now,
        s: u64,
        quanta: u64,
        drop: Option<&Droplet>,
        books: &mut Books,
    ) -> (DVec3, DVec3, bool) {
        let (mut x, mut v) = (now.x, now.v);
        let mut remaining = self.dt;
        let mut struck = false;
        for _ in 0..self.max_impacts {
            let (x_end, v_end, hit) = self.flight(x, v, remaining, s, drop);
            let Some(strike) = hit else {
                return (x_end, v_end, struck);
            };
            struck = true;
            p.set_impacts(p.impacts().saturating_add(1));
            let time = s as f64 * self.dt + (self.dt - remaining) + strike.hit.t * remaining;
            match self.impact(p, &strike, quanta, time, s, books) {
                None => return (strike.hit.point, DVec3::ZERO, true),
                Some(v_out) => {
                    x = strike.hit.point + strike.hit.normal * SURFACE_OFFSET;
                    v = v_out;
                    remaining *= 1.0 - strike.hit.t;
                }
            }
        }
        // Out of impacts for this step: wait at the last impact point.
        (x, v, struck)
    }

    /// Resolves `p`'s impact `strike` at `time` (s) in step `s`: books it, and returns the
    /// rebound velocity, or `None` if the particle stuck (and left flight).
    fn impact(
        &self,
        p: &mut Particle,
        strike: &Strike,
        quanta: u64,
        time: f64,
        s: u64,
        books: &mut Books,
    ) -> Option<DVec3> {
        let Strike { surface: id, hit, velocity: v_in, cell } = *strike;
        let mut rng = self.key.stream(p.id, u32::from(p.impacts()));
        let surface = self.scene.surface(id);
        // An impact on the front of a target: the target, its index and the cell struck. A
        // contact with the layer is on the front by construction, whatever its normal (a
        // particle entering a taller column through its side meets a normal in the face's
        // plane); a hit on the bare surface is on the front if it comes from that side.
        let front = match surface.kind {
            SurfaceKind::Target(t)
                if cell.is_some()
                    || self.targets[t].surface.receives(surface.piece, hit.point, hit.normal) =>
            {
                let target = &self.targets[t];
                Some((t, cell.unwrap_or_else(|| target.surface.cell_at(surface.piece, hit.point))))
            }
            _ => None,
        };
        let model = &self.models[surface.impact];
        let outcome = model.resolve(&self.site(p, model, front, &hit, v_in), &mut rng);
        let stuck = matches!(outcome, Outcome::Stick | Outcome::Rest);
        let wear = self.wear(front, &hit, v_in, quanta);
        let first_substrate = self.first_substrate(p, surface.kind, front);
        let booked = Impact {
            quanta,
            back: matches!(surface.kind, SurfaceKind::Target(_)) && front.is_none(),
            stuck,
            released: p.flags() & flags::RELEASED != 0,
            loose: outcome == Outcome::Rest,
            rebound: p.flags() & flags::BOUNCED != 0,
            first_substrate,
        };
        self.book(&booked, surface.kind, front, wear, books);
        if self.capture.wants(p.id, p.impacts()) {
            let coated = front.is_some_and(|(t, c)| {
                self.targets[t]
                    .erosion
                    .as_ref()
                    .is_some_and(|e| e.coating.get(c as usize).is_some_and(|&x| x > 0.0))
            });
            let event = ImpactEvent {
                time,
                position: hit.point,
                normal: hit.normal,
                velocity: v_in,
                surface: id,
                stuck,
                eroded: if coated { wear.0 as f32 } else { wear.1 as f32 },
                particle: p.id,
                impact: p.impacts(),
            };
            books.events.push((s, event));
        }
        match outcome {
            Outcome::Stick | Outcome::Rest => {
                p.set_flags(p.flags() & !flags::ALIVE);
                None
            }
            Outcome::Rebound(v_out) => {
                p.set_flags(p.flags() | flags::BOUNCED);
                Some(v_out)
            }
        }
    }

    /// Books an impact: in the tallies of its target or obstacle and, on a target's front, in
    /// the cell struck (an impact, its wear) and, if it stuck, in the cells of its deposit's
    /// footprint (its volume shared evenly in whole quanta).
    fn book(
        &self,
        impact: &Impact,
        kind: SurfaceKind,
        front: Option<(usize, u32)>,
        wear: (f64, f64),
        books: &mut Books,
    ) {
        match kind {
            SurfaceKind::Target(t) => books.targets[t].book(impact),
            SurfaceKind::Obstacle(o) => books.obstacles[o].book(impact),
        }
        if impact.first_substrate {
            books.tally.first_substrate_impact(impact.quanta, impact.stuck);
        }
        let Some((t, cell)) = front else { return };
        let target = &self.targets[t];
        let touched = &mut books.touched[t];
        target.pending.impact(cell, wear, touched);
        if impact.stuck {
            let mut n = 0u64;
            target.surface.footprint(cell, &mut |_| n += 1);
            let mut k = 0u64;
            target.surface.footprint(cell, &mut |c| {
                target.pending.deposit(c, share(impact.quanta, n, k), touched);
                k += 1;
            });
        }
    }

    /// Whether this is `p`'s first impact on the front of a substrate target (and marks it).
    fn first_substrate(&self, p: &mut Particle, kind: SurfaceKind, front: Option<(usize, u32)>) -> bool {
        let substrate = matches!((kind, front), (SurfaceKind::Target(t), Some(_)) if self.targets[t].role == Role::Substrate);
        if substrate && p.flags() & flags::HIT_SUBSTRATE == 0 {
            p.set_flags(p.flags() | flags::HIT_SUBSTRATE);
            return true;
        }
        false
    }

    /// Volumes of coating and of substrate (m³) an impact at `hit` with velocity `v_in` would
    /// wear away, under the erosion law of the target whose front it strikes (none elsewhere).
    fn wear(&self, front: Option<(usize, u32)>, hit: &Hit, v_in: DVec3, quanta: u64) -> (f64, f64) {
        let Some(erosion) = front.and_then(|(t, _)| self.config.targets[t].erosion.as_ref()) else {
            return (0.0, 0.0);
        };
        let speed = v_in.length();
        // γ: the impact angle from the surface.
        let gamma = (-v_in.dot(hit.normal) / speed.max(f64::MIN_POSITIVE)).clamp(0.0, 1.0).asin();
        let mass = quanta as f64 * self.config.volume_quantum() * self.density;
        (
            f64::from(erosion.coating_law.removed_volume(mass, speed, gamma) as f32),
            f64::from(erosion.substrate_law.removed_volume(mass, speed, gamma) as f32),
        )
    }

    /// The impact of `p` at `hit` with velocity `v_in` as the impact laws see it: on a target's
    /// front, over the layer averaged over the model's cushion radius, at an angle of incidence
    /// taken on the bare surface.
    fn site(
        &self,
        p: &Particle,
        model: &ImpactModel,
        front: Option<(usize, u32)>,
        hit: &Hit,
        v_in: DVec3,
    ) -> ImpactSite {
        let layer = front.map(|(t, cell)| self.targets[t].surface.mean_thickness(cell, model.cushion_radius));
        let material = self.key.stream(p.id, MATERIAL_EVENT).random::<f64>();
        let site = ImpactModel::site(v_in, hit.normal, layer, material, p.flags() & flags::BOUNCED != 0);
        match front {
            Some((t, cell)) => site.incidence_on(self.targets[t].surface.normal(cell)),
            None => site,
        }
    }

    /// Flies from `x` with velocity `v` for `dt` within step `step` (a droplet `drop` through the
    /// gun's air): the end position and velocity, and the first
    /// hit on the way. A deposited layer is struck on its top, found along the straight chord
    /// of the step (for the exact integrator, the arc's chord, which it leaves by at most
    /// g Δt²/8).
    fn flight(
        &self,
        x: DVec3,
        v: DVec3,
        dt: f64,
        step: u64,
        drop: Option<&Droplet>,
    ) -> (DVec3, DVec3, Option<Strike>) {
        let (x1, v1) = self.advance(x, v, dt, step, drop);
        let mut hit = self.bare_hit(x, v, x1, v1, dt).map(|(surface, hit, velocity)| Strike {
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
    fn bare_hit(&self, x: DVec3, v: DVec3, x1: DVec3, v1: DVec3, dt: f64) -> Option<(SurfaceId, Hit, DVec3)> {
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
}
