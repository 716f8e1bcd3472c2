//! The gun's air and the drag that carries droplets with it: a free turbulent jet from the
//! nozzle, turned parallel to the surface it strikes by a stagnation flow, and droplets that
//! relax towards the local air velocity with their Stokes relaxation time.
//!
//! # The air
//!
//! The jet leaves an outlet of effective diameter d₀ (the round outlet that passes the gun's
//! air at its speed) at speed U₀ along the spray axis, and spreads from the nozzle point, its
//! virtual origin: its half-widths (where the velocity is half the centreline's) grow as
//! `b = S z` with the distance z along the axis, with a spreading rate S of their own along
//! the nozzle's width and height axes (0.094 for a round jet: Hussein, Capp & George 1994; a
//! fan gun's horn air spreads wider along its fan). The centreline keeps U₀ in the potential
//! core (to z = r₀/√(S_w S_h)) and then falls as `U_c = U₀ (d₀/2) / √(b_w b_h)`, which holds the
//! jet's momentum flux constant: for a round jet `U_c/U₀ = 5.3 d₀/z`, against the measured
//! 5.8 d₀/z of Pope 2000, Table 5.1. (A Gaussian jet with this decay carries 1/(2 ln 2) = 72 %
//! of the outlet's top-hat momentum flux; full conservation would give 6.3 d₀/z, farther from
//! the measurements, whose shortfall stands for the losses at a real nozzle.) Across the
//! jet the velocity is Gaussian, `U_c exp(−ln 2 (ξ² + η²))` with ξ, η the offsets over the
//! half-widths, and it points along the ray from the nozzle, as a self-similar jet's mean
//! streamlines do: a droplet keeps the direction it was sprayed in and the air sets only how
//! fast it goes, so the spray's fan is the air's.
//!
//! Where the axis strikes a surface (the first substrate target along it, a distance H from the
//! nozzle), a stagnation layer of thickness δ = λ H covers it (λ = 0.14: the impingement region
//! of Beltaos & Rajaratnam 1974). Inside, at a height h above the surface, the jet's velocity
//! towards the surface falls linearly to zero at the wall, `u_n = −W h/δ`: a linear stagnation
//! flow of strain rate W/δ (W the jet's speed towards the surface, W_c on the axis), in which
//! a droplet that enters with the air's velocity reaches the wall only if its Stokes number
//! τ W/δ exceeds 1/4 (Taylor 1940; Langmuir & Blodgett 1946). The air it brings flows out
//! along the surface: by continuity over the layer, the outflow at an offset ρ from the
//! stagnation point is `u_t = (W_c/δ) 2G(q) (c_w ρ_w e_w + c_h ρ_h e_h)`, with q = ξ² + η²,
//! G(q) = (1 − e^{−q ln 2}) / (2 q ln 2) (so that the inflow inside any ellipse leaves through
//! its rim) and weights c_w = b_h/(b_w + b_h), c_h = b_w/(b_w + b_h) that send a flat jet's
//! air out across its narrow side; no faster than W_c. The air flows while the nozzle sprays,
//! and is still otherwise.
//!
//! # The drag
//!
//! A droplet of diameter d and density ρ_d relaxes towards the air velocity u with the Stokes
//! time τ = ρ_d d² / (18 μ), shortened by the Schiller–Naumann factor
//! f = 1 + 0.15 Re^0.687 (Re = ρ_a |u − v| d / μ ≤ 1000; 0.0183 Re above, C_d = 0.44) of a
//! sphere at higher Reynolds numbers (Schiller & Naumann 1933; Clift, Grace & Weber 1978):
//! `dv/dt = (u − v)/τ_f + g`, τ_f = τ / f. Over a step of length h the air velocity and τ_f are
//! held at their values at the step's start, and the step is integrated exactly:
//! `v₁ = w + (v − w) e^{−h/τ_f}`, `x₁ = x + w h + (v − w) τ_f (1 − e^{−h/τ_f})` with
//! w = u + g τ_f. The update is stable for any τ_f/h, as a 10 µm droplet (τ ≈ 0.4 ms) needs.
//! Under Schiller–Naumann drag, where the slip changes by more than 5 % over a step, τ_f is
//! taken again at the step's mean slip (second order as the droplet slows).
//! Where the air changes within a step (near the nozzle, across the jet, through the
//! stagnation layer) the step is split into substeps ([`AirFlow::substeps`]).

