//! The window: a side panel of controls and live metrics, and the 3D view drawn by the
//! renderer inside egui's own render pass.

use crate::worker::{Command, Published, Shared, Watched};
use eframe::egui;
use eframe::egui_wgpu::{self, wgpu};
use spraysim::Metrics;
use spraysim::output::heatmap;
use spraysim::scenario::{Colormap, ParticleColoring, ViewPreset};
use spraysim_render::camera::{Camera, Orbit};
use spraysim_render::gpu::Renderer;
use spraysim_render::scene::{Caption, FLYING, Framing, Legend, REBOUNDED, RELEASED};
use spraysim_render::{Field, SceneOptions};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Sender;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// Depth buffer bits asked of eframe (egui-wgpu then gives its pass a `Depth32Float` buffer).
pub const DEPTH_BITS: u8 = 32;

/// Speeds offered, simulated seconds per real second (`None`: as fast as possible).
const SPEEDS: [(Option<f64>, &str); 8] = [
    (Some(0.1), "×0.1"),
    (Some(0.25), "×0.25"),
    (Some(0.5), "×0.5"),
    (Some(1.0), "×1 real time"),
    (Some(2.0), "×2"),
    (Some(5.0), "×5"),
    (Some(10.0), "×10"),
    (None, "as fast as possible"),
];

/// Particles drawn at most, and at least when the GPU is slow.
const MOST_PARTICLES: usize = 4_000_000;
const FEWEST_PARTICLES: usize = 20_000;

/// Closing the window by itself after some frames, with a screenshot (for tests).
pub struct ExitPlan {
    /// Frames to show before closing.
    pub frames: u64,
    /// Where to save the window's image before closing.
    pub screenshot: Option<PathBuf>,
    /// Where the screenshot's outcome is written (the path saved, or why not).
    pub saved: Arc<Mutex<Option<Result<PathBuf, String>>>>,
}

/// What the window last received from the simulation thread.
struct Shown {
    framing: Framing,
    legend: Option<Legend>,
    particles: (ParticleColoring, f64),
    caption: Caption,
    metrics: Arc<Metrics>,
    watched: Watched,
    playing: bool,
    finished: bool,
    achieved: f64,
}

/// The window's state.
pub struct App {
    title: String,
    commands: Sender<Command>,
    shared: Arc<Shared>,
    options: SceneOptions,
    orbit: Option<Orbit>,
    follow: bool,
    shown: Option<Shown>,
    speed: usize,
    /// Smoothed time between continuous frames, s.
    frame_time: f64,
    last_frame: Instant,
    adapter: String,
    exit: Option<ExitPlan>,
    screenshot_asked: bool,
    frame: u64,
    closing: Arc<AtomicBool>,
    /// Width over height of the 3D view.
    aspect: f64,
}

/// The renderer, kept in egui-wgpu's callback resources.
struct ViewGpu(Renderer);

