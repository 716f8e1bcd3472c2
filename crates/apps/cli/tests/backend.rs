//! `--backend` and `[simulation] backend`: a build without the GPU backend refuses `gpu`, saying
//! how to build one, and runs `auto` on the CPU saying why; a build with it runs the default scene
//! on the GPU (Mesa's lavapipe will do) and refuses a scenario outside its scope before writing.

mod common;

use common::{spraysim, stderr};
use spraysim::scenario::scenes::wall_scene;
use std::process::Output;

/// What a run printed on stdout.
fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The outputs' directory holds a run's files.
fn wrote(dir: &std::path::Path) -> bool {
    dir.join("metrics.json").is_file()
}

#[cfg(not(feature = "gpu"))]
#[test]
fn a_build_without_the_gpu_refuses_gpu_and_runs_auto_on_the_cpu() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), wall_scene(0.02, 16)).expect("write");
    let o = spraysim(&["run", "s.toml", "-o", "gpu", "--backend", "gpu"], tmp.path());
    let err = stderr(&o);
    assert!(!o.status.success() && err.contains("--features gpu"), "{err}");
    assert!(!wrote(&tmp.path().join("gpu")), "a refused run wrote its outputs");
    let o = spraysim(&["run", "s.toml", "-o", "auto", "--backend", "auto"], tmp.path());
    let err = stderr(&o);
    assert!(o.status.success() && err.contains("running on the CPU"), "{err}");
    assert!(!stdout(&o).contains("particles flown on") && wrote(&tmp.path().join("auto")));
    let resolved = std::fs::read_to_string(tmp.path().join("auto/scenario.resolved.toml")).expect("resolved");
    assert!(resolved.contains("backend = \"auto\""), "the resolved scenario records the backend");
    let o = spraysim(&["run", "s.toml", "--backend", "tpu"], tmp.path());
    assert!(!o.status.success() && stderr(&o).contains("\"cpu\", \"gpu\", \"auto\""));
}

#[cfg(feature = "gpu")]
#[test]
fn a_build_with_the_gpu_runs_on_it_and_refuses_what_it_does_not_run() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), wall_scene(0.02, 16)).expect("write");
    let o = spraysim(&["run", "s.toml", "-o", "gpu", "--backend", "gpu"], tmp.path());
    let err = stderr(&o);
    if !o.status.success() && err.contains("no GPU adapter") && std::env::var_os("CI").is_none() {
        common::skip(&format!("no GPU adapter ({err})"));
        return;
    }
    assert!(o.status.success(), "{err}");
    assert!(stdout(&o).contains("particles flown on: GPU") && wrote(&tmp.path().join("gpu")));
    let gun = format!("{}\n[process]\npreset = \"painting\"\ngun = \"hvlp\"\n", wall_scene(0.02, 16));
    std::fs::write(tmp.path().join("a.toml"), gun).expect("write");
    let o = spraysim(&["run", "a.toml", "-o", "air", "--backend", "gpu"], tmp.path());
    let err = stderr(&o);
    assert!(!o.status.success() && err.contains("the gun's air") && err.contains("CPU backend"), "{err}");
    assert!(!wrote(&tmp.path().join("air")), "a refused run wrote its outputs");
}
