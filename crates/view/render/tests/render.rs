//! Rendered views checked against the scene's own geometry: known 3D points projected to
//! pixels, not stored images, so that a Mesa update does not break them.
//!
//! They need a graphics adapter. The software one (Mesa's lavapipe, Vulkan) is asked for, so
//! that the pixels do not depend on the machine's GPU; without any adapter the tests say so and
//! pass, except in CI (the `CI` variable set), where `.ci/run` installs Mesa and a missing
//! adapter fails them.

use glam::DVec3;
use image::RgbaImage;
use spraysim::deposit::DepositSurface;
use spraysim::{Scenario, Simulation};
use spraysim_render::gpu::GpuOptions;
use spraysim_render::scene::{BACKGROUND, BARE, FLYING, REBOUNDED};
use spraysim_render::{Camera, Offscreen, Scene, SceneOptions, Show, ViewPreset};

const W: u32 = 640;
const H: u32 = 400;

/// Says in the test output that a test cannot run here, and why. Written straight to the
/// standard error, which the test harness does not capture (it captures `eprintln!`), so that
/// the note shows without `--nocapture`.
fn skip(reason: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipped: {reason}");
}

/// An offscreen view on the software Vulkan driver (GL if Vulkan is missing), one sample per
/// pixel; `None` (with a note) when there is no adapter outside CI.
fn view(samples: u32) -> Option<Offscreen> {
    let mut last = String::new();
    for backends in [wgpu::Backends::VULKAN, wgpu::Backends::GL] {
        match Offscreen::new(&GpuOptions { backends, software: true, samples }, W, H) {
            Ok(v) => return Some(v),
            Err(e) => last = e.to_string(),
        }
    }
    assert!(std::env::var_os("CI").is_none(), "CI must render: {last}");
    skip(&last);
    None
}

/// The default scene for `duration` seconds with its nozzle at `[-1, 0, 1]`, spraying until
/// `spray_end` (s), on a coarse wall (31 mm cells, each struck by many particles): vertex colours
/// are means of the cells around a vertex and the GPU blends them in RGB, so a noisy fine map
/// would show colours between the scale's.
fn scene(duration: f64, spray_end: f64) -> Scenario {
    let text = spraysim::scenario::DEFAULT_SCENE
        .replace("duration = 2.0", &format!("duration = {duration}"))
        .replace("resolution = [1024, 1024]", "resolution = [64, 64]")
        .replace(
            "[nozzle]\nposition = [-1.0, 0.0, 1.0]   # m: 1 m in front of the wall's centre\naxis = [1.0, 0.0, 0.0]        # spraying square onto the wall",
            &format!(
                "[[nozzle.waypoints]]\ntime = 0.0\nposition = [-1.0, 0.0, 1.0]\naxis = [1.0, 0.0, 0.0]\n\
                 [[nozzle.waypoints]]\ntime = {spray_end}\nposition = [-1.0, 0.0, 1.0]\naxis = [1.0, 0.0, 0.0]\nspray = false"
            ),
        );
    Scenario::from_toml(&text, "test scene").expect("valid")
}

fn run_to(sc: &Scenario, t: f64) -> Simulation {
    let mut sim = sc.build().expect("builds");
    while sim.time() < t - 1e-9 {
        sim.step();
    }
    sim
}

fn pixel(img: &RgbaImage, (x, y): (f64, f64)) -> [u8; 4] {
    img.get_pixel((x as u32).min(W - 1), (y as u32).min(H - 1)).0
}

/// How far `c` is from the nearest colour of the viridis scale, and where on it that is.
fn on_scale(c: [u8; 4]) -> (u32, f64) {
    (0..=255)
        .map(|i| {
            let t = f64::from(i) / 255.0;
            let s = spraysim::output::heatmap::color(spraysim::scenario::Colormap::Viridis, t).0;
            ((0..3).map(|k| u32::from(c[k].abs_diff(s[k]))).sum::<u32>(), t)
        })
        .min_by(|a, b| a.0.cmp(&b.0))
        .unwrap_or((u32::MAX, 0.0))
}