use glam::DVec3;
use std::f64::consts::LN_2;

/// Most substeps one step of a droplet through the air is split into (see
/// [`AirFlow::substeps`]).
pub const MAX_SUBSTEPS: u32 = 256;

/// How the drag on a droplet depends on its Reynolds number.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DragLaw {
    /// Stokes drag at every Reynolds number: the closed forms' law.
    Stokes,
    /// Stokes drag times 1 + 0.15 Re^0.687 (Re ≤ 1000; C_d = 0.44 above).
    #[default]
    SchillerNaumann,
}

/// The gun's air jet and the properties of the air (see the module's docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AirFlow {
    /// Air speed at the outlet, U₀, m/s.
    pub speed: f64,
    /// Effective outlet diameter d₀, m.
    pub outlet_diameter: f64,
    /// Growth of the jet's half-width per unit distance along the nozzle's width axis and its
    /// height axis, S, dimensionless.
    pub spread: [f64; 2],
    /// Thickness of the stagnation layer as a share of the distance from the nozzle to the
    /// surface the axis strikes, λ, dimensionless.
    pub stagnation_layer: f64,
    /// Dynamic viscosity of the air, μ, Pa·s.
    pub viscosity: f64,
    /// Density of the air, kg/m³ (for the Reynolds number).
    pub density: f64,
    /// How drag depends on the Reynolds number.
    pub drag_law: DragLaw,
    /// A droplet slower than this, where the air is slower than this too, has left the jet:
    /// the booth's air carries it off as overspray, m/s (0: never).
    pub booth_speed: f64,
}

/// Where the jet strikes a surface: the stagnation layer over it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Wall {
    /// The stagnation point: where the axis meets the surface, m.
    pub point: DVec3,
    /// Unit normal of the surface, towards the nozzle.
    pub normal: DVec3,
    /// Thickness δ of the stagnation layer, m.
    pub depth: f64,
    /// Its largest strain rate: the centreline's speed towards the surface over δ, 1/s.
    pub strain: f64,
    /// The nozzle's width and height axes projected onto the surface (unit), and the weights
    /// c_w, c_h of the outflow along them.
    pub outflow: [(DVec3, f64); 2],
}

/// The jet in one step: the nozzle's pose and the surface it strikes, if any.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JetFrame {
    /// Nozzle position, m.
    pub origin: DVec3,
    /// Unit spray axis.
    pub axis: DVec3,
    /// Unit width and height axes of the nozzle.
    pub across: [DVec3; 2],
    /// The stagnation layer where the axis strikes a surface.
    pub wall: Option<Wall>,
}

/// A droplet's own aerodynamics: its diameter and its Stokes relaxation time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Droplet {
    /// Diameter, m.
    pub diameter: f64,
    /// Stokes relaxation time ρ_d d² / (18 μ), s.
    pub tau: f64,
}

impl AirFlow {
    /// Checks the parameters; the message names the one that is wrong.
    pub fn check(&self) -> Result<(), String> {
        let within = |name: &str, x: f64, lo: f64, hi: f64, open_lo: bool| {
            if x.is_finite() && (x > lo || (!open_lo && x == lo)) && x <= hi {
                Ok(())
            } else {
                Err(format!("{name} must lie in {}{lo}, {hi}], got {x}", if open_lo { "(" } else { "[" }))
            }
        };
        within("speed", self.speed, 0.0, 1000.0, false)?;
        within("outlet_diameter", self.outlet_diameter, 0.0, 1.0, true)?;
        within("spread", self.spread[0], 0.0, 2.0, true)?;
        within("spread", self.spread[1], 0.0, 2.0, true)?;
        within("stagnation_layer", self.stagnation_layer, 0.0, 1.0, false)?;
        within("viscosity", self.viscosity, 0.0, 1.0, true)?;
        within("density", self.density, 0.0, 100.0, true)?;
        within("booth_speed", self.booth_speed, 0.0, 2.0, false)
    }

    /// The droplet of diameter `diameter` (m) and density `density` (kg/m³) in this air.
    pub fn droplet(&self, diameter: f64, density: f64) -> Droplet {
        Droplet { diameter, tau: density * diameter * diameter / (18.0 * self.viscosity) }
    }

