//! What the command does without being told: `check` with no file checks the default scene,
//! `check` reports the splat radius a target gets by default, `calibrate` writes where the
//! scenario's runs write, and every bundled example writes to a folder of its own.

mod common;

use common::{spraysim, stderr};
use spraysim::Scenario;
use spraysim::scenario::DEFAULT_SCENE;
use std::path::{Path, PathBuf};

/// The bundled examples' folder.
fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../examples")
}

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn check_without_a_file_checks_the_default_scene_as_run_runs_it() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = spraysim(&["check"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).starts_with("the default scene: valid"), "{}", stdout(&o));
    // The same scene as the file of it: resolved, the two are the same text.
    std::fs::write(tmp.path().join("default.toml"), DEFAULT_SCENE).expect("write");
    let from_file = spraysim(&["check", "default.toml", "--resolved"], tmp.path());
    let built_in = spraysim(&["check", "--resolved"], tmp.path());
    assert!(built_in.status.success(), "{}", stderr(&built_in));
    assert_eq!(stdout(&built_in), stdout(&from_file));
    // Overrides apply to it, and are checked.
    let o = spraysim(&["check", "--set", "simulation.duration=0.5"], tmp.path());
    assert!(o.status.success() && stdout(&o).contains("500 steps"), "{}", stdout(&o));
    let o = spraysim(&["check", "--set", "simulation.dt=-1"], tmp.path());
    assert!(!o.status.success() && stderr(&o).contains("`simulation.dt`"), "{}", stderr(&o));
    // Nothing is written.
    let left: Vec<_> = std::fs::read_dir(tmp.path()).expect("list").collect();
    assert_eq!(left.len(), 1, "only the file this test wrote");
}

/// The painting preset square onto a 1 m panel from 0.25 m for 0.2 s at the default grid, with
/// `splat` added to the panel.
fn painting(splat: &str) -> String {
    format!(
        "[simulation]\nduration = 0.2\n[process]\npreset = \"painting\"\n[nozzle]\nposition = [-0.25, 0.0, 1.0]\n\
         axis = [1.0, 0.0, 0.0]\n[[target]]\nname = \"panel\"\ncenter = [0.0, 0.0, 1.0]\nnormal = [-1.0, 0.0, 0.0]\n\
         up = [0.0, 0.0, 1.0]\nsize = [1.0, 1.0]\n{splat}\n"
    )
}

#[test]
fn check_reports_the_splat_radius_it_derives_and_resolved_writes_it() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("derived.toml"), painting("")).expect("write");
    std::fs::write(tmp.path().join("given.toml"), painting("splat_radius = 0.005")).expect("write");
    let o = spraysim(&["check", "derived.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let line =
        "target `panel`: splat radius 2.930 mm (3 cells) by default, about 10.6 particles expected per splat";
    assert!(stdout(&o).contains(line), "{}", stdout(&o));
    let o = spraysim(&["check", "derived.toml", "--resolved"], tmp.path());
    assert!(stdout(&o).contains("splat_radius = 0.0029296875\n"), "{}", stdout(&o));
    // A radius the file gives is the file's: nothing to report.
    let o = spraysim(&["check", "given.toml"], tmp.path());
    assert!(o.status.success() && !stdout(&o).contains("splat radius"), "{}", stdout(&o));
    // The run reports it per target.
    let o = spraysim(&["run", "derived.toml", "-o", "res", "-q"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let metrics: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("res/metrics.json")).expect("metrics"))
            .expect("json");
    assert_eq!(metrics["targets"][0]["splat_radius"], 0.0029296875);
}

#[test]
fn calibrate_writes_to_the_scenarios_output_directory_without_o() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for name in ["calibrate.toml", "profile.csv"] {
        std::fs::copy(examples().join(name), tmp.path().join(name)).expect("copy");
    }
    let scenario = Scenario::from_path(&tmp.path().join("calibrate.toml")).expect("the example reads");
    let folder = scenario.output().directory.clone();
    assert_eq!(folder, "out/calibrate");
    let o =
        spraysim(&["calibrate", "calibrate.toml", "profile.csv", "--max-iterations", "1", "-q"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(tmp.path().join(&folder).join("calibrated.toml").is_file(), "nothing in {folder}");
    assert!(!tmp.path().join("calibration").exists(), "wrote ./calibration as before");
    // `-o` wins over the scenario's folder.
    let o = spraysim(
        &["calibrate", "calibrate.toml", "profile.csv", "--max-iterations", "1", "-q", "-o", "fit"],
        tmp.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(tmp.path().join("fit/calibration.json").is_file());
}

#[test]
fn every_example_writes_to_a_folder_of_its_own() {
    let mut seen = 0;
    for entry in std::fs::read_dir(examples()).expect("examples") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            let stem = path.file_stem().and_then(|s| s.to_str()).expect("a name").to_string();
            let sc = Scenario::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(sc.output().directory, format!("out/{stem}"), "{}", path.display());
            seen += 1;
        }
    }
    assert!(seen >= 7, "{seen} examples");
    // The Python examples that write outputs write under out/ too.
    for entry in std::fs::read_dir(examples().join("python")).expect("python examples") {
        let path = entry.expect("entry").path();
        let text = std::fs::read_to_string(&path).expect("read");
        if text.contains("write_outputs") || text.contains(" -o ") {
            assert!(text.contains("\"out/"), "{} writes outside out/NAME/", path.display());
        }
    }
}