#[test]
fn the_deposit_shows_its_colours_where_the_spray_struck_and_the_background_elsewhere() {
    let Some(mut v) = view(1) else { return };
    let sim = run_to(&scene(0.3, 1.0), 0.3);
    let show = Show { particles: false, nozzle: false, path: false, ..Show::default() };
    let s = Scene::build(&sim, &SceneOptions { show, lighting: false, ..SceneOptions::default() });
    let cam = Camera::preset(ViewPreset::Front, &s.framing, 40f64.to_radians(), f64::from(W) / f64::from(H));
    let img = v.render(&s, &cam).expect("renders");
    let wall = &sim.targets()[0].surface;
    let max = wall.thickness().iter().copied().fold(0.0, f64::max);
    assert!(max > 1e-3, "the spray built a layer ({max} m)");
    // Where the axis meets the wall: a deposit colour, at the height of the scale the layer has
    // there. Vertex colours are means of the cells around each vertex, so the layer is judged by
    // its mean over a few cells rather than by its one (noisy) cell.
    let centre = DVec3::new(0.0, 0.0, 1.0);
    let t = wall.mean_thickness(wall.cell_at(0, centre), 0.02);
    let c = pixel(&img, cam.project(centre - DVec3::X * t, W, H).expect("visible"));
    let (distance, level) = on_scale(c);
    assert!(distance <= 12, "{c:?} is a colour of the scale");
    assert!((level - t / max).abs() < 0.2, "{c:?} shows {level}, the layer is at {}", t / max);
    // Near the wall's corners nothing struck: the bare surface.
    for p in [DVec3::new(0.0, 0.9, 1.9), DVec3::new(0.0, -0.9, 0.1)] {
        assert_eq!(pixel(&img, cam.project(p, W, H).expect("visible")), BARE, "at {p}");
    }
    // Above the wall and the image's corners: the background.
    let above = cam.project(DVec3::new(0.0, 0.0, 2.3), W, H).expect("visible");
    for at in [above, (1.0, 1.0), (f64::from(W) - 2.0, 1.0)] {
        assert_eq!(pixel(&img, at), BACKGROUND, "at {at:?}");
    }
}

/// Pixels in the particles' state colours.
fn particle_pixels(img: &RgbaImage) -> usize {
    img.pixels().filter(|p| p.0 == FLYING || p.0 == REBOUNDED).count()
}

#[test]
fn particles_show_mid_spray_and_not_once_the_spray_has_ended_and_settled() {
    let Some(mut v) = view(1) else { return };
    let sc = scene(1.5, 0.2);
    let opts = SceneOptions { lighting: false, ..SceneOptions::default() };
    let aspect = f64::from(W) / f64::from(H);
    let mid = run_to(&sc, 0.1);
    assert!(mid.swarm().alive() > 100);
    let s = Scene::build(&mid, &opts);
    let cam = Camera::preset(ViewPreset::Side, &s.framing, 40f64.to_radians(), aspect);
    let img = v.render(&s, &cam).expect("renders");
    let hidden = Scene::build(
        &mid,
        &SceneOptions { show: Show { particles: false, ..Show::default() }, ..opts.clone() },
    );
    let without = v.render(&hidden, &cam).expect("renders");
    let changed = img.pixels().zip(without.pixels()).filter(|(a, b)| a != b).count();
    assert!(particle_pixels(&img) > 200, "{} particle pixels mid-spray", particle_pixels(&img));
    assert!(changed > 200, "particles change {changed} pixels");
    // A particle in flight lands on its projected pixel (or an occluder's).
    let (position, _, _) = mid.in_flight().next().expect("one in flight");
    assert!(cam.project(position, W, H).is_some());

    let end = run_to(&sc, 1.5);
    assert_eq!(end.swarm().alive(), 0, "everything has settled");
    let s = Scene::build(&end, &opts);
    let img = v
        .render(&s, &Camera::preset(ViewPreset::Side, &s.framing, 40f64.to_radians(), aspect))
        .expect("renders");
    assert_eq!(particle_pixels(&img), 0);
}

