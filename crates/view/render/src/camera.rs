//! Where a view is taken from: a perspective camera, presets that frame the whole scene, and
//! an orbit for interactive use.

use crate::scene::Framing;
use glam::{DMat4, DVec3, Mat4};
use spraysim::scenario::ViewPreset;

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position, m.
    pub eye: DVec3,
    /// Point looked at, m.
    pub target: DVec3,
    /// Direction that is up in the image (need not be perpendicular to the view).
    pub up: DVec3,
    /// Vertical field of view, rad.
    pub fov_y: f64,
}

/// Share of the image the framed scene may fill along its tighter side.
const FILL: f64 = 0.9;

impl Camera {
    /// Unit vectors of the view: right, up (in the image) and forward (into the scene).
    pub fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let fwd = (self.target - self.eye).normalize_or(DVec3::X);
        let mut right = fwd.cross(self.up);
        if right.length_squared() < 1e-12 {
            right = fwd.cross(fwd.any_orthonormal_vector());
        }
        let right = right.normalize();
        (right, right.cross(fwd), fwd)
    }

    /// Near and far clipping distances, m, for a scene of bounds `framing`.
    pub fn depth_range(&self, framing: &Framing) -> (f64, f64) {
        let centre = (framing.min + framing.max) / 2.0;
        let radius = (framing.max - framing.min).length() / 2.0 + 1.0;
        let far = (self.eye - centre).length() + 4.0 * radius;
        (0.02, far.max(1.0))
    }

    /// The view-projection matrix for an image of `aspect` (width / height), clipping at
    /// `near` and `far` (m); wgpu's clip space (depth 0..1).
    pub fn view_proj(&self, aspect: f64, (near, far): (f64, f64)) -> Mat4 {
        let (_, up, _) = self.basis();
        let view = DMat4::look_at_rh(self.eye, self.target, up);
        let proj = DMat4::perspective_rh(self.fov_y, aspect.max(1e-6), near, far);
        (proj * view).as_mat4()
    }

    /// Pixel coordinates `(x right, y down)` of `p` (m) in an image of `width × height` px, or
    /// `None` when `p` is behind the eye.
    pub fn project(&self, p: DVec3, width: u32, height: u32) -> Option<(f64, f64)> {
        let (right, up, fwd) = self.basis();
        let d = p - self.eye;
        let z = d.dot(fwd);
        if z <= 1e-9 {
            return None;
        }
        let t = (self.fov_y / 2.0).tan();
        let aspect = f64::from(width) / f64::from(height);
        let (x, y) = (d.dot(right) / (z * t * aspect), d.dot(up) / (z * t));
        Some(((x + 1.0) / 2.0 * f64::from(width), (1.0 - y) / 2.0 * f64::from(height)))
    }

    /// The camera of `preset` for a scene of bounds `framing`, with vertical field of view
    /// `fov_y` (rad), for an image of `aspect` (width / height): every preset but
    /// [`ViewPreset::Follow`] looks at the centre of the bounds from the distance at which all
    /// of them fit in the image.
    pub fn preset(preset: ViewPreset, framing: &Framing, fov_y: f64, aspect: f64) -> Camera {
        let (front, side) = directions(framing.front);
        let (dir, up) = match preset {
            ViewPreset::Front => (front, DVec3::Z),
            ViewPreset::Side => (side, DVec3::Z),
            ViewPreset::Top => (DVec3::Z, if front.z.abs() > 0.99 { DVec3::Y } else { -front }),
            ViewPreset::Iso => ((front + side * 0.55 + DVec3::Z * 0.5).normalize(), DVec3::Z),
            ViewPreset::Follow => {
                let a = framing.axis;
                let (_, height) = directions(-a);
                let eye = framing.nozzle - a * 0.8 + height * 0.35;
                let target = framing.nozzle + a * framing.aim.min(5.0);
                return Camera { eye, target, up: DVec3::Z, fov_y: fov_y.max(50f64.to_radians()) };
            }
        };
        let up = if dir.cross(up).length_squared() < 1e-6 { dir.any_orthonormal_vector() } else { up };
        fit(framing, dir, up, fov_y, aspect)
    }
}

/// The horizontal front direction (`front` with its vertical part kept only when it is nearly
/// vertical) and the direction to its right, both unit.
fn directions(front: DVec3) -> (DVec3, DVec3) {
    let front = front.normalize_or(DVec3::NEG_X);
    if front.z.abs() > 0.99 {
        // A floor or a ceiling: its front is above or below it, its side along x.
        return (front, DVec3::X);
    }
    let side = front.cross(DVec3::Z).normalize();
    (front, side)
}

/// The camera looking along `-dir` at the centre of the bounds from the distance at which
/// every corner of them lies within the image.
fn fit(framing: &Framing, dir: DVec3, up: DVec3, fov_y: f64, aspect: f64) -> Camera {
    let centre = (framing.min + framing.max) / 2.0;
    let probe = Camera { eye: centre + dir, target: centre, up, fov_y };
    let (right, up_img, fwd) = probe.basis();
    let tan_v = (fov_y / 2.0).tan() * FILL;
    let tan_h = tan_v * aspect;
    let mut distance: f64 = 0.1;
    for &p in &framing.points {
        let rel = p - centre;
        let depth = rel.dot(fwd);
        distance =
            distance.max(rel.dot(right).abs() / tan_h - depth).max(rel.dot(up_img).abs() / tan_v - depth);
    }
    Camera { eye: centre + dir * distance, target: centre, up, fov_y }
}

