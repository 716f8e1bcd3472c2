//! The sanity warnings: the ordinary mistakes that used to end in "transfer efficiency 0.00 %"
//! and a success are told, with the key to change, in the summary, by `check` and in
//! `metrics.json`; `--strict` makes them errors.

mod common;

use common::{spraysim, stderr};
use spraysim::scenario::DEFAULT_SCENE;
use spraysim::scenario::scenes::wall_scene;
use std::path::Path;

fn stdout(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// The `warnings` of `dir/metrics.json` as (code, key) pairs.
fn warnings_in(dir: &Path) -> Vec<(String, String)> {
    let text = std::fs::read(dir.join("metrics.json")).expect("metrics.json");
    let metrics: serde_json::Value = serde_json::from_slice(&text).expect("json");
    let listed = metrics["warnings"].as_array().expect("a `warnings` array").clone();
    listed
        .iter()
        .map(|w| {
            assert!(w["message"].as_str().is_some_and(|m| !m.is_empty()), "{w}");
            (
                w["code"].as_str().unwrap_or_default().to_string(),
                w["key"].as_str().unwrap_or_default().to_string(),
            )
        })
        .collect()
}

/// The default scene with its nozzle following `path.csv`: a pass across the wall at 1 m,
/// spraying square onto it, with every position in millimetres.
fn millimetre_path(dir: &Path) -> &'static str {
    // The tool's z axis turned onto +x: a quarter turn about y.
    let q = "0,0.7071067811865476,0,0.7071067811865476";
    let csv = format!("t,x,y,z,qx,qy,qz,qw\n0,-1000,-500,1000,{q}\n2,-1000,500,1000,{q}\n");
    std::fs::write(dir.join("path.csv"), csv).expect("write the path");
    let text = DEFAULT_SCENE
        .replace(
            "position = [-1.0, 0.0, 1.0]   # m: 1 m in front of the wall's centre\n",
            "path_csv = \"path.csv\"\n",
        )
        .replace("axis = [1.0, 0.0, 0.0]        # spraying square onto the wall\n", "");
    std::fs::write(dir.join("mm.toml"), text).expect("write the scenario");
    "mm.toml"
}

#[test]
fn a_nozzle_aimed_away_from_every_target_is_warned_of_and_fails_with_strict() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let away = "nozzle.axis=[-1,0,0]";
    let o = spraysim(&["run", "--set", away], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    let line =
        out.lines().find(|l| l.starts_with("warning: ")).unwrap_or_else(|| panic!("no warning:\n{out}"));
    assert!(line.contains("no particle can reach") && line.contains("`nozzle.axis`"), "{line}");
    assert!(line.contains("no_target_reachable"), "{line}");
    assert_eq!(warnings_in(&tmp.path().join("out")), [("no_target_reachable".into(), "nozzle.axis".into())]);
    // The nozzle's window, which metrics.json has, is in the summary too.
    assert!(out.lines().any(|l| l.starts_with("off target") && l.ends_with("100.0%")), "{out}");

    // With --strict, the run is refused before it starts, naming the warning and its key.
    let o = spraysim(&["run", "--strict", "-o", "strict", "--set", away], tmp.path());
    assert!(!o.status.success(), "--strict must fail");
    let err = stderr(&o);
    assert!(err.contains("--strict") && err.contains("no_target_reachable (change `nozzle.axis`)"), "{err}");
    assert!(!tmp.path().join("strict/metrics.json").exists(), "nothing run, nothing written");
}

#[test]
fn a_tool_path_in_millimetres_fails_check_with_strict_and_is_warned_of_by_run() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let scenario = millimetre_path(tmp.path());
    let o = spraysim(&["check", scenario], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("warning: waypoint 0 of the nozzle's path") && out.contains("millimetres"),
        "check must warn of the path:\n{out}"
    );
    assert!(out.contains("path_far_from_targets; change `nozzle.waypoints`"), "{out}");
    let o = spraysim(&["check", "--strict", scenario], tmp.path());
    assert!(!o.status.success(), "check --strict must fail");
    assert!(stderr(&o).contains("path_far_from_targets (change `nozzle.waypoints`)"), "{}", stderr(&o));

    let o = spraysim(&["run", "-q", scenario], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let codes: Vec<String> = warnings_in(&tmp.path().join("out")).into_iter().map(|(code, _)| code).collect();
    assert_eq!(codes, ["path_far_from_targets", "no_target_reachable", "still_in_flight"]);
    // Quiet, the warnings go to stderr.
    assert!(
        stderr(&o).contains("warning: ") && stderr(&o).contains("`simulation.duration`"),
        "{}",
        stderr(&o)
    );
    let o = spraysim(&["run", "-q", "--strict", "-o", "strict", scenario], tmp.path());
    assert!(!o.status.success(), "run --strict must fail");
}

#[test]
fn the_default_scene_gives_no_warning() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("default.toml"), DEFAULT_SCENE).expect("write");
    let o = spraysim(&["check", "--strict", "default.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stdout(&o).contains("warning"), "{}", stdout(&o));
    let o = spraysim(&["run", "-q", "--strict", "default.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o), "");
    assert_eq!(warnings_in(&tmp.path().join("out")), []);
}

#[test]
fn check_counts_only_what_the_spraying_legs_emit_and_says_1_target() {
    let tmp = tempfile::tempdir().expect("tempdir");
    // 2 s at 10⁴ particles/s, of which the first second sprays.
    let legs = [(0.0, true), (1.0, false), (2.0, false)]
        .map(|(t, spray)| {
            format!("[[nozzle.waypoints]]\ntime = {t:?}\nposition = [-1.0, 0.0, 1.0]\naxis = [1.0, 0.0, 0.0]\nspray = {spray}\n")
        })
        .join("");
    std::fs::write(tmp.path().join("s.toml"), format!("{}{legs}", wall_scene(2.0, 64))).expect("write");
    let o = spraysim(&["check", "s.toml"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(out.contains("valid (1 target, 0 obstacles)"), "{out}");
    assert!(out.contains("1.0000e4 particles sprayed"), "{out}");
}

#[test]
fn a_run_too_short_for_its_particles_to_land_writes_its_outputs_then_fails_with_strict() {
    let tmp = tempfile::tempdir().expect("tempdir");
    // 0.3 s: most of what was emitted is still on its way (at a spawn rate that keeps the map
    // well sampled, so that nothing is amiss before the run).
    let short = ["--set", "simulation.duration=0.3", "--set", "emitter.spawn_rate=1e5"];
    let o = spraysim(&[&["run", "--strict"][..], &short[..]].concat(), tmp.path());
    assert!(!o.status.success(), "--strict must fail after the run");
    let err = stderr(&o);
    assert!(err.contains("still_in_flight (change `simulation.duration`)"), "{err}");
    let out = stdout(&o);
    assert!(out.contains("still in flight at the end of the run"), "the summary tells it:\n{out}");
    assert_eq!(
        warnings_in(&tmp.path().join("out")),
        [("still_in_flight".into(), "simulation.duration".into())]
    );
}
