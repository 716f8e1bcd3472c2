//! The renderer's frame time on the reference scene (`spraysim_bench::ReferenceScene`) with
//! 10⁶ particles in flight, 1280 × 720: building the scene on the CPU, and uploading, drawing and
//! reading back the image. On software rendering (Mesa's lavapipe) this is slow; it is reported
//! all the same.
//!
//! `cargo bench -p spraysim-render` runs it; `spraysim bench` (with the `render` feature) prints
//! the same figure.

#![allow(missing_docs, reason = "criterion's macros generate undocumented functions")]

use criterion::{Criterion, criterion_group, criterion_main};
use spraysim_render::{Camera, Offscreen, Scene, SceneOptions, ViewPreset};

fn frame(c: &mut Criterion) {
    let sim = spraysim_bench::in_flight(1_000_000).expect("the reference scene runs");
    let opts = SceneOptions { max_particles: usize::MAX, ..SceneOptions::default() };
    let mut group = c.benchmark_group("3D view, reference scene, 10⁶ particles in flight");
    group.sample_size(10);
    group.bench_function("scene", |b| b.iter(|| Scene::build(&sim, &opts)));
    let scene = Scene::build(&sim, &opts);
    let mut view = match Offscreen::new(&Default::default(), 1280, 720) {
        Ok(v) => v,
        Err(e) => return eprintln!("no frame timing: {e}"),
    };
    eprintln!("{} particles drawn on {}", scene.points.len(), view.describe());
    let camera = Camera::preset(ViewPreset::Iso, &scene.framing, 40f64.to_radians(), 1280.0 / 720.0);
    group.bench_function("draw and read back, 1280 × 720", |b| {
        b.iter(|| view.render(&scene, &camera).expect("renders"))
    });
    let one = spraysim_render::GpuOptions { samples: 1, ..Default::default() };
    if let Ok(mut view) = Offscreen::new(&one, 1280, 720) {
        group.bench_function("draw and read back, 1280 × 720, 1 sample per pixel", |b| {
            b.iter(|| view.render(&scene, &camera).expect("renders"))
        });
    }
    group.finish();
}

criterion_group!(benches, frame);
criterion_main!(benches);