impl App {
    /// The window for `title`, steering the simulation thread through `commands`.
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        title: String,
        options: SceneOptions,
        (commands, shared): (Sender<Command>, Arc<Shared>),
        exit: Option<ExitPlan>,
    ) -> Result<App, String> {
        let rs = cc.wgpu_render_state.as_ref().ok_or("the window is not running on wgpu")?;
        let info = rs.adapter.get_info();
        let depth = egui_wgpu::depth_format_from_bits(DEPTH_BITS, 0);
        let renderer = Renderer::new(&rs.device, rs.target_format, depth, 1);
        rs.renderer.write().callback_resources.insert(ViewGpu(renderer));
        Ok(App {
            title,
            commands,
            shared,
            options,
            orbit: None,
            follow: false,
            shown: None,
            speed: 3,
            frame_time: 0.0,
            last_frame: Instant::now(),
            adapter: format!("{} ({:?})", info.name, info.backend),
            exit,
            screenshot_asked: false,
            frame: 0,
            closing: Arc::new(AtomicBool::new(false)),
            aspect: 1.6,
        })
    }

    fn send(&self, c: Command) {
        let _ = self.commands.send(c);
    }

    /// Takes the latest state from the simulation thread and uploads its scene.
    fn receive(&mut self, frame: &eframe::Frame) {
        let Some(p) = self.shared.latest.lock().ok().and_then(|mut s| s.take()) else { return };
        let Published { scene, metrics, watched, playing, finished, achieved_speed } = p;
        if let Some(rs) = frame.wgpu_render_state()
            && let Some(ViewGpu(r)) = rs.renderer.write().callback_resources.get_mut::<ViewGpu>()
        {
            r.upload(&rs.device, &rs.queue, &scene);
        }
        if self.orbit.is_none() {
            let c = Camera::preset(ViewPreset::Iso, &scene.framing, 40f64.to_radians(), 1.6);
            self.orbit = Some(Orbit::from_camera(&c));
        }
        self.shown = Some(Shown {
            framing: scene.framing,
            legend: scene.legend,
            particles: scene.particle_legend,
            caption: scene.caption,
            metrics,
            watched,
            playing,
            finished,
            achieved: achieved_speed,
        });
    }

    /// Lowers the number of particles drawn while frames are slow, raises it while fast.
    fn adapt(&mut self, continuous: bool) {
        let now = Instant::now();
        let dt = now.duration_since(self.last_frame).as_secs_f64();
        self.last_frame = now;
        if !continuous || dt > 2.0 {
            return;
        }
        self.frame_time = if self.frame_time == 0.0 { dt } else { 0.8 * self.frame_time + 0.2 * dt };
        let in_flight = self.shown.as_ref().map_or(0, |s| s.caption.in_flight);
        let cap = &self.shared.max_particles;
        let current = cap.load(Ordering::Relaxed);
        if self.frame_time > 1.0 / 12.0 && in_flight > FEWEST_PARTICLES {
            let drawn = current.min(in_flight);
            cap.store((drawn * 7 / 10).max(FEWEST_PARTICLES), Ordering::Relaxed);
            self.frame_time = 1.0 / 20.0;
        } else if self.frame_time < 1.0 / 30.0 && current < in_flight {
            cap.store((current + current / 4).min(MOST_PARTICLES), Ordering::Relaxed);
        }
    }

    fn camera(&self) -> Option<Camera> {
        let s = self.shown.as_ref()?;
        if self.follow {
            return Some(Camera::preset(ViewPreset::Follow, &s.framing, 50f64.to_radians(), self.aspect));
        }
        self.orbit.map(|o| o.camera())
    }

    /// Places the camera by `preset` for a view of `aspect`.
    fn preset(&mut self, preset: ViewPreset, aspect: f64) {
        self.follow = preset == ViewPreset::Follow;
        if let Some(s) = &self.shown {
            self.orbit =
                Some(Orbit::from_camera(&Camera::preset(preset, &s.framing, 40f64.to_radians(), aspect)));
        }
    }
}

impl eframe::App for App {
    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        self.frame += 1;
        self.receive(frame);
        let playing = self.shown.as_ref().is_some_and(|s| s.playing);
        self.adapt(playing);
        egui::Panel::left("controls").default_size(290.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| self.controls(ui));
        });
        egui::CentralPanel::default().show(ui, |ui| self.view(ui));
        self.exit_plan(ui.ctx());
        if playing {
            ui.ctx().request_repaint();
        }
    }
}

impl App {
    /// The side panel.
    fn controls(&mut self, ui: &mut egui::Ui) {
        ui.heading(&self.title);
        let (playing, finished) = self.shown.as_ref().map_or((false, false), |s| (s.playing, s.finished));
        ui.horizontal(|ui| {
            if ui.button(if playing { "pause" } else { "play" }).clicked() {
                self.send(Command::Play(!playing));
            }
            if ui.button("step").clicked() {
                self.send(Command::Step);
            }
            if ui.button("restart").clicked() {
                self.send(Command::Restart);
                self.send(Command::Play(true));
            }
        });
        if finished {
            ui.label("the run has reached its duration");
        }
        let before = self.speed;
        egui::ComboBox::from_label("speed").selected_text(SPEEDS[self.speed].1).show_ui(ui, |ui| {
            for (i, (_, name)) in SPEEDS.iter().enumerate() {
                ui.selectable_value(&mut self.speed, i, *name);
            }
        });
        if self.speed != before {
            self.send(Command::Speed(SPEEDS[self.speed].0));
        }
        ui.separator();
        self.camera_buttons(ui);
        ui.separator();
        self.toggles(ui);
        ui.separator();
        self.metrics(ui);
        self.legend(ui);
        ui.separator();
        ui.small(format!("{} · {:.0} ms a frame", self.adapter, 1e3 * self.frame_time));
        ui.small("drag: orbit · right or middle drag: pan · wheel: zoom");
    }

