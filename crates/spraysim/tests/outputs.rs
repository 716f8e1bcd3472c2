//! The output directory holds one run's complete set: every file its `metrics.json` lists, with
//! its size, and nothing an earlier run or a killed writer left behind. (The faults sent to a
//! running `spraysim`, kills and Ctrl-C, are in the command's own tests.)

use spraysim::Scenario;
use spraysim::output::directory::{LOCK_FILE, RUN_RECORD, entries};
use spraysim::output::{FILE_LIST, STAGING_PREFIX, write_outputs};
use spraysim::scenario::scenes::{Rectangle, floor, wall_scene};
use std::path::Path;

/// Checks that `dir` holds exactly the set its `metrics.json` lists, each file with its size
/// and hash, beside the list of names; returns the set's names.
fn assert_one_complete_set(dir: &Path) -> Vec<String> {
    let metrics: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("metrics.json")).expect("metrics.json"))
            .expect("json");
    let mut expected = vec!["metrics.json".to_string(), FILE_LIST.to_string()];
    for f in metrics["files"].as_array().expect("a manifest") {
        let name = f["name"].as_str().expect("name");
        let bytes = std::fs::read(dir.join(name)).expect("listed file present");
        assert_eq!(bytes.len() as u64, f["bytes"].as_u64().expect("size"), "{name}");
        expected.push(name.to_string());
    }
    expected.sort();
    // Besides the set: the lock and the record of the run the directory holds.
    let names: Vec<String> =
        entries(dir).expect("dir").into_iter().filter(|n| n != LOCK_FILE && n != RUN_RECORD).collect();
    assert_eq!(names, expected);
    expected
}

/// 50 steps of the wall scene with `floor` (a second substrate) and an impact log every
/// `impact_log` s (0: none), written into `dir`.
fn run_into(dir: &Path, floor: &Rectangle, impact_log: f64, origin: &str) {
    let text = format!("{}\n{floor}[output]\nimpact_log = {impact_log:?}\n", wall_scene(0.05, 32));
    let sc = Scenario::from_toml(&text, origin).expect("valid");
    let mut sim = sc.build().expect("builds");
    for _ in 0..50 {
        sim.step();
    }
    write_outputs(&sim, &sc, dir).expect(origin);
}

#[test]
fn a_run_removes_the_outputs_an_earlier_run_and_a_killed_writer_left() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path().join("out");
    let floor = floor().substrate().resolution(16, 16);
    run_into(&dir, &floor, 0.5, "first run");
    let names = assert_one_complete_set(&dir);
    assert!(names.iter().any(|n| n.starts_with("floor_")) && names.contains(&"impacts.csv".to_string()));
    // A killed writer's staging folder, with what it had moved in before its index.
    let dead = dir.join(format!("{STAGING_PREFIX}4294967295"));
    std::fs::create_dir(&dead).expect("mkdir");
    let ghost = b"half a run";
    let hash: String = {
        use sha2::Digest;
        sha2::Sha256::digest(ghost).iter().map(|b| format!("{b:02x}")).collect()
    };
    let journal = format!("index metrics.json\nnew {hash} {} ghost_thickness.npy\n", ghost.len());
    std::fs::write(dead.join("journal"), journal).expect("write");
    std::fs::write(dir.join("ghost_thickness.npy"), ghost).expect("write");
    run_into(&dir, &floor.named("ground"), 0.0, "second run");
    let names = assert_one_complete_set(&dir);
    assert!(names.iter().any(|n| n.starts_with("ground_")));
    assert!(!names.iter().any(|n| n.starts_with("floor_") || n == "impacts.csv" || n.starts_with("ghost")));
}
