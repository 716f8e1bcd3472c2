//! What the GPU backend's tests share: the device (or why there is none), and runs of a scenario
//! on either backend.

// Each test binary uses a part of these.
#![allow(dead_code)]

use spraysim_engine::Simulation;
use spraysim_gpu::{GpuFlight, GpuOptions};
use spraysim_scenario::Scenario;
use std::sync::{Arc, OnceLock};

/// Set (to anything), as `CI` is, where the tests must find an adapter: `.ci/run`, which installs
/// Mesa's lavapipe, sets it.
pub const REQUIRE: &str = "SPRAYSIM_REQUIRE_GPU";

/// The GPU's flight stage, opened once for the test binary; `None`, with the reason on stderr,
/// where no adapter opens and neither `SPRAYSIM_REQUIRE_GPU` nor `CI` is set (else a failure).
pub fn gpu() -> Option<Arc<GpuFlight>> {
    static GPU: OnceLock<Result<Arc<GpuFlight>, String>> = OnceLock::new();
    let opened =
        GPU.get_or_init(|| GpuFlight::new(&GpuOptions::default()).map(Arc::new).map_err(|e| e.to_string()));
    match opened {
        Ok(g) => Some(g.clone()),
        Err(e) if std::env::var_os(REQUIRE).is_some() || std::env::var_os("CI").is_some() => {
            panic!("{REQUIRE} or CI is set, but no GPU opens: {e}")
        }
        Err(e) => {
            eprintln!("skipped: no GPU adapter ({e}); install Mesa's Vulkan drivers (lavapipe) to run it");
            None
        }
    }
}

/// A GPU flight stage of the caller's own, for a test that reads back what the stage holds
/// between calls, which the tests running beside it must not change; `None` as for [`gpu`].
pub fn own_gpu() -> Option<GpuFlight> {
    gpu()?;
    Some(GpuFlight::new(&GpuOptions::default()).expect("a second device opens where the first did"))
}

/// `scenario` run to its end, its particles flown on `gpu` (`None`: the CPU engine).
pub fn run(scenario: &Scenario, gpu: Option<&Arc<GpuFlight>>) -> Simulation {
    let mut sim = scenario.build().expect("the scenario builds");
    if let Some(g) = gpu {
        spraysim_gpu::check(&scenario.config()).expect("the GPU runs the scenario");
        sim.set_flight_stage(Some(g.clone()));
    }
    sim.run(|_| {});
    assert_eq!(sim.flight_stage_error(), None, "the GPU declined a call");
    sim
}

/// Mean and sample standard deviation.
pub fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}