    /// The jet of a nozzle at `origin` spraying along `axis` with width and height axes
    /// `across`, striking at `strike` (the point and the surface's unit normal) a distance H
    /// along the axis, if it strikes anything.
    pub fn frame(
        &self,
        origin: DVec3,
        axis: DVec3,
        across: [DVec3; 2],
        strike: Option<(DVec3, DVec3)>,
    ) -> JetFrame {
        let wall = strike.and_then(|(point, normal)| {
            let normal = if normal.dot(axis) > 0.0 { -normal } else { normal };
            let distance = (point - origin).dot(axis);
            let depth = self.stagnation_layer * distance;
            if depth <= 0.0 {
                return None;
            }
            let [bw, bh] = self.half_widths(distance);
            let strain = self.centre_speed(distance) * -axis.dot(normal) / depth;
            let onto = |a: DVec3, other: DVec3| {
                (a - normal * a.dot(normal))
                    .try_normalize()
                    .unwrap_or_else(|| normal.cross(other).normalize_or_zero())
            };
            let ew = onto(across[0], across[1]);
            let eh = onto(across[1], across[0]);
            Some(Wall { point, normal, depth, strain, outflow: [(ew, bh / (bw + bh)), (eh, bw / (bw + bh))] })
        });
        JetFrame { origin, axis, across, wall }
    }

    /// Half-widths of the jet along the width and height axes at a distance `z` (m) from the
    /// nozzle, m: it spreads from the nozzle, its virtual origin.
    #[inline]
    fn half_widths(&self, z: f64) -> [f64; 2] {
        [self.spread[0] * z, self.spread[1] * z]
    }

    /// The centreline speed at a distance `z` (m) from the nozzle, m/s: U₀ in the potential
    /// core, then U₀ (d₀/2) / √(b_w b_h), which holds the momentum flux constant (at 72 % of
    /// the outlet's top-hat flux: see the module's docs).
    #[inline]
    fn centre_speed(&self, z: f64) -> f64 {
        let [bw, bh] = self.half_widths(z);
        let r0 = 0.5 * self.outlet_diameter;
        let area = bw * bh;
        if area <= r0 * r0 { self.speed } else { self.speed * r0 / area.sqrt() }
    }

    /// Where `x` (m) lies in the jet `frame`: its distance z along the axis (m), its offsets
    /// across it over the half-widths squared and summed (q = ξ² + η²), and the offset across
    /// the axis (m).
    #[inline]
    fn place(&self, frame: &JetFrame, x: DVec3) -> (f64, f64, DVec3) {
        let r = x - frame.origin;
        let z = r.dot(frame.axis);
        let across = r - frame.axis * z;
        if z <= 0.0 {
            return (z, f64::INFINITY, across);
        }
        let (xi, eta) = (r.dot(frame.across[0]) / self.spread[0], r.dot(frame.across[1]) / self.spread[1]);
        (z, (xi * xi + eta * eta) / (z * z), across)
    }

    /// The air velocity at `x` (m) in the jet `frame`, m/s.
    #[inline]
    pub fn velocity(&self, frame: &JetFrame, x: DVec3) -> DVec3 {
        let (z, q, across) = self.place(frame, x);
        // Behind the nozzle, and beyond 5 half-widths (the profile below 3·10⁻⁸, the wall jet
        // tapered off from 4), still air.
        if q > 25.0 || self.speed == 0.0 {
            return DVec3::ZERO;
        }
        let centre = self.centre_speed(z);
        let profile = (-LN_2 * q).exp();
        // Along the ray from the nozzle: a self-similar jet's mean streamlines.
        let mut u = (frame.axis + across / z) * (centre * profile);
        if let Some(w) = &frame.wall {
            let h = (x - w.point).dot(w.normal);
            // The centreline's speed towards the wall, W_c.
            let towards = -frame.axis.dot(w.normal) * centre;
            if h >= 0.0 && h < w.depth && towards > 0.0 {
                // The normal part falls linearly to the wall; the air flows out along it.
                let normal = u.dot(w.normal);
                if normal < 0.0 {
                    u -= w.normal * (normal * (1.0 - h / w.depth));
                }
                let offset = x - w.point;
                let g = if q < 1e-6 { 0.5 } else { -(-LN_2 * q).exp_m1() / (2.0 * LN_2 * q) };
                let strain = towards / w.depth * 2.0 * g;
                let out: DVec3 = w.outflow.iter().map(|&(e, c)| e * (strain * c * offset.dot(e))).sum();
                // A wall jet is no faster than the jet that feeds it (a flat jet's far sides
                // would otherwise outrun it).
                let fast = out.length() / towards;
                // The wall jet fades out between 4 and 5 half-widths (smoothly, to no air).
                let fade = ((25.0 - q) / 9.0).clamp(0.0, 1.0);
                let fade = fade * fade * (3.0 - 2.0 * fade);
                u += (if fast > 1.0 { out / fast } else { out }) * fade;
            }
        }
        u
    }

