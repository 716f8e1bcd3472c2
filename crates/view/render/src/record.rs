//! Rendering a run as it goes: the stills and the animation a scenario's `[output] render`
//! (or `spraysim render`) asks for, as files to write with the run's outputs.
//!
//! A [`Recorder`] is shown the simulation before the first step and after every step
//! ([`Recorder::observe`]); it renders whenever a requested time is reached (the nearest step)
//! and, at the end ([`Recorder::finish`]), the `end` stills, then encodes the animation's
//! frames as an animated GIF, and as MP4 when `ffmpeg` is on the `PATH`.

use crate::camera::Camera;
use crate::gpu::{GpuOptions, Offscreen};
use crate::overlay;
use crate::scene::{Scene, SceneOptions};
use crate::{RenderCamera, RenderError, RenderParams, RenderTime};
use glam::DVec3;
use image::RgbaImage;
use spraysim::Simulation;
use spraysim::scenario::Scenario;
use std::process::Command;

/// Widest GIF frame, px: animations stay small enough for a README.
const GIF_WIDTH: u32 = 640;

/// Files made by a recording, and remarks for the user.
#[derive(Debug, Default)]
pub struct Recording {
    /// `(path relative to the output directory, contents)`.
    pub files: Vec<(String, Vec<u8>)>,
    /// What could not be made and why (no `ffmpeg`, say).
    pub notes: Vec<String>,
}

/// Renders the views of one run.
pub struct Recorder {
    params: RenderParams,
    view: Offscreen,
    options: SceneOptions,
    /// Requested still times not yet taken, ascending, s.
    stills: Vec<f64>,
    /// Animation frame times not yet taken, ascending, s.
    frame_times: Vec<f64>,
    frames_taken: usize,
    gif: Vec<RgbaImage>,
    recording: Recording,
    dt: f64,
}

impl Recorder {
    /// A recorder of `params` for a run of `scenario`; fails now, before the run, when no
    /// graphics adapter can be opened or a setting is out of range.
    pub fn new(
        scenario: &Scenario,
        params: &RenderParams,
        gpu: &GpuOptions,
    ) -> Result<Recorder, RenderError> {
        let duration = scenario.simulation().duration;
        params
            .check(duration)
            .map_err(|(field, message)| RenderError::Settings(format!("`{field}` {message}")))?;
        let view = Offscreen::new(gpu, params.size[0], params.size[1])?;
        let mut stills: Vec<f64> = params
            .at
            .iter()
            .filter_map(|t| if let RenderTime::At(t) = t { Some(*t) } else { None })
            .collect();
        stills.sort_by(f64::total_cmp);
        stills.dedup();
        let n = params.frames as usize;
        let frame_times = (0..n).map(|k| duration * (k + 1) as f64 / n as f64).collect();
        Ok(Recorder {
            params: params.clone(),
            view,
            options: SceneOptions::for_scenario(scenario).with_render(params),
            stills,
            frame_times,
            frames_taken: 0,
            gif: Vec::new(),
            recording: Recording::default(),
            dt: scenario.simulation().dt,
        })
    }

    /// The adapter in use.
    pub fn describe(&self) -> String {
        self.view.describe()
    }

    /// Steps from `sim`'s present to the one at whose end the next still or frame is due, if
    /// any: a run that advances several steps at a time stops there.
    pub fn steps_to_next(&self, sim: &Simulation) -> Option<u64> {
        let due = match (self.stills.first().copied(), self.frame_times.first().copied()) {
            (Some(a), Some(b)) => a.min(b),
            (a, b) => a.or(b)?,
        };
        // A view is drawn at the first step end within half a step of its time.
        Some(((due - sim.time()) / self.dt - 0.5).ceil().max(1.0) as u64)
    }

