//! What happens when a particle strikes a surface: stick or rebound (the paper's stochastic
//! adhesion model), and the rebound's direction and speed.

use super::ReboundLaw;
use glam::DVec3;
use rand::Rng;
use std::f64::consts::TAU;
use std::sync::Arc;

/// One impact, as the laws of the impact stage see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactSite {
    /// Incoming velocity, m/s.
    pub velocity: DVec3,
    /// Unit normal of the surface struck (the layer's, on a deposit), facing the particle: the
    /// rebound reflects about it.
    pub normal: DVec3,
    /// Angle of incidence θ between the incoming path and the surface's normal, rad, in
    /// `[0, π/2]`: on a deposit, the bare surface's normal (see [`ImpactSite::incidence_on`]).
    pub theta: f64,
    /// Thickness of the deposit under the impact, m (averaged over the model's
    /// `cushion_radius`); `None` off the receiving side of a deposit surface (obstacles, backs
    /// of targets).
    pub layer: Option<f64>,
    /// What the particle is made of, as a uniform draw in `[0, 1)` from its own random stream:
    /// the same at every impact of the particle (a law maps it to mortar or a grain size).
    pub material: f64,
    /// Whether the particle has rebounded before.
    pub bounced: bool,
}

impl ImpactSite {
    /// The same impact with θ measured against unit `normal` instead: on a deposit, the bare
    /// surface's. The field's rebound-versus-angle curves are measured against the surface
    /// sprayed and already include the fresh layer's own roughness, which a particle model
    /// resolves only as the noise of its particles (so that a slope read from the layer would
    /// make rebound depend on the particle size).
    pub fn incidence_on(self, normal: DVec3) -> ImpactSite {
        let speed = self.velocity.length();
        let cos = if speed > 0.0 { (self.velocity.dot(normal) / speed).abs().min(1.0) } else { 1.0 };
        ImpactSite { theta: cos.acos(), ..self }
    }
}

/// Impact parameters of one surface.
#[derive(Clone, Debug)]
pub struct ImpactModel {
    /// Anti-adhesion factor α (dimensionless, `[0, 1]`).
    pub alpha: f64,
    /// Rebound law p_r.
    pub rebound: Arc<dyn ReboundLaw>,
    /// Coefficient of restitution: rebound speed / impact speed (dimensionless, `[0, 1]`).
    pub restitution: f64,
    /// Half-angle of the scatter cone about the specular direction, rad.
    pub scatter: f64,
    /// A rebound slower than this (m/s) comes to rest and sticks, where the surface can hold it.
    pub rest_speed: f64,
    /// Steepest surface (angle of its normal from +z, rad) on which a slow rebound can rest.
    pub rest_max_slope: f64,
    /// Radius over which the layer under an impact is averaged, m (0: the struck cell): a
    /// cushion is a layer, not one particle's splat.
    pub cushion_radius: f64,
}

/// Outcome of one impact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outcome {
    /// The particle adheres where it hit: it becomes part of the layer.
    Stick,
    /// The particle rebounded too slowly to leave and lies where it hit, loose, on a surface
    /// that can hold it: material on the surface, but not in place in the layer.
    Rest,
    /// The particle leaves with this velocity (m/s).
    Rebound(DVec3),
}

impl ImpactModel {
    /// `P(rebound) = α · p_r`, clamped to `[0, 1]`.
    pub fn rebound_probability(&self, site: &ImpactSite) -> f64 {
        (self.alpha * self.rebound.probability(site)).clamp(0.0, 1.0)
    }

    /// The impact site of a particle with velocity `v` (m/s) on a surface with unit `normal`
    /// facing it, over a layer of `layer` (m; `None` off deposits), made of `material`, having
    /// `bounced` before or not.
    pub fn site(v: DVec3, normal: DVec3, layer: Option<f64>, material: f64, bounced: bool) -> ImpactSite {
        let speed = v.length();
        let cos_theta = if speed > 0.0 { (-v.dot(normal) / speed).clamp(0.0, 1.0) } else { 1.0 };
        ImpactSite { velocity: v, normal, theta: cos_theta.acos(), layer, material, bounced }
    }

    /// Decides the outcome of an impact at `site`. Draws from `rng` in a fixed order (decision,
    /// then scatter), so the outcome depends only on the particle's own stream.
    pub fn resolve<R: Rng>(&self, site: &ImpactSite, rng: &mut R) -> Outcome {
        let (v, normal) = (site.velocity, site.normal);
        let speed = v.length();
        let u: f64 = rng.random();
        if u >= self.rebound_probability(site) {
            return Outcome::Stick;
        }
        let out_speed = speed * self.restitution;
        if out_speed < self.rest_speed && normal.z >= self.rest_max_slope.cos() {
            return Outcome::Rest;
        }
        // Specular reflection; `min(0)` keeps a grazing particle from being turned inwards.
        let reflected = v - 2.0 * v.dot(normal).min(0.0) * normal;
        let dir = scatter(reflected.normalize_or(normal), self.scatter, rng.random(), rng.random());
        // Scatter never sends a particle into the surface: mirror such a direction back out.
        let dir = if dir.dot(normal) < 0.0 { dir - 2.0 * dir.dot(normal) * normal } else { dir };
        Outcome::Rebound(dir * out_speed)
    }
}

/// A unit direction within `half_angle` (rad) of unit `axis`, uniform over that cone's solid
/// angle, from two uniform variates in `[0, 1)`.
pub fn scatter(axis: DVec3, half_angle: f64, u1: f64, u2: f64) -> DVec3 {
    if half_angle <= 0.0 {
        return axis;
    }
    let cos_t = 1.0 - u1 * (1.0 - half_angle.cos());
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = TAU * u2;
    let (a, b) = axis.any_orthonormal_pair();
    (axis * cos_t + (a * phi.cos() + b * phi.sin()) * sin_t).normalize()
}