    /// Advances `droplet` at `x` (m) with velocity `v` (m/s) by a step of `h` (s) through the
    /// jet `frame` (`None`: still air) under gravity `g` (m/s²): one held-air step, or the
    /// [`AirFlow::substeps`] it needs, each holding the air where it starts.
    #[inline]
    pub fn step(
        &self,
        frame: Option<&JetFrame>,
        droplet: &Droplet,
        x: DVec3,
        v: DVec3,
        g: DVec3,
        h: f64,
    ) -> (DVec3, DVec3) {
        let Some(frame) = frame else { return self.advance(droplet, x, v, DVec3::ZERO, g, h) };
        self.step_in(frame, droplet, (x, v, self.velocity(frame, x)), g, h)
    }

    /// [`AirFlow::step`] through the jet `frame` from `x` (m) and `v` (m/s) where the air moves
    /// at `u` (m/s): for a caller that has the air at the step's start already.
    #[inline]
    pub fn step_in(
        &self,
        frame: &JetFrame,
        droplet: &Droplet,
        (x, v, u): (DVec3, DVec3, DVec3),
        g: DVec3,
        h: f64,
    ) -> (DVec3, DVec3) {
        let tau = self.relaxation_time(droplet, v, u);
        let (x1, v1) = self.advance_from(droplet, (x, v, u), g, h, tau);
        let n = self.substeps(frame, (x, v), x1, h, tau);
        if n <= 1 {
            return (x1, v1);
        }
        let h = h / f64::from(n);
        let (mut x, mut v) = self.advance_from(droplet, (x, v, u), g, h, tau);
        for _ in 1..n {
            let u = self.velocity(frame, x);
            (x, v) = self.advance_from(droplet, (x, v, u), g, h, self.relaxation_time(droplet, v, u));
        }
        (x, v)
    }

    /// Substeps a droplet's step of `h` (s) from `x` (m) with velocity `v` (m/s) and drag
    /// relaxation time `tau` (s), whose one held-air step would end at `x1`, must be split into
    /// so that the air it feels is followed (each substep holds the air where it starts):
    ///
    /// - in the jet (within 3 half-widths of its axis at either end), each substep moves along
    ///   the ray from the nozzle at most a quarter of the distance from it (over which the
    ///   centreline speed changes), and across rays at most half the jet's half-width; both
    ///   times τ_f/h where the droplet responds too slowly for the air's change within a step
    ///   to matter;
    /// - into or through a stagnation layer where the jet strikes it (within 5 half-widths),
    ///   each substep lasts at most a quarter of the local strain time δ/W, and, within 3
    ///   half-widths, moves at most δ/4.
    ///
    /// At most [`MAX_SUBSTEPS`].
    pub fn substeps(&self, frame: &JetFrame, (x, v): (DVec3, DVec3), x1: DVec3, h: f64, tau: f64) -> u32 {
        if self.speed <= 0.0 {
            return 1;
        }
        let (z, q0, _) = self.place(frame, x);
        let q = q0.min(self.place(frame, x1).1);
        if q >= 25.0 {
            return 1;
        }
        let mut n: f64 = 1.0;
        if q < 9.0 {
            let r0 = 0.5 * self.outlet_diameter;
            let ray = (x - frame.origin).normalize_or(frame.axis);
            let along = v.dot(ray).abs() * h;
            let cross = (v - ray * v.dot(ray)).length() * h;
            let b = self.spread[0].min(self.spread[1]) * z.max(0.0) + r0;
            let response = (h / tau).min(1.0);
            n = n.max((along / (0.25 * (z.max(0.0) + r0))).max(cross / (0.5 * b)) * response);
        }
        if let Some(w) = &frame.wall {
            let (h0, h1) = ((x - w.point).dot(w.normal), (x1 - w.point).dot(w.normal));
            if h0.min(h1) < w.depth && h0.max(h1) > 0.0 {
                n = n.max(4.0 * w.strain * (-LN_2 * q).exp() * h);
                if q < 9.0 {
                    n = n.max((x1 - x).length() / (0.25 * w.depth));
                }
            }
        }
        n.ceil().min(f64::from(MAX_SUBSTEPS)) as u32
    }

