//! What the command's tests share: starting `spraysim`, pausing or killing it at a named
//! point, and reading an output directory back.
#![allow(dead_code)] // each test file uses its own part

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Child, ChildStderr, Command, Output, Stdio};

/// Runs `spraysim ARGS` in `cwd` to its end.
pub fn spraysim(args: &[&str], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_spraysim"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("spraysim starts")
}

/// Says in the test output that a test cannot run here, and why. Written straight to the
/// standard error, which the test harness does not capture (it captures `eprintln!`), so that
/// the note shows without `--nocapture`.
pub fn skip(reason: &str) {
    use std::io::Write;
    let _ = writeln!(std::io::stderr(), "skipped: {reason}");
}

/// What a run printed on stderr.
pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Starts `spraysim ARGS` pausing at `point` (several: comma-separated; see the command's
/// run control, `src/control.rs`), and waits until it has reached the first.
pub fn paused_at(args: &[&str], cwd: &Path, point: &str) -> (Child, BufReader<ChildStderr>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_spraysim"))
        .args(args)
        .current_dir(cwd)
        .env("SPRAYSIM_PAUSE_AT", point)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spraysim starts");
    let mut err = BufReader::new(child.stderr.take().expect("stderr"));
    let first = point.split(',').next().unwrap_or(point);
    wait_for(&mut err, &format!("paused at {first}"));
    (child, err)
}

/// Starts `spraysim ARGS` in `cwd` and kills it (`kill -9`) once it has reached `point` (see
/// [`paused_at`]): what a crash at that moment leaves behind.
pub fn killed_at(args: &[&str], cwd: &Path, point: &str) {
    let (mut child, _err) = paused_at(args, cwd, point);
    child.kill().expect("kill -9");
    child.wait().expect("wait");
}

/// Reads stderr until a line contains `what` (panics if the child ends first).
pub fn wait_for(err: &mut BufReader<ChildStderr>, what: &str) {
    let mut line = String::new();
    loop {
        line.clear();
        assert!(err.read_line(&mut line).expect("stderr") > 0, "the child ended before `{what}`");
        if line.contains(what) {
            return;
        }
    }
}

/// Sends signal `name` (`INT`, `KILL`) to `child`.
pub fn signal(child: &Child, name: &str) {
    let status =
        Command::new("kill").args([&format!("-{name}"), &child.id().to_string()]).status().expect("kill");
    assert!(status.success());
}

/// The names in `dir`, sorted, dot-files included.
pub fn listing(dir: &Path) -> Vec<String> {
    spraysim::output::directory::entries(dir).expect("dir")
}

/// Whether `name` is the writer's bookkeeping rather than an output: the lock, the record of
/// the run, and a staging folder an abort left (the next writer finishes it).
pub fn bookkeeping(name: &str) -> bool {
    name == ".spraysim-lock" || name == ".spraysim-run" || name.starts_with(".spraysim-staging-")
}

/// `dir` holds exactly the set its `metrics.json` lists (sizes checked) beside the writer's
/// list of names and its bookkeeping, and a checkpoint; returns the metrics.
pub fn one_complete_set(dir: &Path) -> serde_json::Value {
    let metrics: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("metrics.json")).expect("metrics.json"))
            .expect("json");
    let mut expected = vec!["metrics.json".to_string(), ".spraysim-files".to_string()];
    for f in metrics["files"].as_array().expect("manifest") {
        let name = f["name"].as_str().expect("name").to_string();
        let len = std::fs::metadata(dir.join(&name)).expect("listed file present").len();
        assert_eq!(len, f["bytes"].as_u64().expect("bytes"), "{name}");
        expected.push(name);
    }
    expected.sort();
    let names: Vec<String> =
        listing(dir).into_iter().filter(|n| n != "checkpoint.spraysim" && !bookkeeping(n)).collect();
    assert_eq!(names, expected);
    metrics
}

/// Every file of `dir` with its contents, but the writer's bookkeeping.
pub fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    listing(dir)
        .into_iter()
        .filter(|n| !bookkeeping(n))
        .map(|n| (n.clone(), std::fs::read(dir.join(&n)).expect("read")))
        .collect()
}