/// An interactive camera: it circles a target point, z up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Point circled, m.
    pub target: DVec3,
    /// Angle of the eye about z from +x, rad.
    pub yaw: f64,
    /// Angle of the eye above the horizontal, rad (within ±89°).
    pub pitch: f64,
    /// Distance from the eye to the target, m.
    pub distance: f64,
    /// Vertical field of view, rad.
    pub fov_y: f64,
}

/// Highest pitch an orbit takes, rad: just short of straight down, where yaw is undefined.
const MAX_PITCH: f64 = 89.0 * std::f64::consts::PI / 180.0;

impl Orbit {
    /// The orbit whose camera is `c` (its up direction becomes z).
    pub fn from_camera(c: &Camera) -> Orbit {
        let d = c.eye - c.target;
        let distance = d.length().max(1e-3);
        let pitch = (d.z / distance).clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH);
        // Straight above: keep the camera's image-up as the direction away from the eye.
        let yaw =
            if d.truncate().length() < 1e-9 * distance { (-c.up.y).atan2(-c.up.x) } else { d.y.atan2(d.x) };
        Orbit { target: c.target, yaw, pitch, distance, fov_y: c.fov_y }
    }

    /// The camera of this orbit.
    pub fn camera(&self) -> Camera {
        let (sp, cp) = self.pitch.sin_cos();
        let (sy, cy) = self.yaw.sin_cos();
        let eye = self.target + DVec3::new(cp * cy, cp * sy, sp) * self.distance;
        Camera { eye, target: self.target, up: DVec3::Z, fov_y: self.fov_y }
    }

    /// Turns the eye about the target by `d_yaw` and `d_pitch` (rad).
    pub fn rotate(&mut self, d_yaw: f64, d_pitch: f64) {
        self.yaw += d_yaw;
        self.pitch = (self.pitch + d_pitch).clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Moves the target (and the eye with it) by `dx`, `dy` image heights right and up.
    pub fn pan(&mut self, dx: f64, dy: f64) {
        let (right, up, _) = self.camera().basis();
        let scale = 2.0 * self.distance * (self.fov_y / 2.0).tan();
        self.target += (right * dx + up * dy) * scale;
    }

    /// Moves the eye towards the target by the factor `factor` (below 1 closer, above 1 away).
    pub fn zoom(&mut self, factor: f64) {
        self.distance = (self.distance * factor).clamp(0.05, 1e4);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn framing() -> Framing {
        let (min, max) = (DVec3::new(-1.0, -1.0, 0.0), DVec3::new(0.0, 1.0, 2.0));
        Framing {
            min,
            max,
            points: (0..8)
                .map(|i| {
                    let c = |bit: usize, lo: f64, hi: f64| if i & bit == 0 { lo } else { hi };
                    DVec3::new(c(1, min.x, max.x), c(2, min.y, max.y), c(4, min.z, max.z))
                })
                .collect(),
            front: DVec3::NEG_X,
            nozzle: DVec3::new(-1.0, 0.0, 1.0),
            axis: DVec3::X,
            aim: 1.0,
        }
    }

    #[test]
    fn presets_keep_every_corner_inside_the_image() {
        let f = framing();
        for preset in [ViewPreset::Front, ViewPreset::Side, ViewPreset::Top, ViewPreset::Iso] {
            let c = Camera::preset(preset, &f, 40f64.to_radians(), 16.0 / 9.0);
            for i in 0..8 {
                let p = DVec3::new(
                    if i & 1 == 0 { f.min.x } else { f.max.x },
                    if i & 2 == 0 { f.min.y } else { f.max.y },
                    if i & 4 == 0 { f.min.z } else { f.max.z },
                );
                let (x, y) = c.project(p, 1280, 720).expect("in front of the eye");
                assert!((0.0..=1280.0).contains(&x) && (0.0..=720.0).contains(&y), "{preset:?}: {x}, {y}");
            }
        }
    }

    #[test]
    fn the_front_view_looks_at_the_sprayed_side_and_an_orbit_keeps_the_camera() {
        let c = Camera::preset(ViewPreset::Front, &framing(), 0.7, 1.5);
        assert!(c.eye.x < -1.0, "{c:?}");
        let o = Orbit::from_camera(&c);
        let back = o.camera();
        assert!((back.eye - c.eye).length() < 1e-9 && (back.target - c.target).length() < 1e-12);
    }

    #[test]
    fn projection_agrees_with_the_matrix() {
        let c = Camera::preset(ViewPreset::Iso, &framing(), 0.7, 2.0);
        let m = c.view_proj(2.0, (0.02, 100.0));
        let p = DVec3::new(-0.3, 0.4, 1.2);
        let clip = m * p.as_vec3().extend(1.0);
        let (nx, ny) = (f64::from(clip.x / clip.w), f64::from(clip.y / clip.w));
        let (x, y) = c.project(p, 200, 100).expect("visible");
        assert!(((nx + 1.0) * 100.0 - x).abs() < 1e-3 && ((1.0 - ny) * 50.0 - y).abs() < 1e-3);
    }
}