    /// A bound of the air's speed (m/s) within `radius` (m) of `x` in the jet `frame`: the
    /// centreline's speed where the ball comes nearest the nozzle (it only falls along the
    /// axis), along a ray within 5 half-widths (√(1 + 25 S²) times it), doubled over a
    /// stagnation layer (see [`AirFlow::max_speed`]).
    #[inline]
    pub fn speed_bound(&self, frame: &JetFrame, x: DVec3, radius: f64) -> f64 {
        let z = ((x - frame.origin).dot(frame.axis) - radius).max(0.0);
        let s = self.spread[0].max(self.spread[1]);
        self.centre_speed(z) * (1.0 + 25.0 * s * s).sqrt() * if frame.wall.is_some() { 2.0 } else { 1.0 }
    }

    /// A bound of the air's speed anywhere in the jet `frame`, m/s: the jet is no faster than
    /// at its outlet, turning it only slows it, and the outflow along a wall is no faster than
    /// the jet.
    pub fn max_speed(&self, frame: &JetFrame) -> f64 {
        // Along a ray within 5 half-widths the speed is at most U₀ √(1 + 25 S²).
        let s = self.spread[0].max(self.spread[1]);
        self.speed * (1.0 + 25.0 * s * s).sqrt() * if frame.wall.is_some() { 2.0 } else { 1.0 }
    }

    /// The drag relaxation time of `droplet` moving at `v` through air moving at `u`, s.
    #[inline]
    pub fn relaxation_time(&self, droplet: &Droplet, v: DVec3, u: DVec3) -> f64 {
        match self.drag_law {
            DragLaw::Stokes => droplet.tau,
            DragLaw::SchillerNaumann => {
                let re = self.density * (u - v).length() * droplet.diameter / self.viscosity;
                let f = if re <= 1000.0 { 1.0 + 0.15 * re.powf(0.687) } else { 0.0183 * re };
                droplet.tau / f
            }
        }
    }

    /// Advances a droplet at `x` (m) with velocity `v` (m/s) by `h` (s) through air moving at
    /// `u` (m/s, held over the step) under gravity `g` (m/s²), exactly for that held air and a
    /// held relaxation time (see the module's docs); returns the new position and velocity.
    #[inline]
    pub fn advance(
        &self,
        droplet: &Droplet,
        x: DVec3,
        v: DVec3,
        u: DVec3,
        g: DVec3,
        h: f64,
    ) -> (DVec3, DVec3) {
        self.advance_from(droplet, (x, v, u), g, h, self.relaxation_time(droplet, v, u))
    }

    /// [`AirFlow::advance`] from the relaxation time `tau` (s) at the step's start. Under
    /// Schiller–Naumann drag, where the droplet's slip changes by more than 5 % over the step,
    /// the relaxation time is taken again at the step's mean slip (predicted by this first
    /// pass), which makes the step second order in h as the droplet slows; a smaller change
    /// moves the relaxation time by under 0.035 of itself.
    #[inline]
    fn advance_from(
        &self,
        droplet: &Droplet,
        (x, v, u): (DVec3, DVec3, DVec3),
        g: DVec3,
        h: f64,
        tau: f64,
    ) -> (DVec3, DVec3) {
        let held = |tau: f64| {
            let decay = -(-h / tau).exp_m1(); // 1 − e^{−h/τ}, exact for small h/τ
            let w = u + g * tau;
            ((x + w * h + (v - w) * (tau * decay), v + (w - v) * decay), decay)
        };
        let (end, decay) = held(tau);
        if self.drag_law == DragLaw::Stokes || decay <= 0.05 {
            return end;
        }
        held(self.relaxation_time(droplet, 0.5 * (v + end.1), u)).0
    }

