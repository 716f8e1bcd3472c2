//! The `spraysim` command line: runs, refusals and presets.

mod common;

use common::{bookkeeping, listing, spraysim, stderr};
use spraysim::scenario::scenes::wall_scene;
use std::path::Path;
use std::process::Command;

/// The smallest runnable scene the tests start from: 0.05 s onto the wall at 32 × 32 cells.
fn small() -> String {
    wall_scene(0.05, 32)
}

#[test]
fn run_writes_every_output() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), small()).expect("write");
    let o = spraysim(&["run", "s.toml", "-o", "res", "-q"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let names: Vec<String> = listing(&tmp.path().join("res"))
        .into_iter()
        .filter(|n| n != ".spraysim-files" && !bookkeeping(n))
        .collect();
    assert_eq!(
        names,
        [
            "metrics.json",
            "scenario.resolved.toml",
            "wall_hits.npy",
            "wall_hits.png",
            "wall_thickness.npy",
            "wall_thickness.png"
        ]
    );
    let metrics: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("res/metrics.json")).expect("metrics"))
            .expect("json");
    assert_eq!(metrics["emitted"]["count"], 500);
    // The .npy is float32, rows × cols.
    let npy = std::fs::read(tmp.path().join("res/wall_thickness.npy")).expect("npy");
    let header = String::from_utf8_lossy(&npy[..128]);
    assert!(header.contains("'descr': '<f4'") && header.contains("'shape': (32, 32)"), "{header}");
}

#[test]
fn bad_scenarios_are_refused_and_write_nothing() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for (i, (bad, expect)) in [
        (small().replace("duration = 0.05", "duration = 0.05\ndt = -1.0"), "`simulation.dt`"),
        (small().replace("resolution = [32, 32]", "resolution = [32, 0]"), "`target[0].resolution`"),
        (small().replace("up = [0.0, 0.0, 1.0]", "up = [1.0, 0.0, 0.0]"), "`target[0].up`"),
        (small().replace("[simulation]", "[simulation]\nspeed = 3.0"), "`simulation.speed` is not a key"),
        (format!("{}\n[process]\npreset = \"gunite\"\n", small()), "`process.preset` must be one of"),
    ]
    .into_iter()
    .enumerate()
    {
        let file = format!("bad{i}.toml");
        std::fs::write(tmp.path().join(&file), bad).expect("write");
        for cmd in ["run", "check"] {
            let o = spraysim(&[cmd, &file, "-o", "never"][..if cmd == "run" { 4 } else { 2 }], tmp.path());
            assert!(!o.status.success(), "{cmd} accepted {file}");
            let err = stderr(&o);
            assert!(err.contains(&file) && err.contains(expect), "{cmd} {file}: {err}");
            assert!(!tmp.path().join("never").exists(), "{cmd} {file} left an output directory");
        }
    }
}

#[test]
fn an_output_directory_under_a_file_is_refused_before_the_run() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), small()).expect("write");
    std::fs::write(tmp.path().join("plain-file"), "").expect("write");
    let o = spraysim(&["run", "s.toml", "-o", "plain-file/out"], tmp.path());
    assert!(!o.status.success());
    assert!(stderr(&o).contains("plain-file: is a file, not a folder"), "{}", stderr(&o));
    assert_eq!(std::fs::read_dir(tmp.path()).expect("dir").count(), 2, "something was written");
}

#[test]
fn check_reports_steps_particles_and_memory() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), small()).expect("write");
    let o = spraysim(&["check", "s.toml"], tmp.path());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success() && text.contains("50 steps") && text.contains("particles"), "{text}");
    assert!(text.contains("of memory (limit"), "{text}");
    let o = spraysim(
        &["check", "s.toml", "--set", "emitter.spawn_rate=1e9", "--set", "simulation.dt=0.1"],
        tmp.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && err.contains("`emitter.spawn_rate`") && err.contains("memory"), "{err}");
    let o = spraysim(
        &["check", "s.toml", "--set", "simulation.duration=1e4", "--set", "simulation.dt=1e-4"],
        tmp.path(),
    );
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains("100000000 steps"), "{err}");
}

