//! Motion between impacts: gravity and optional quadratic drag, advanced at a fixed time step;
//! or, for droplets in a gun's air, the drag that carries them with it ([`air`]).

pub mod air;

pub use air::{AirFlow, DragLaw, Droplet, JetFrame, Wall};
use glam::DVec3;

/// Standard gravity along −z, m/s².
pub const GRAVITY: DVec3 = DVec3::new(0.0, 0.0, -9.81);

/// Time-stepping scheme.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum Integrator {
    /// Forward (explicit) Euler, as in the paper: `x += v·Δt; v += a(v)·Δt`.
    #[default]
    Euler,
    /// Semi-implicit (symplectic) Euler: `v += a(v)·Δt; x += v·Δt`.
    SemiImplicitEuler,
    /// Exact ballistic flight `x + v τ + ½ g τ²`, with exact impact times on the parabola (no
    /// impact is missed at any Δt). Gravity only: refused together with drag, which has no
    /// closed form.
    Exact,
}

/// Forces acting on a particle in flight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion {
    /// Gravitational acceleration, m/s².
    pub gravity: DVec3,
    /// Quadratic drag coefficient `k` in `a = −k |v| v`, 1/m.
    pub drag: f64,
    /// Time-stepping scheme that advances positions and velocities over a step.
    pub integrator: Integrator,
    /// The gun's air, which droplets from the nozzle feel through drag (`None`: still air).
    /// Each step of a droplet in it is then the exact solution for the air held over the step
    /// (see [`air`]), with either Euler integrator; the exact integrator has no closed form
    /// through moving air and is refused with it.
    pub air: Option<AirFlow>,
}

impl Motion {
    /// Acceleration at velocity `v`, m/s².
    #[inline]
    pub fn acceleration(&self, v: DVec3) -> DVec3 {
        if self.drag == 0.0 { self.gravity } else { self.gravity - self.drag * v.length() * v }
    }

    /// Advances position `x` (m) and velocity `v` (m/s) by `dt` (s); returns the new pair.
    #[inline]
    pub fn advance(&self, x: DVec3, v: DVec3, dt: f64) -> (DVec3, DVec3) {
        let a = self.acceleration(v);
        match self.integrator {
            Integrator::Euler => (x + v * dt, v + a * dt),
            Integrator::SemiImplicitEuler => {
                let v1 = v + a * dt;
                (x + v1 * dt, v1)
            }
            Integrator::Exact => (x + v * dt + 0.5 * a * dt * dt, v + a * dt),
        }
    }
}