    /// Renders what is due at `sim`'s time: call it before the first step and after each (or
    /// after each run of steps that stops at [`Recorder::steps_to_next`]).
    pub fn observe(&mut self, sim: &Simulation) -> Result<(), RenderError> {
        let due = sim.time() + self.dt / 2.0;
        if self.stills.first().is_none_or(|&t| t > due) && self.frame_times.first().is_none_or(|&t| t > due) {
            return Ok(());
        }
        let img = self.render(sim)?;
        while self.stills.first().is_some_and(|&t| t <= due) {
            let t = self.stills.remove(0);
            self.push_png(format!("view_{t:.3}s.png"), &img)?;
        }
        while self.frame_times.first().is_some_and(|&t| t <= due) {
            self.frame_times.remove(0);
            self.push_frame(&img)?;
        }
        Ok(())
    }

    /// Drops the stills and frames due before `time` (s), which a run resumed at `time` cannot
    /// draw from the state they show.
    pub fn skip_before(&mut self, time: f64) {
        let due = time - self.dt / 2.0;
        self.stills.retain(|&t| t >= due);
        self.frame_times.retain(|&t| t >= due);
    }

    /// Drops the stills and frames due after `time` (s), which a run stopped at `time` never
    /// reached: an interrupted run's views show only what it simulated.
    pub fn drop_after(&mut self, time: f64) {
        let due = time + self.dt / 2.0;
        self.stills.retain(|&t| t <= due);
        self.frame_times.retain(|&t| t <= due);
    }

    /// Takes the stills and frames still due (the `end` stills among them) from the final
    /// state `sim`, and encodes the animation.
    pub fn finish(mut self, sim: &Simulation) -> Result<Recording, RenderError> {
        let pending = !self.stills.is_empty() || !self.frame_times.is_empty();
        let end = self.params.at.contains(&RenderTime::End);
        if pending || end {
            let img = self.render(sim)?;
            for t in std::mem::take(&mut self.stills) {
                self.push_png(format!("view_{t:.3}s.png"), &img)?;
            }
            for _ in std::mem::take(&mut self.frame_times) {
                self.push_frame(&img)?;
            }
            if end {
                self.push_png("view_end.png".into(), &img)?;
            }
        }
        if self.frames_taken > 0 {
            self.encode_animation(sim.config().duration)?;
        }
        Ok(self.recording)
    }

    /// The camera for `scene`.
    fn camera(&self, scene: &Scene) -> Camera {
        let fov = self.params.fov.to_radians();
        let [w, h] = self.params.size;
        match self.params.camera {
            RenderCamera::Preset(p) => Camera::preset(p, &scene.framing, fov, f64::from(w) / f64::from(h)),
            RenderCamera::Custom { eye, target } => Camera {
                eye: DVec3::from_array(eye),
                target: DVec3::from_array(target),
                up: DVec3::Z,
                fov_y: fov,
            },
        }
    }

    /// `sim` now, annotated.
    fn render(&mut self, sim: &Simulation) -> Result<RgbaImage, RenderError> {
        let scene = Scene::build(sim, &self.options);
        let camera = self.camera(&scene);
        let mut img = self.view.render(&scene, &camera)?;
        overlay::annotate(&mut img, &scene);
        Ok(img)
    }

    fn push_png(&mut self, name: String, img: &RgbaImage) -> Result<(), RenderError> {
        let bytes = png(img, &name)?;
        self.recording.files.push((name, bytes));
        Ok(())
    }

    fn push_frame(&mut self, img: &RgbaImage) -> Result<(), RenderError> {
        self.frames_taken += 1;
        self.push_png(format!("frames/frame_{:04}.png", self.frames_taken), img)?;
        let small = if img.width() > GIF_WIDTH {
            let h = (f64::from(img.height()) * f64::from(GIF_WIDTH) / f64::from(img.width())).round() as u32;
            image::imageops::resize(img, GIF_WIDTH, h.max(1), image::imageops::FilterType::Triangle)
        } else {
            img.clone()
        };
        self.gif.push(small);
        Ok(())
    }

