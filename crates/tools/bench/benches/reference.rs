//! Criterion benchmarks on the reference scene (see `spraysim_bench::ReferenceScene`): whole
//! runs, so the figures include emission, the parallel flight through each layer epoch, the
//! merge of its books and the settling of the layers.
//!
//! `cargo bench -p spraysim-bench` runs them; `spraysim bench` prints the scaling table.

#![allow(missing_docs, reason = "criterion's macros generate undocumented functions")]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use spraysim_bench::ReferenceScene;

fn run(scene: &spraysim_scenario::Scenario) -> u64 {
    let mut sim = scene.build().expect("the reference scene is valid");
    sim.run(|_| {});
    sim.particle_steps()
}

fn reference(c: &mut Criterion) {
    let mut group = c.benchmark_group("reference scene");
    group.sample_size(10);
    for (name, scene) in [
        ("26 bars", ReferenceScene { spawn_rate: 1e6, duration: 0.1, ..ReferenceScene::default() }),
        (
            "520 bars",
            ReferenceScene {
                spawn_rate: 1e6,
                duration: 0.1,
                pieces_per_bar: 20,
                ..ReferenceScene::default()
            },
        ),
    ] {
        let sc = scene.scenario().expect("the reference scene is valid");
        // Particle-steps per run, to report throughput in particle-steps per second.
        group.throughput(Throughput::Elements(run(&sc)));
        group.bench_function(name, |b| b.iter(|| run(&sc)));
    }
    group.finish();
}

criterion_group!(benches, reference);
criterion_main!(benches);