#[test]
fn presets_paste_into_scenarios() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = spraysim(&["presets"], tmp.path());
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout).into_owned();
    let chunks: Vec<&str> = text.split("# ---- ").skip(1).collect();
    // The three process presets, then the five paint guns over the painting preset.
    assert_eq!(chunks.len(), 3 + 5);
    for (k, chunk) in chunks.into_iter().enumerate() {
        let (header, body) = chunk.split_once('\n').expect("header line");
        let header = header.trim_end_matches(" ----");
        let file = format!("preset{k}.toml");
        std::fs::write(tmp.path().join(&file), format!("{}\n{body}", small())).expect("write");
        let check = spraysim(&["check", &file, "--resolved"], tmp.path());
        assert!(check.status.success(), "{header}: {}", stderr(&check));
        let resolved = String::from_utf8_lossy(&check.stdout).into_owned();
        let expected = match header.split_once("gun = ") {
            Some((_, gun)) => format!("gun = {}", gun.split(' ').next().unwrap_or_default()),
            None => format!("preset = \"{header}\""),
        };
        assert!(resolved.contains(&expected), "{header}: no `{expected}` in\n{resolved}");
    }
}

#[test]
fn the_default_scene_runs_without_a_scenario() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = spraysim(&["run", "-o", "d"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("rebound (ACI") && out.contains("wall") && out.contains("floor"), "{out}");
    assert!(tmp.path().join("d/wall_thickness.png").exists());
    assert!(tmp.path().join("d/floor_thickness.npy").exists());
}

fn example(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../examples").join(name).display().to_string()
}

#[test]
fn calibrate_writes_a_fitted_scenario_that_runs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let (scenario, profile) = (example("calibrate.toml"), example("profile.csv"));
    // A few iterations only: the fit itself is tested in the library.
    let o = spraysim(&["calibrate", &scenario, &profile, "--max-iterations", "3", "-o", "cal"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    for words in ["max absolute", "RMS", "mean absolute", "mu", "sigma"] {
        assert!(out.contains(words), "summary lacks `{words}`: {out}");
    }
    for name in ["calibrated.toml", "calibration.json", "profile.csv", "profile.png"] {
        assert!(tmp.path().join("cal").join(name).is_file(), "{name} missing");
    }
    let o = spraysim(&["check", "cal/calibrated.toml"], tmp.path());
    assert!(o.status.success(), "the fitted scenario is refused: {}", stderr(&o));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(tmp.path().join("cal/calibration.json")).expect("json"))
            .expect("parses");
    assert_eq!(json["params"], serde_json::json!(["mu", "sigma"]));
    let rms = json["errors"]["rms"].as_f64().expect("rms");
    assert!(rms < json["initial_errors"]["rms"].as_f64().expect("initial rms"), "no progress: {json}");
}

#[test]
fn calibrate_refuses_bad_input_and_writes_nothing() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("inches.csv"), "radius [in],thickness [mm]\n0,1\n1,1\n2,1\n")
        .expect("write");
    std::fs::write(
        tmp.path().join("polar.toml"),
        format!("{}\n[emitter]\ndirection = \"uniform_polar\"\n", small()),
    )
    .expect("write");
    let (scenario, profile) = (example("calibrate.toml"), example("profile.csv"));
    for (args, expect) in [
        (vec!["calibrate", &scenario, "inches.csv"], "inches.csv:1"),
        (vec!["calibrate", &scenario, &profile, "--fit", "mu,tau"], "invalid value 'tau' for '--fit <FIT>'"),
        (vec!["calibrate", &scenario, &profile, "--shape", "diagonal"], "invalid value 'diagonal'"),
        (vec!["calibrate", &scenario, &profile, "--target", "ceiling"], "no target named `ceiling`"),
        (vec!["calibrate", "polar.toml", &profile], "truncated_normal"),
        (vec!["calibrate", &scenario, "missing.csv"], "missing.csv"),
        (vec!["calibrate", &scenario, &profile, "--center", "0.1"], "two numbers"),
        (
            vec!["calibrate", &scenario, &profile, "--center=0.3,-0.4", "--shape", "up"],
            "no cell of the target",
        ),
    ] {
        let mut args = args.clone();
        args.extend(["-o", "never"]);
        let o = spraysim(&args, tmp.path());
        assert!(!o.status.success(), "{args:?} accepted");
        assert!(stderr(&o).contains(expect), "{args:?}: {}", stderr(&o));
        assert!(!tmp.path().join("never").exists(), "{args:?} left an output directory");
    }
}

