//! The live window under a virtual display: `spraysim-view` runs a short scene for a few dozen
//! frames under Xvfb, saves a screenshot of itself and closes; the screenshot shows the 3D view
//! (its background and the deposit's and particles' colours) beside the egui panel.
//!
//! Needs `xvfb-run` (Debian's `xvfb` package) and Mesa; without them the test says so and
//! passes, except in CI (the `CI` variable set), where `.ci/run` installs them.

use std::process::Command;

/// Says in the test output that a test cannot run here, and why. Written straight to the
/// standard error, which the test harness does not capture (it captures `eprintln!`), so that
/// the note shows without `--nocapture`.
fn skip(reason: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipped: {reason}");
}

fn have(program: &str) -> bool {
    Command::new("sh")
        .arg("-c")
        .arg(format!("command -v {program}"))
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn the_window_runs_a_scene_under_xvfb_and_takes_a_screenshot() {
    if !have("xvfb-run") {
        assert!(std::env::var_os("CI").is_none(), "CI must run the window test: xvfb-run is missing");
        return skip("xvfb-run is not installed");
    }
    let tmp = tempfile::tempdir().expect("tempdir");
    let shot = tmp.path().join("window.png");
    let out = Command::new("timeout")
        .args(["300", "xvfb-run", "-a", "-s", "-screen 0 1280x800x24"])
        .arg(env!("CARGO_BIN_EXE_spraysim-view"))
        .args(["--set", "simulation.duration=0.6", "--set", "target[0].resolution=[256,256]"])
        .args(["--window", "1200,760", "--frames", "40", "--screenshot"])
        .arg(&shot)
        .env("XDG_RUNTIME_DIR", tmp.path())
        .output()
        .expect("xvfb-run starts");
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "the window failed: {log}");
    let img = image::open(&shot).expect("a screenshot").to_rgba8();
    assert!(img.width() >= 1000 && img.height() >= 600, "{}×{}", img.width(), img.height());
    let bg = spraysim_render::scene::BACKGROUND;
    let background = img.pixels().filter(|p| p.0 == bg).count();
    // The 3D view is right of the side panel (at most 400 px wide): there, the deposit and the
    // particles are the saturated colours.
    let colourful = img
        .enumerate_pixels()
        .filter(|(x, _, p)| {
            let (hi, lo) =
                (p.0[..3].iter().max().copied().unwrap_or(0), p.0[..3].iter().min().copied().unwrap_or(0));
            *x > 400 && hi - lo > 60
        })
        .count();
    let total = (img.width() * img.height()) as usize;
    assert!(background > total / 10, "the 3D view's background covers {background} of {total} pixels");
    assert!(colourful > 1000, "deposit and particles colour {colourful} pixels of the 3D view");
}