    fn camera_buttons(&mut self, ui: &mut egui::Ui) {
        ui.label("camera");
        ui.horizontal_wrapped(|ui| {
            for (preset, name) in [
                (ViewPreset::Front, "front"),
                (ViewPreset::Side, "side"),
                (ViewPreset::Top, "top"),
                (ViewPreset::Iso, "3/4"),
                (ViewPreset::Follow, "follow nozzle"),
            ] {
                if ui.button(name).clicked() {
                    self.preset(preset, self.aspect);
                }
            }
        });
    }

    fn toggles(&mut self, ui: &mut egui::Ui) {
        let before = self.options.clone();
        let show = &mut self.options.show;
        ui.horizontal_wrapped(|ui| {
            ui.checkbox(&mut show.particles, "particles");
            ui.checkbox(&mut show.obstacles, "obstacles");
            ui.checkbox(&mut show.deposit, "deposit");
            ui.checkbox(&mut show.path, "path");
            ui.checkbox(&mut show.nozzle, "nozzle");
        });
        ui.horizontal(|ui| {
            ui.label("particles by");
            ui.selectable_value(&mut self.options.particles, ParticleColoring::State, "state");
            ui.selectable_value(&mut self.options.particles, ParticleColoring::Speed, "speed");
        });
        ui.horizontal(|ui| {
            ui.label("targets show");
            for (f, name) in [
                (Field::Auto, "auto"),
                (Field::Thickness, "thickness"),
                (Field::Erosion, "erosion"),
                (Field::Coating, "coating"),
            ] {
                ui.selectable_value(&mut self.options.field, f, name);
            }
        });
        ui.add(egui::Slider::new(&mut self.options.point_size, 1.0..=8.0).text("particle px"));
        ui.add(egui::Slider::new(&mut self.options.exaggeration, 0.0..=20.0).text("relief ×"));
        if self.options != before {
            self.send(Command::Options(self.options.clone()));
        }
    }

    fn metrics(&self, ui: &mut egui::Ui) {
        let Some(s) = &self.shown else {
            ui.label("starting…");
            return;
        };
        let m = &s.metrics;
        let pct = |x: Option<f64>| x.map_or("n/a".to_string(), |v| format!("{:.1} %", 100.0 * v));
        egui::Grid::new("metrics").num_columns(2).striped(true).show(ui, |ui| {
            let mut row = |k: &str, v: String| {
                ui.label(k);
                ui.label(v);
                ui.end_row();
            };
            row("time", format!("{:.3} s", s.caption.time));
            row("achieved speed", format!("×{:.2}", s.achieved));
            row("emitted", format!("{}", s.watched.emitted));
            row("in flight", format!("{}", s.caption.in_flight));
            row("rebound ratio", pct(m.rebound_ratio));
            row("transfer efficiency", pct(m.transfer_efficiency));
            row("cohesive failures", format!("{}", s.watched.failures.len()));
            for t in &m.targets {
                row(
                    &format!("{} mean / max", t.name),
                    format!("{:.2} / {:.2} mm", 1e3 * t.thickness.mean, 1e3 * t.thickness.max),
                );
            }
        });
        if s.caption.drawn < s.caption.in_flight && self.options.show.particles {
            ui.colored_label(
                egui::Color32::from_rgb(180, 90, 0),
                format!(
                    "drawing a sample of {} of the {} particles in flight: the GPU cannot keep up with all of them",
                    s.caption.drawn, s.caption.in_flight
                ),
            );
        }
    }

    /// The targets' colour scale and the particles' key.
    fn legend(&self, ui: &mut egui::Ui) {
        let Some(s) = &self.shown else { return };
        if let Some(l) = &s.legend {
            ui.label(&l.label);
            gradient(ui, l.colormap, (0.0, l.max));
        }
        match s.particles {
            (ParticleColoring::State, _) => {
                ui.horizontal(|ui| {
                    for (c, name) in [(FLYING, "in flight"), (REBOUNDED, "rebounded"), (RELEASED, "released")]
                    {
                        ui.colored_label(egui::Color32::from_rgb(c[0], c[1], c[2]), name);
                    }
                });
            }
            (ParticleColoring::Speed, vmax) => {
                ui.label("particle speed [m/s]");
                gradient(ui, Colormap::Turbo, (0.0, vmax));
            }
        }
    }

