//! Faults sent to a running `spraysim` child process: kills while it writes, repeated runs
//! into one directory, Ctrl-C once and twice, and a resume after `kill -9`.
//!
//! The child stops at a named point when `SPRAYSIM_PAUSE_AT` names it (it says so on stderr
//! and waits for an interrupt), so each signal lands at a known moment without any timing.
#![cfg(unix)]

mod common;

use common::{contents, killed_at, listing, one_complete_set, paused_at, signal, spraysim, wait_for};
use spraysim::scenario::scenes::{floor, wall};

/// 0.2 s onto the wall at 32 × 32 cells over the floor at 16 × 16 named `floor_name`, with an
/// impact log every `impact_log` s (written as TOML; 0: none).
fn scene(floor_name: &str, impact_log: &str) -> String {
    format!(
        "[simulation]\nduration = 0.2\n[output]\nimpact_log = {impact_log}\n{}{}",
        wall().resolution(32, 32),
        floor().named(floor_name).resolution(16, 16),
    )
}

/// A folder with the scene as `s.toml`, and as `ground.toml` with its floor named `ground` and
/// no impact log.
fn setup() -> tempfile::TempDir {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("s.toml"), scene("floor", "0.2")).expect("write");
    std::fs::write(tmp.path().join("ground.toml"), scene("ground", "0")).expect("write");
    tmp
}

#[test]
fn repeated_runs_into_one_directory_leave_only_the_last_set() {
    let tmp = setup();
    let o = spraysim(&["run", "s.toml", "-o", "out", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let first = one_complete_set(&tmp.path().join("out"));
    assert!(
        first["files"].to_string().contains("floor_hits.npy")
            && first["files"].to_string().contains("impacts.csv")
    );
    let o = spraysim(&["run", "ground.toml", "-o", "out", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let second = one_complete_set(&tmp.path().join("out"));
    let files = second["files"].to_string();
    assert!(files.contains("ground_hits.npy") && !files.contains("floor_") && !files.contains("impacts.csv"));
}

#[test]
fn a_kill_while_files_move_into_place_leaves_no_mixed_set() {
    let tmp = setup();
    let out = tmp.path().join("out");
    assert!(spraysim(&["run", "s.toml", "-o", "out", "-q"], tmp.path()).status.success());
    // Killed after two of the new files moved in: the index is gone, so no set is claimed.
    killed_at(&["run", "ground.toml", "-o", "out", "-q"], tmp.path(), "commit:2");
    assert!(!out.join("metrics.json").exists(), "metrics.json beside files of another run");
    assert!(listing(&out).iter().any(|n| n.starts_with(".spraysim-staging-")));
    // The next run cleans up after it: one complete set, nothing of either earlier run.
    assert!(spraysim(&["run", "ground.toml", "-o", "out", "-q"], tmp.path()).status.success());
    let m = one_complete_set(&out);
    assert!(!m["files"].to_string().contains("floor_"));
    assert!(!listing(&out).iter().any(|n| n.contains("floor") || n.starts_with(".spraysim-staging-")));
}

#[test]
fn a_first_ctrl_c_stops_and_writes_the_run_so_far() {
    let tmp = setup();
    let (mut child, mut err) = paused_at(&["run", "s.toml", "-o", "out", "-q"], tmp.path(), "step:40");
    signal(&child, "INT");
    wait_for(&mut err, "interrupted at t = 0.040000 s");
    let status = child.wait().expect("wait");
    assert_eq!(status.code(), Some(130));
    let m = one_complete_set(&tmp.path().join("out"));
    assert_eq!(m["completed"], false);
    assert_eq!(m["steps"], 40);
    assert!((m["time"].as_f64().expect("time") - 0.04).abs() < 1e-12);
}

#[test]
fn a_second_ctrl_c_aborts_leaving_the_previous_outputs_intact() {
    let tmp = setup();
    let out = tmp.path().join("out");
    assert!(spraysim(&["run", "ground.toml", "-o", "out", "-q"], tmp.path()).status.success());
    let before = contents(&out);
    // The first Ctrl-C at a step, the second while the outputs so far are being staged.
    let (mut child, mut err) = paused_at(&["run", "s.toml", "-o", "out", "-q"], tmp.path(), "step:40,staged");
    signal(&child, "INT");
    wait_for(&mut err, "paused at staged");
    signal(&child, "INT");
    assert_eq!(child.wait().expect("wait").code(), Some(130));
    assert!(listing(&out).iter().any(|n| n.starts_with(".spraysim-staging-")), "aborted while staging");
    assert!(contents(&out) == before, "the previous outputs changed");
    assert_eq!(one_complete_set(&out)["completed"], true);
}

#[test]
fn a_resume_after_kill_9_is_byte_identical_to_an_uninterrupted_run() {
    let tmp = setup();
    let out = tmp.path().join("out");
    let args = ["run", "s.toml", "-o", "out", "-q", "--checkpoint-every", "50ms", "-j", "2"];
    assert!(spraysim(&args, tmp.path()).status.success());
    assert!(!out.join("checkpoint.spraysim").exists(), "a completed run keeps no checkpoint");
    let reference = contents(&out);
    std::fs::remove_dir_all(&out).expect("rm");
    // Killed between the checkpoints at 0.10 s and 0.15 s, then resumed on one thread.
    killed_at(&args, tmp.path(), "step:120");
    assert!(out.join("checkpoint.spraysim").exists());
    let o = spraysim(&["resume", "out", "-q", "-j", "1"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(contents(&out) == reference, "the resumed run's outputs differ");
    // Interrupted with Ctrl-C, then resumed: the same bytes again.
    std::fs::remove_dir_all(&out).expect("rm");
    let (mut child, mut err) = paused_at(&args, tmp.path(), "step:77");
    signal(&child, "INT");
    wait_for(&mut err, "spraysim resume");
    assert_eq!(child.wait().expect("wait").code(), Some(130));
    assert_eq!(one_complete_set(&out)["completed"], false);
    let o = spraysim(&["resume", "out", "-q"], tmp.path());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(contents(&out) == reference, "the outputs after Ctrl-C and resume differ");
}