#[test]
fn every_preset_frames_the_whole_scene() {
    let Some(mut v) = view(1) else { return };
    let sim = run_to(&scene(0.1, 1.0), 0.1);
    let s = Scene::build(&sim, &SceneOptions::default());
    let aspect = f64::from(W) / f64::from(H);
    for preset in [ViewPreset::Front, ViewPreset::Side, ViewPreset::Top, ViewPreset::Iso] {
        let cam = Camera::preset(preset, &s.framing, 40f64.to_radians(), aspect);
        // Every corner of every target is inside the image…
        for t in sim.targets() {
            for p in t.surface.mesh(false, 4).positions {
                let (x, y) = cam.project(p, W, H).expect("in front of the eye");
                assert!(
                    (0.0..f64::from(W)).contains(&x) && (0.0..f64::from(H)).contains(&y),
                    "{preset:?}: {p} at {x}, {y}"
                );
            }
        }
        // …and nothing drawn touches the image's border.
        let img = v.render(&s, &cam).expect("renders");
        let border =
            (0..W).flat_map(|x| [(x, 0), (x, H - 1)]).chain((0..H).flat_map(|y| [(0, y), (W - 1, y)]));
        for (x, y) in border {
            assert_eq!(img.get_pixel(x, y).0, BACKGROUND, "{preset:?} draws on the border at {x}, {y}");
        }
        let drawn = img.pixels().filter(|p| p.0 != BACKGROUND).count();
        assert!(drawn > (W * H / 20) as usize, "{preset:?}: the scene fills {drawn} pixels");
    }
}

#[test]
fn two_renders_of_the_same_scene_and_time_are_identical() {
    let (Some(mut a), Some(mut b)) = (view(4), view(4)) else { return };
    let sc = scene(0.2, 1.0);
    let (s1, s2) = (run_to(&sc, 0.15), run_to(&sc, 0.15));
    let opts = SceneOptions::default();
    let (x, y) = (Scene::build(&s1, &opts), Scene::build(&s2, &opts));
    let cam = Camera::preset(ViewPreset::Iso, &x.framing, 40f64.to_radians(), f64::from(W) / f64::from(H));
    let (i1, i2) = (a.render(&x, &cam).expect("renders"), b.render(&y, &cam).expect("renders"));
    assert!(i1.as_raw() == i2.as_raw(), "the same scene renders to the same bytes");
    let again = a.render(&x, &cam).expect("renders");
    assert!(again.as_raw() == i1.as_raw(), "and again in the same view");
}

#[test]
fn a_recording_writes_its_stills_frames_and_animation() {
    use spraysim_render::record::Recorder;
    use spraysim_render::{RenderParams, RenderTime};
    let sc = scene(0.2, 1.0);
    let params = RenderParams {
        at: vec![RenderTime::At(0.05), RenderTime::End],
        frames: 3,
        size: [320, 200],
        ..RenderParams::defaults(sc.process().preset)
    };
    let gpu =
        GpuOptions { backends: wgpu::Backends::VULKAN | wgpu::Backends::GL, software: true, samples: 1 };
    let mut rec = match Recorder::new(&sc, &params, &gpu) {
        Ok(r) => r,
        Err(e) => {
            assert!(std::env::var_os("CI").is_none(), "CI must render: {e}");
            return skip(&e.to_string());
        }
    };
    let mut sim = sc.build().expect("builds");
    rec.observe(&sim).expect("renders");
    while !sim.is_finished() {
        sim.step();
        rec.observe(&sim).expect("renders");
    }
    let out = rec.finish(&sim).expect("finishes");
    let names: Vec<&str> = out.files.iter().map(|(n, _)| n.as_str()).collect();
    for want in
        ["view_0.050s.png", "view_end.png", "frames/frame_0001.png", "frames/frame_0003.png", "animation.gif"]
    {
        assert!(names.contains(&want), "{want} missing from {names:?}");
    }
    let gif = &out.files.iter().find(|(n, _)| n == "animation.gif").expect("gif").1;
    let decoder = image::codecs::gif::GifDecoder::new(std::io::Cursor::new(gif)).expect("a GIF");
    let frames = image::AnimationDecoder::into_frames(decoder).collect_frames().expect("frames");
    assert_eq!(frames.len(), 3);
    assert_eq!(names.contains(&"animation.mp4"), spraysim_render::record::ffmpeg_available());
    let png = image::load_from_memory(&out.files[0].1).expect("a PNG");
    assert_eq!((png.width(), png.height()), (320, 200));
}