    /// True if `droplet` at `x` (m), moving at `v` (m/s) where the air of the jet `frame` (if it
    /// blows) moves at `u` (m/s), under gravity `g` (m/s²), will strike nothing the jet aims
    /// at: the air carries it off as overspray. That is so where
    ///
    /// - it has left the jet: outside a stagnation layer's reach (where the air turns, and a
    ///   droplet may land slowly), it and the air there are both slower than the booth's air
    ///   (see [`AirFlow::booth_speed`]); or
    /// - the stagnation layer turns it past the surface: it is inside the layer, moving
    ///   outwards along the surface (as the outflow it relaxes to carries it) and not away from
    ///   it, gravity does not pull it towards the surface, and with the largest strain a the
    ///   layer can have where it may go (the centreline's speed at the layer's top over δ,
    ///   times the largest normal share of a ray within 5 half-widths, times the profile at
    ///   its offset seen from as deep as the wall) the equation τ h'' + h' + a h = 0 is
    ///   overdamped even at its Stokes relaxation time τ (the longest it can have: 4 a τ < 1),
    ///   and it approaches the surface no faster than |λ₂| h, λ₂ = −(1 + √(1 − 4aτ))/(2τ) the
    ///   equation's fast root. Its height then falls monotonically and never reaches zero
    ///   (Taylor 1940's argument), and a weaker strain only slows its approach.
    #[inline]
    pub fn carried_off(
        &self,
        frame: Option<&JetFrame>,
        droplet: &Droplet,
        x: DVec3,
        v: DVec3,
        u: DVec3,
        g: DVec3,
    ) -> bool {
        let layer = frame.and_then(|f| {
            let wall = f.wall.as_ref()?;
            let h = (x - wall.point).dot(wall.normal);
            (h > 0.0 && h < wall.depth && self.place(f, x).1 < 25.0).then_some((f, wall, h))
        });
        let Some((frame, wall, h)) = layer else {
            let s2 = self.booth_speed * self.booth_speed;
            return v.length_squared() < s2 && u.length_squared() < s2;
        };
        let approach = -v.dot(wall.normal);
        let offset = x - wall.point - wall.normal * h;
        let outwards = offset.dot(v + wall.normal * approach) >= 0.0;
        if approach < 0.0 || !outwards || g.dot(wall.normal) < 0.0 {
            return false;
        }
        let cos = -frame.axis.dot(wall.normal);
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let spread = self.spread[0].max(self.spread[1]);
        let (z, q, _) = self.place(frame, x);
        // Moving outwards its offset from the axis only grows, and down to the wall its
        // distance from the nozzle grows by at most δ/cos: its q falls by at most that ratio
        // squared (0.74 for δ = 0.14 H square on).
        let deeper = z / (z + wall.depth / cos.max(0.1));
        let profile = (-LN_2 * q * deeper * deeper).exp();
        let strain =
            self.centre_speed((z - wall.depth).max(0.0)) * (cos + 5.0 * spread * sin) * profile / wall.depth;
        let tau = droplet.tau;
        let disc = 1.0 - 4.0 * strain * tau;
        disc > 0.0 && approach <= (1.0 + disc.sqrt()) / (2.0 * tau) * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn air() -> AirFlow {
        AirFlow {
            speed: 100.0,
            outlet_diameter: 0.006,
            spread: [0.094, 0.094],
            stagnation_layer: 0.14,
            viscosity: 1.81e-5,
            density: 1.2,
            drag_law: DragLaw::Stokes,
            booth_speed: 0.0,
        }
    }

    /// The free round jet's momentum flux ∫ρu² dA (Gaussian: U_c² π b² / (2 ln 2)) is the same
    /// at every distance past its core: U₀² π r₀² / (2 ln 2), 72 % of the outlet's top-hat
    /// flux; and its centreline decays like 5.3 d₀/z.
    #[test]
    fn the_free_jet_keeps_its_momentum_flux() {
        let a = air();
        let frame = a.frame(DVec3::ZERO, DVec3::X, [DVec3::Y, DVec3::Z], None);
        let flux = |z: f64| {
            let (n, r) = (4000, 0.6 * z);
            let dr = r / n as f64;
            (0..n)
                .map(|k| {
                    let rr = (k as f64 + 0.5) * dr;
                    a.velocity(&frame, DVec3::new(z, rr, 0.0)).x.powi(2) * std::f64::consts::TAU * rr * dr
                })
                .sum::<f64>()
        };
        let at_outlet = a.speed * a.speed * std::f64::consts::PI * 0.003f64.powi(2) / (2.0 * LN_2);
        for z in [0.05, 0.2, 0.5] {
            assert!((flux(z) / at_outlet - 1.0).abs() < 1e-3, "z = {z}: {}", flux(z) / at_outlet);
        }
        let uc = a.velocity(&frame, DVec3::new(0.5, 0.0, 0.0)).x;
        assert!((uc / (a.speed * 0.006 / 0.5) - 0.5 / 0.094).abs() < 1e-9);
        // In the core (z < r₀/S = 32 mm) the centreline keeps U₀; off the axis the air runs
        // along the ray from the nozzle.
        assert_eq!(a.velocity(&frame, DVec3::new(0.02, 0.0, 0.0)).x, a.speed);
        let u = a.velocity(&frame, DVec3::new(0.2, 0.01, 0.0));
        assert!((u.y / u.x - 0.01 / 0.2).abs() < 1e-12);
    }

    /// Inside the stagnation layer the air brought in through any disc's top leaves through
    /// its rim: ∫₀^R W(ρ) 2πρ dρ = 2πR δ u_t(R), and it has no normal component at the wall.
    #[test]
    fn the_stagnation_layer_conserves_the_air_it_turns() {
        let a = air();
        let wall = (DVec3::new(0.2, 0.0, 0.0), DVec3::NEG_X);
        let frame = a.frame(DVec3::ZERO, DVec3::X, [DVec3::Y, DVec3::Z], Some(wall));
        let w = frame.wall.expect("the axis strikes the wall");
        assert!((w.depth - 0.028).abs() < 1e-12);
        // The disc's top at the layer's mid-depth, where the outflow is taken: the profile
        // there is the one the outflow was derived from.
        let mid = 0.2 - 0.5 * w.depth;
        let top = |rho: f64| a.velocity(&frame, DVec3::new(mid, rho, 0.0)).x / 0.5;
        for r in [0.005, 0.02, 0.06] {
            let n = 4000;
            let inflow: f64 = (0..n)
                .map(|k| {
                    let rho = (k as f64 + 0.5) * r / n as f64;
                    top(rho) * std::f64::consts::TAU * rho * r / n as f64
                })
                .sum();
            // Less the jet's own spread along its ray.
            let out = a.velocity(&frame, DVec3::new(mid, r, 0.0)).y - r / mid * top(r);
            let side = std::f64::consts::TAU * r * w.depth * out;
            assert!((side / inflow - 1.0).abs() < 0.03, "R = {r}: out/in = {}", side / inflow);
        }
        assert!(a.velocity(&frame, DVec3::new(0.2, 0.01, 0.004)).x.abs() < 1e-12);
    }

    /// A droplet in uniform air follows v(t) = w + (v₀ − w) e^{−t/τ}, w = u + g τ, and
    /// x(t) = x₀ + w t + (v₀ − w) τ (1 − e^{−t/τ}), whatever the step.
    #[test]
    fn a_step_is_exact_in_uniform_air() {
        let a = air();
        let d = a.droplet(30e-6, 1200.0);
        let (u, g, v0) = (DVec3::new(0.0, 3.0, 0.0), DVec3::new(0.0, 0.0, -9.81), DVec3::new(20.0, 0.0, 0.0));
        let t = 0.01;
        let w = u + g * d.tau;
        let exact_x = w * t + (v0 - w) * d.tau * (1.0 - (-t / d.tau).exp());
        for n in [1, 7, 100] {
            let (mut x, mut v) = (DVec3::ZERO, v0);
            for _ in 0..n {
                (x, v) = a.advance(&d, x, v, u, g, t / n as f64);
            }
            assert!((x - exact_x).length() < 1e-12, "{n} steps");
        }
    }
}