#[test]
fn a_reader_that_goes_away_early_is_not_an_error() {
    // `spraysim presets | head -1`: the pipe closes before everything is written.
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    let o = Command::new(env!("CARGO_BIN_EXE_spraysim"))
        .arg("presets")
        .stdout(writer)
        .output()
        .expect("spraysim starts");
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(stderr(&o), "", "no panic, no error message");
}

#[test]
fn an_error_quotes_its_cause_once() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = spraysim(&["check", "missing.toml"], tmp.path());
    assert!(!o.status.success());
    let err = stderr(&o);
    assert!(err.starts_with("error: missing.toml: cannot read the scenario"), "{err}");
    assert_eq!(err.matches("os error").count(), 1, "{err}");
}

#[test]
fn bench_refuses_a_bad_reference_scene_without_a_panic() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for (flag, value) in [("--duration", "-1"), ("--spawn-rate", "0"), ("--spawn-rate", "nan")] {
        let o = spraysim(&["bench", &format!("{flag}={value}")], tmp.path());
        let err = stderr(&o);
        assert!(!o.status.success());
        assert!(err.starts_with(&format!("error: {flag} must be a positive number")), "{err}");
        assert!(o.stdout.is_empty(), "nothing printed before the refusal");
    }
}

#[cfg(not(feature = "render"))]
#[test]
fn a_build_without_3d_views_refuses_them_before_the_run_and_says_how_to_build_them() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), format!("{}\n[output]\nrender = true\n", small()))
        .expect("write");
    let o = spraysim(&["run", "s.toml", "-o", "res", "-q"], tmp.path());
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("[output] render") && stderr(&o).contains("--features render"),
        "{}",
        stderr(&o)
    );
    assert!(!tmp.path().join("res").exists(), "nothing is written");
    let o = spraysim(&["render", "-o", "views"], tmp.path());
    assert!(!o.status.success() && stderr(&o).contains("--features render"), "{}", stderr(&o));
    // Its flags are checked all the same.
    let o = spraysim(&["render", "-o", "views", "--size", "10x10"], tmp.path());
    assert!(stderr(&o).contains("--size must be two sizes of 16 to 8192 px"), "{}", stderr(&o));
    let o = spraysim(&["render", "-o", "views", "--at", "9"], tmp.path());
    assert!(stderr(&o).contains("--at must be times within the run"), "{}", stderr(&o));
}

#[cfg(feature = "render")]
#[test]
fn render_writes_the_stills_asked_for_and_run_writes_its_views_with_its_outputs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), small()).expect("write");
    let o = spraysim(
        &["render", "s.toml", "-o", "views", "--at", "0.02,end", "--size", "320x200", "-q"],
        tmp.path(),
    );
    if !o.status.success() && stderr(&o).contains("no graphics adapter") && std::env::var_os("CI").is_none() {
        return common::skip(&stderr(&o));
    }
    assert!(o.status.success(), "{}", stderr(&o));
    for name in ["view_0.020s.png", "view_end.png"] {
        let img = image_size(&tmp.path().join("views").join(name));
        assert_eq!(img, (320, 200), "{name}");
    }
    let with =
        format!("{}\n[output.render]\nat = [\"end\"]\nsize = [200, 120]\ncamera = \"front\"\n", small());
    std::fs::write(tmp.path().join("r.toml"), with).expect("write");
    let o = spraysim(&["run", "r.toml", "-o", "res", "-q"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(tmp.path().join("res/metrics.json").is_file());
    assert_eq!(image_size(&tmp.path().join("res/view_end.png")), (200, 120));
}

/// Width and height of a PNG, from its header.
#[cfg(feature = "render")]
fn image_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}
