//! The fuzzed entry points, as plain functions: each takes arbitrary bytes and must return
//! without panicking, whatever they hold. The libFuzzer targets in `fuzz_targets/` call them.

use spraysim::Scenario;

/// A scenario's text: parsed and validated; when accepted, set up and stepped twice.
pub fn scenario(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(sc) = Scenario::from_toml(text, "fuzz.toml") else { return };
    let _ = sc.budget();
    let _ = sc.to_toml();
    if let Ok(mut sim) = sc.build() {
        sim.step();
        sim.step();
        let _ = sim.metrics();
    }
}

/// A scenario that uses `file` (written into a fresh folder as `name`) in `section`.
fn with_file(name: &str, data: &[u8], section: &str) {
    let Ok(dir) = tempfile::tempdir() else { return };
    if std::fs::write(dir.path().join(name), data).is_err() {
        return;
    }
    let text = format!(
        "[simulation]\nduration = 0.002\n[[target]]\nname = \"wall\"\ncenter = [0.0, 0.0, 1.0]\n\
         normal = [-1.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\nsize = [2.0, 2.0]\nresolution = [8, 8]\n{section}"
    );
    if std::fs::write(dir.path().join("s.toml"), text).is_err() {
        return;
    }
    if let Ok(sc) = Scenario::from_path(&dir.path().join("s.toml")) {
        if let Ok(mut sim) = sc.build() {
            sim.step();
        }
    }
}

/// A mesh file: the first byte picks STL or OBJ, the rest is the file.
pub fn mesh(data: &[u8]) {
    let Some((&kind, rest)) = data.split_first() else { return };
    let name = if kind % 2 == 0 { "m.stl" } else { "m.obj" };
    with_file(name, rest, &format!("[[obstacle]]\nname = \"m\"\nshape = \"mesh\"\nfile = \"{name}\"\n"));
}

/// A robot tool path (CSV).
pub fn tool_path(data: &[u8]) {
    with_file("p.csv", data, "[nozzle]\npath_csv = \"p.csv\"\n");
}

/// A measured deposition profile (CSV) for calibration.
pub fn profile(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let _ = spraysim_calibrate::MeasuredProfile::from_csv(text, "fuzz.csv");
}

/// A checkpoint's engine state for the example wall 0.1 s run: restored (or refused) and, when
/// accepted, stepped to the end of the run.
pub fn checkpoint(data: &[u8]) {
    let config = spraysim::SimulationConfig::example_wall(0.1);
    let Ok(mut sim) = spraysim::Simulation::new(config) else { return };
    if sim.restore_state(data).is_ok() {
        while !sim.is_finished() {
            sim.step();
        }
        let _ = sim.metrics();
    }
}
