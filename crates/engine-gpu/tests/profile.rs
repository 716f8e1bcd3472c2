//! The stage's profile: every call and epoch counted, and on an adapter that writes timestamps
//! between kernels, each kernel's GPU time, which the wall time of the same calls bounds.

mod common;

use spraysim_scenario::scenes::{NOZZLE_AT_WALL, scenario, wall};
use std::sync::Arc;

#[test]
fn the_profile_times_each_kernel_within_the_wall_time_of_its_calls() {
    // Its own stage: its profile counts this test's dispatches alone.
    let Some(gpu) = common::own_gpu().map(Arc::new) else { return };
    // 0.3 s of shotcrete with cohesion every 0.1 s: three calls of twenty 5-ms epochs.
    let text = format!(
        "[simulation]\nduration = 0.3\nseed = 11\n[emitter]\nspawn_rate = 20000.0\n\
         [process.cohesion]\ninterval = 0.1\n{NOZZLE_AT_WALL}{}",
        wall().resolution(128, 128),
    );
    let sc = scenario(&text, "shotcrete");
    gpu.take_profile();
    let sim = common::run(&sc, Some(&gpu));
    let p = gpu.take_profile();
    let steps = sim.steps_done();
    let epochs = steps.div_ceil(sim.epoch_steps());
    assert_eq!((p.calls, p.epochs), (3, epochs), "every epoch flown once, a call per cohesion interval");
    assert_eq!(p.members, p.calls, "a single run: one member a call");
    let writes = gpu.gpu().device.features().contains(wgpu::Features::TIMESTAMP_QUERY_INSIDE_PASSES);
    if !writes {
        assert_eq!((p.timed, p.gpu.total()), (0, 0.0), "no timestamps, no kernel times");
        assert!(p.describe().contains("no kernel timestamps"), "{}", p.describe());
        return;
    }
    assert_eq!((p.timed, p.timed_epochs), (p.calls, p.epochs), "every call timed");
    let g = p.gpu;
    let each = [g.restore, g.born, g.fly, g.census, g.settle, g.gather];
    assert!(each.iter().all(|&t| t > 0.0 && t.is_finite()), "a kernel went untimed: {g:?}");
    // The kernels ran between the submission and the read-back's end: their GPU time cannot
    // exceed that wall time (a timestamp period misread by a factor would).
    assert!(
        g.total() <= p.kernels,
        "GPU time {} s past the wall time {} s of its calls",
        g.total(),
        p.kernels
    );
    let text = p.describe();
    for kernel in ["restore", "born", "fly", "census", "settle", "gather"] {
        assert!(text.contains(kernel), "the profile does not name {kernel}: {text}");
    }
}