    /// The frames as `animation.gif`, and as `animation.mp4` when `ffmpeg` is there; each frame
    /// shows for its share of the run in real time (at least 40 ms).
    fn encode_animation(&mut self, duration: f64) -> Result<(), RenderError> {
        let n = self.frames_taken.max(1) as f64;
        let ms = ((duration / n) * 1e3).clamp(40.0, 1000.0);
        let gif = encode_gif(std::mem::take(&mut self.gif), ms as u32)?;
        self.recording.files.push(("animation.gif".into(), gif));
        match encode_mp4(&self.recording.files, 1e3 / ms) {
            Ok(Some(mp4)) => self.recording.files.push(("animation.mp4".into(), mp4)),
            Ok(None) => self.recording.notes.push(
                "ffmpeg is not on the PATH: no animation.mp4 (the frames and animation.gif are written)"
                    .into(),
            ),
            Err(e) => self.recording.notes.push(format!("ffmpeg failed, no animation.mp4: {e}")),
        }
        Ok(())
    }
}

/// `img` as PNG bytes.
pub fn png(img: &RgbaImage, name: &str) -> Result<Vec<u8>, RenderError> {
    let mut bytes = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut bytes), image::ImageFormat::Png)
        .map_err(|e| RenderError::Encode { what: name.into(), message: e.to_string() })?;
    Ok(bytes)
}

/// `frames` as an endlessly repeating animated GIF, each shown `delay_ms` ms.
pub fn encode_gif(frames: Vec<RgbaImage>, delay_ms: u32) -> Result<Vec<u8>, RenderError> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let err =
        |e: image::ImageError| RenderError::Encode { what: "animation.gif".into(), message: e.to_string() };
    let mut bytes = Vec::new();
    {
        let mut encoder = GifEncoder::new_with_speed(&mut bytes, 10);
        encoder.set_repeat(Repeat::Infinite).map_err(err)?;
        let delay = image::Delay::from_numer_denom_ms(delay_ms, 1);
        encoder
            .encode_frames(frames.into_iter().map(|f| image::Frame::from_parts(f, 0, 0, delay)))
            .map_err(err)?;
    }
    Ok(bytes)
}

/// Whether `ffmpeg` runs.
pub fn ffmpeg_available() -> bool {
    Command::new("ffmpeg").arg("-version").output().is_ok_and(|o| o.status.success())
}

/// The `frames/frame_NNNN.png` among `files` as an H.264 (or the build's default) MP4 at `fps`
/// frames per second, made by `ffmpeg`; `None` when `ffmpeg` is not there.
pub fn encode_mp4(files: &[(String, Vec<u8>)], fps: f64) -> Result<Option<Vec<u8>>, String> {
    if !ffmpeg_available() {
        return Ok(None);
    }
    let dir = std::env::temp_dir().join(format!("spraysim-mp4-{}-{:p}", std::process::id(), files));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let result = (|| {
        for (name, bytes) in files.iter().filter(|(n, _)| n.starts_with("frames/")) {
            std::fs::write(dir.join(name.trim_start_matches("frames/")), bytes).map_err(|e| e.to_string())?;
        }
        let out = dir.join("animation.mp4");
        let o = Command::new("ffmpeg")
            .args(["-y", "-loglevel", "error", "-framerate", &format!("{fps:.3}"), "-i"])
            .arg(dir.join("frame_%04d.png"))
            .args(["-vf", "scale=trunc(iw/2)*2:trunc(ih/2)*2", "-pix_fmt", "yuv420p"])
            .arg(&out)
            .output()
            .map_err(|e| e.to_string())?;
        if !o.status.success() {
            return Err(String::from_utf8_lossy(&o.stderr).trim().to_string());
        }
        std::fs::read(&out).map_err(|e| e.to_string())
    })();
    let _ = std::fs::remove_dir_all(&dir);
    result.map(Some)
}
