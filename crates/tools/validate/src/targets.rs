//! Deposition on curved targets against closed forms: a point source on the axis of a
//! cylindrical shell, and at the centre of a triangulated sphere section.
//!
//! A point source emitting `n` particles of total volume `V` uniformly over the solid angle Ω of
//! a cone puts on a surface element `dA`, seen at distance ρ with the angle γ between the ray and
//! the surface's normal, the solid angle `dΩ = dA cos γ / ρ²`, so the thickness
//! `t = V cos γ / (Ω ρ²)`. From the axis of a cylinder of radius R, a ray at elevation ψ from the
//! plane across the axis meets the shell at ρ = R / cos ψ with γ = ψ: `t = V cos³ψ / (Ω R²)`, the
//! cos³ law of a flat plate with the radius for the height. On a sphere section from its centre,
//! each triangle collects the share of the cone's solid angle it subtends.

use super::checks::run;
use glam::DVec3;
use spraysim_engine::Simulation;
use spraysim_engine::collision::Triangle;
use spraysim_engine::deposit::{DepositSurface, MeshSurface, Surface};
use spraysim_scenario::Scenario;
use spraysim_scenario::scenes::scenario;
use std::f64::consts::PI;

/// A simulated deposit against its closed form, in bins.
#[derive(Clone, Debug)]
pub struct CurvedLaw {
    /// Bin centres: the angle from the cone's axis, degrees.
    pub angles: Vec<f64>,
    /// Mean simulated thickness per bin, m.
    pub simulated: Vec<f64>,
    /// Closed form over the same cells, m.
    pub closed_form: Vec<f64>,
    /// χ² of simulated against closed form (Poisson errors).
    pub chi2: f64,
    /// Particles emitted.
    pub emitted: u64,
    /// Volume in the target's map (Σ thickness × area) against the volume emitted, minus one.
    pub volume_error: f64,
}

/// Half-angle of both sources' cones, degrees.
const HALF_DEG: f64 = 40.0;

/// Width of the bins in angle from the cone's axis, degrees.
const BIN_DEG: f64 = 4.0;

/// The shell of [`shell_cos3`]: a 0.5 m cylinder along y, 1.6 m long, seen from inside, with
/// a point nozzle on its axis spraying along +x; no gravity, no rebound.
pub fn shell_scene(particles: f64) -> Scenario {
    let text = format!(
        r#"
        [simulation]
        duration = 0.15
        gravity = [0.0, 0.0, 0.0]
        [process.impact]
        rebound_model = "never"
        [process.slump]
        interval = 0.0
        [emitter]
        shape = "point"
        direction = "uniform_solid_angle"
        cone_angle = {cone}
        speed = [20.0, 20.0]
        spawn_rate = {rate}
        [[nozzle.waypoints]]
        time = 0.0
        position = [0.0, 0.0, 0.0]
        axis = [1.0, 0.0, 0.0]
        [[nozzle.waypoints]]
        time = 0.1
        position = [0.0, 0.0, 0.0]
        axis = [1.0, 0.0, 0.0]
        spray = false
        [[target]]
        name = "shell"
        shape = "cylinder"
        center = [0.0, 0.0, 0.0]
        axis = [0.0, 1.0, 0.0]
        radius = 0.5
        length = 1.6
        reference = [1.0, 0.0, 0.0]
        angles = [-180.0, 180.0]
        resolution = [360, 160]
        splat_radius = 0.0 # each particle in the cell it strikes: the law is the density per cell
        "#,
        cone = 2.0 * HALF_DEG,
        rate = particles / 0.1,
    );
    scenario(&text, "shell cos³ law")
}

/// Bins the cells of `surface` by the angle of their centre's direction from the cone's axis
/// (+x from the origin), comparing the mean thickness with `law` at the same centres; a bin's
/// error is its expected mean over the square root of its expected particles, `n` times the
/// ring's share of the cone's solid angle.
fn binned(surface: &impl DepositSurface, law: impl Fn(u32) -> f64, n: f64) -> CurvedLaw {
    let half = HALF_DEG.to_radians();
    // Rings clear of the cone's edge by one bin.
    let bins = (HALF_DEG / BIN_DEG) as usize - 1;
    let (mut sim, mut model, mut area) = (vec![0.0; bins], vec![0.0; bins], vec![0.0; bins]);
    let t = surface.thickness();
    for c in 0..t.len() as u32 {
        let dir = surface.point_above(c, 0.0).normalize();
        let k = (dir.x.clamp(-1.0, 1.0).acos().to_degrees() / BIN_DEG) as usize;
        if k < bins {
            let a = surface.cell_area(c);
            sim[k] += t[c as usize] * a;
            model[k] += law(c) * a;
            area[k] += a;
        }
    }
    let mut chi2 = 0.0;
    for k in 0..bins {
        let (lo, hi) = ((k as f64 * BIN_DEG).to_radians(), ((k + 1) as f64 * BIN_DEG).to_radians());
        let expected = n * (lo.cos() - hi.cos()) / (1.0 - half.cos());
        chi2 += ((sim[k] - model[k]) / (model[k] / expected.sqrt())).powi(2);
    }
    CurvedLaw {
        angles: (0..bins).map(|k| (k as f64 + 0.5) * BIN_DEG).collect(),
        simulated: sim.iter().zip(&area).map(|(s, a)| s / a).collect(),
        closed_form: model.iter().zip(&area).map(|(s, a)| s / a).collect(),
        chi2,
        emitted: n as u64,
        volume_error: 0.0,
    }
}