    /// The 3D view, with the mouse steering the camera.
    fn view(&mut self, ui: &mut egui::Ui) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), egui::Sense::click_and_drag());
        let aspect = f64::from(rect.width() / rect.height().max(1.0));
        if let Some(o) = &mut self.orbit {
            let d = response.drag_delta();
            let h = f64::from(rect.height().max(1.0));
            if response.dragged_by(egui::PointerButton::Primary) {
                o.rotate(-f64::from(d.x) * 0.008, f64::from(d.y) * 0.008);
                self.follow = false;
            } else if response.dragged_by(egui::PointerButton::Secondary)
                || response.dragged_by(egui::PointerButton::Middle)
            {
                o.pan(-f64::from(d.x) / h, f64::from(d.y) / h);
                self.follow = false;
            }
            if response.hovered() {
                let scroll = ui.input(|i| i.smooth_scroll_delta.y);
                if scroll != 0.0 {
                    o.zoom((-f64::from(scroll) * 0.002).exp());
                }
            }
        }
        let bg = spraysim_render::scene::BACKGROUND;
        ui.painter().rect_filled(rect, 0.0, egui::Color32::from_rgb(bg[0], bg[1], bg[2]));
        let (Some(camera), Some(s)) = (self.camera(), &self.shown) else { return };
        let ppp = ui.ctx().pixels_per_point();
        let size = ((rect.width() * ppp).round() as u32, (rect.height() * ppp).round() as u32);
        let callback = ViewCallback { camera, size, depth: camera.depth_range(&s.framing) };
        ui.painter().add(egui_wgpu::Callback::new_paint_callback(rect, callback));
        self.aspect = aspect;
    }

    /// Closes the window after the planned frames, once its screenshot is saved.
    fn exit_plan(&mut self, ctx: &egui::Context) {
        let Some(plan) = &self.exit else { return };
        ctx.request_repaint();
        if self.frame < plan.frames {
            return;
        }
        if let Some(path) = plan.screenshot.clone()
            && !self.screenshot_asked
        {
            self.screenshot_asked = true;
            let saved = plan.saved.clone();
            ctx.request_screenshot(move |img| {
                let [w, h] = img.size;
                let result = image::save_buffer(
                    &path,
                    img.as_raw(),
                    w as u32,
                    h as u32,
                    image::ExtendedColorType::Rgba8,
                )
                .map(|()| path.clone())
                .map_err(|e| format!("{}: {e}", path.display()));
                if let Ok(mut s) = saved.lock() {
                    *s = Some(result);
                }
            });
            return;
        }
        let done = plan.screenshot.is_none() || plan.saved.lock().is_ok_and(|s| s.is_some());
        if done && !self.closing.swap(true, Ordering::SeqCst) {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
    }
}

/// A horizontal colour bar of `map` with its range's ends labelled.
fn gradient(ui: &mut egui::Ui, map: Colormap, (lo, hi): (f64, f64)) {
    let (rect, _) =
        ui.allocate_exact_size(egui::vec2(ui.available_width().min(240.0), 14.0), egui::Sense::hover());
    let n = 64;
    for i in 0..n {
        let c = heatmap::color(map, (f64::from(i) + 0.5) / f64::from(n)).0;
        let x0 = rect.left() + rect.width() * i as f32 / n as f32;
        let x1 = rect.left() + rect.width() * (i + 1) as f32 / n as f32;
        let r = egui::Rect::from_min_max(egui::pos2(x0, rect.top()), egui::pos2(x1 + 0.5, rect.bottom()));
        ui.painter().rect_filled(r, 0.0, egui::Color32::from_rgb(c[0], c[1], c[2]));
    }
    ui.horizontal(|ui| {
        ui.small(format!("{lo:.2}"));
        ui.add_space((rect.width() - 70.0).max(0.0));
        ui.small(format!("{hi:.2}"));
    });
}

/// One frame's draw of the 3D view inside egui's pass.
struct ViewCallback {
    camera: Camera,
    size: (u32, u32),
    depth: (f64, f64),
}

impl egui_wgpu::CallbackTrait for ViewCallback {
    fn prepare(
        &self,
        _device: &wgpu::Device,
        queue: &wgpu::Queue,
        _screen: &egui_wgpu::ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut egui_wgpu::CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(ViewGpu(r)) = resources.get::<ViewGpu>() {
            r.set_view(queue, &self.camera, self.size, self.depth);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &egui_wgpu::CallbackResources,
    ) {
        if let Some(ViewGpu(r)) = resources.get::<ViewGpu>() {
            r.draw(pass);
        }
    }
}