/// Sprays `particles` from the axis of [`shell_scene`] and compares the unrolled map with
/// `t = V cos³ψ / (Ω R²)` inside the cone.
pub fn shell_cos3(particles: f64, threads: usize) -> CurvedLaw {
    let sim = run(&shell_scene(particles), threads);
    let m = sim.metrics();
    let shell = &sim.targets()[0].surface;
    let (r, half) = (0.5, HALF_DEG.to_radians());
    let omega = 2.0 * PI * (1.0 - half.cos());
    let v = m.targets[0].stuck.volume;
    let law = |c: u32| {
        let p = shell.point_above(c, 0.0);
        let dir = p.normalize();
        let cos_psi = r / p.length();
        if dir.x >= half.cos() { v * cos_psi.powi(3) / (omega * r * r) } else { 0.0 }
    };
    let mut out = binned(shell, law, m.emitted.count as f64);
    out.volume_error = shell.volume() / m.emitted.volume - 1.0;
    out
}

/// Triangles of a sphere of radius `r` about the origin, from the +x pole out to `cap` (rad)
/// from it, in rings of `ring` (rad) and sectors of `sector` (rad), facing the centre.
pub fn sphere_section(r: f64, cap: f64, ring: f64, sector: f64) -> Vec<Triangle> {
    let point = |polar: f64, azimuth: f64| {
        let (s, c) = polar.sin_cos();
        DVec3::new(c, s * azimuth.cos(), s * azimuth.sin()) * r
    };
    let (rings, sectors) = ((cap / ring).round() as usize, (2.0 * PI / sector).round() as usize);
    let mut out = Vec::new();
    for i in 0..rings {
        let (p0, p1) = (i as f64 * cap / rings as f64, (i + 1) as f64 * cap / rings as f64);
        for j in 0..sectors {
            let (a0, a1) = (j as f64 * 2.0 * PI / sectors as f64, (j + 1) as f64 * 2.0 * PI / sectors as f64);
            let (a, b, c, d) = (point(p0, a0), point(p1, a0), point(p1, a1), point(p0, a1));
            // Corners ordered so that the right-handed normal points to the centre.
            for t in [Triangle::new(a, c, b), Triangle::new(a, d, c)].into_iter().flatten() {
                out.push(t);
            }
        }
    }
    out
}

/// The solid angle a triangle subtends from the origin, sr (Van Oosterom & Strackee 1983).
pub fn solid_angle(t: &Triangle) -> f64 {
    let [a, b, c] = t.corners;
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}

/// Sprays `particles` from the centre of a triangulated sphere section (0.5 m radius, 60°
/// cap, rings of 3° and sectors of 6°) and compares each triangle's thickness with the share of
/// the cone's solid angle it subtends: `t = V Ω_tri / (Ω A_tri)`.
pub fn sphere_cos3(particles: f64, threads: usize) -> CurvedLaw {
    let triangles = sphere_section(0.5, 60f64.to_radians(), 3f64.to_radians(), 6f64.to_radians());
    let mut config = shell_scene(particles).config();
    // A mesh built here rather than read from a file: the mesh surface is what is checked.
    let mesh = MeshSurface::new(triangles).unwrap_or_else(|e| panic!("a valid mesh: {e}"));
    config.targets[0].surface = Surface::Mesh(mesh);
    let mut sim = Simulation::new(config).unwrap_or_else(|e| panic!("built-in scene: {e}"));
    let _ = sim.set_threads(threads);
    sim.run(|_| {});
    let m = sim.metrics();
    let surface = &sim.targets()[0].surface;
    let Surface::Mesh(mesh) = surface else { unreachable!("set above") };
    let half = HALF_DEG.to_radians();
    let omega = 2.0 * PI * (1.0 - half.cos());
    let v = m.targets[0].stuck.volume;
    let inside = |t: &Triangle| t.corners.iter().all(|c| c.normalize().x >= half.cos());
    let law = |c: u32| {
        let t = &mesh.triangles()[c as usize];
        // Triangles across the cone's edge lie in the outer, excluded bins.
        if inside(t) { v * solid_angle(t) / (omega * t.area()) } else { 0.0 }
    };
    let mut out = binned(surface, law, m.emitted.count as f64);
    out.volume_error = surface.volume() / m.emitted.volume - 1.0;
    out
}
