//! Regression tests of issue 17 (hardening): inputs that `check` accepts never crash or
//! exhaust memory, refusals name their key, outputs are always one run's complete set, and a
//! checkpoint restores the whole state. Each test is named for the defect it pins down; the
//! faults sent to a running `spraysim` (kills, Ctrl-C) are in the command's own tests.

use spraysim::output::directory::{LOCK_FILE, RUN_RECORD};
use spraysim::output::{FILE_LIST, STAGING_PREFIX, write_outputs};
use spraysim::scenario::ScenarioError;
use spraysim::{Scenario, Simulation};
use std::path::Path;

const WALL: &str = r#"
[simulation]
duration = 0.05
[[target]]
name = "wall"
center = [0.0, 0.0, 1.0]
normal = [-1.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
size = [2.0, 2.0]
resolution = [32, 32]
"#;

/// The key and message of a refusal (panics on acceptance, naming `what`).
fn refusal(result: Result<Scenario, ScenarioError>, what: &str) -> (String, String) {
    match result {
        Ok(_) => panic!("{what}: accepted"),
        Err(ScenarioError::Invalid { key, message, .. }) => (key, message),
        Err(other) => panic!("{what}: refused without a key: {other}"),
    }
}

fn ascii_stl(corners: [[f64; 3]; 3]) -> String {
    let v: Vec<String> = corners.iter().map(|c| format!("vertex {} {} {}", c[0], c[1], c[2])).collect();
    format!("solid t\nfacet normal 0 0 1\nouter loop\n{}\nendloop\nendfacet\nendsolid t\n", v.join("\n"))
}

fn run_steps(sc: &Scenario, steps: usize) -> Simulation {
    let mut sim = sc.build().expect("builds");
    for _ in 0..steps {
        sim.step();
    }
    sim
}

#[test]
fn issue17_01_mesh_with_large_coordinates_is_refused_not_a_panic() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for (name, corners, scale) in [
        ("huge.stl", [[-1e30, 0.0, 0.0], [1e30, 0.0, 0.0], [0.0, 0.0, 1e30]], 1.0),
        ("big.stl", [[-1e9, 0.0, 0.0], [1e10, 0.0, 0.0], [0.0, 0.0, 1e9]], 1.0),
        ("scaled.stl", [[-1e4, 0.0, 0.0], [1e4, 0.0, 0.0], [0.0, 0.0, 1e4]], 1e6),
    ] {
        std::fs::write(tmp.path().join(name), ascii_stl(corners)).expect("write");
        let text = format!(
            "{WALL}\n[[obstacle]]\nname = \"o\"\nshape = \"mesh\"\nfile = \"{name}\"\nscale = {scale:e}\n"
        );
        std::fs::write(tmp.path().join("s.toml"), text).expect("write");
        let (key, message) = refusal(Scenario::from_path(&tmp.path().join("s.toml")), name);
        assert_eq!(key, "obstacle[0].file", "{name}");
        assert!(message.contains("must lie within"), "{name}: {message}");
    }
    // The largest accepted extent, a mesh 2 × 10⁴ m wide, runs (and its broad phase is small:
    // the cap on cells is tested in the engine, the memory in tests/property.rs).
    let corners = [[-1e4, -1e4, 0.0], [1e4, -1e4, 0.0], [0.0, 1e4, 0.0]];
    std::fs::write(tmp.path().join("wide.stl"), ascii_stl(corners)).expect("write");
    let text = format!("{WALL}\n[[obstacle]]\nname = \"o\"\nshape = \"mesh\"\nfile = \"wide.stl\"\n");
    std::fs::write(tmp.path().join("s.toml"), text).expect("write");
    let sc = Scenario::from_path(&tmp.path().join("s.toml")).expect("accepted");
    let sim = run_steps(&sc, 5);
    assert!(sim.swarm().alive() > 0);
}

#[test]
fn issue17_02_scenario_beyond_the_memory_limit_is_refused_naming_the_key() {
    let sc = Scenario::from_toml(WALL, "wall.toml").expect("valid");
    let (key, message) = refusal(
        sc.with_all(&[
            ("emitter.spawn_rate".into(), 1e9.into()),
            ("simulation.dt".into(), 0.1.into()),
            ("simulation.duration".into(), 2.0.into()),
        ]),
        "spawn_rate = 1e9",
    );
    assert_eq!(key, "emitter.spawn_rate");
    assert!(message.contains("of memory") && message.contains("simulation.max_memory"), "{message}");
    // The same limit, set low, refuses a heightfield too large for it, naming its resolution.
    let (key, message) = refusal(
        sc.with_all(&[
            ("simulation.max_memory".into(), 2e8.into()),
            ("target[0].resolution".into(), [4096.0, 4096.0].into()),
        ]),
        "4096² cells under 200 MB",
    );
    assert_eq!(key, "target[0].resolution", "{message}");
    // Steps and particles are reported, whatever their number.
    let b = sc.budget();
    assert_eq!((b.steps, b.particles.round()), (50, 500.0));
    assert!(b.memory < b.limit && b.memory > 0.0);
}

#[test]
fn issue17_03_overlong_target_name_is_refused_before_the_run() {
    let sc = Scenario::from_toml(WALL, "wall.toml").expect("valid");
    let long = "w".repeat(242);
    let (key, message) = refusal(sc.with("target[0].name", long.as_str()), "242 characters");
    assert_eq!(key, "target[0].name");
    assert!(message.contains("at most 64"), "{message}");
    assert!(sc.with("target[0].name", "w".repeat(64).as_str()).is_ok());
}

#[test]
fn issue17_04_nan_or_infinity_in_keys_the_shape_does_not_use_is_refused() {
    let sc = Scenario::from_toml(WALL, "wall.toml").expect("valid");
    for (key, value) in [
        ("emitter.width", f64::NAN),
        ("emitter.height", f64::INFINITY),
        ("emitter.inner_diameter", f64::NAN),
        ("emitter.fan_wide_angle", f64::NAN),
        ("process.impact.rebound_polynomial", f64::NAN),
        ("process.erosion.grain_diameter", f64::NEG_INFINITY),
        ("nozzle.circle_frequency", f64::NAN),
        ("emitter.diameter", f64::NAN),
    ] {
        let (named, message) = refusal(sc.with(key, value), key);
        assert_eq!(named, key, "{message}");
    }
    let text = format!("{WALL}\n[emitter]\nshape = \"circle\"\nwidth = nan\n");
    let (named, _) = refusal(Scenario::from_toml(&text, "t.toml"), "width = nan in the file");
    assert_eq!(named, "emitter.width");
}

#[test]
fn issue17_05_unstable_drag_is_refused_naming_the_keys() {
    let sc = Scenario::from_toml(WALL, "wall.toml").expect("valid");
    let (key, message) = refusal(
        sc.with_all(&[("process.drag".into(), 30.0.into()), ("simulation.dt".into(), 0.01.into())]),
        "drag 30 at dt 0.01",
    );
    assert_eq!(key, "process.drag");
    assert!(message.contains("emitter.speed") && message.contains("simulation.dt"), "{message}");
    // Stable but coarse: accepted with a warning naming the keys; fine: no warning.
    let coarse = sc.with_all(&[("process.drag".into(), 30.0.into()), ("simulation.dt".into(), 5e-4.into())]);
    let coarse = coarse.expect("stable");
    assert!(coarse.warnings().iter().any(|w| w.contains("process.drag")), "{:?}", coarse.warnings());
    let fine = sc.with_all(&[("process.drag".into(), 0.1.into())]).expect("fine");
    assert!(!fine.warnings().iter().any(|w| w.contains("process.drag")));
}

#[test]
fn issue17_06_resolved_scenario_runs_from_any_working_directory() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let sub = tmp.path().join("project");
    std::fs::create_dir(&sub).expect("mkdir");
    std::fs::write(sub.join("panel.stl"), ascii_stl([[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]]))
        .expect("write");
    std::fs::write(sub.join("path.csv"), "t,x,y,z,qx,qy,qz,qw\n0,-1,0,1,0,0.7071068,0,0.7071068\n")
        .expect("write");
    let text = "[simulation]\nduration = 0.02\n[nozzle]\npath_csv = \"path.csv\"\n[[target]]\nname = \"panel\"\n\
                shape = \"mesh\"\nfile = \"panel.stl\"\n";
    std::fs::write(sub.join("s.toml"), text).expect("write");
    // Given by a relative path (as `spraysim run project/s.toml` from the parent would).
    let relative = pathdiff(&sub.join("s.toml"));
    let sc = Scenario::from_path(&relative).expect("valid");
    let elsewhere = tmp.path().join("out");
    std::fs::create_dir(&elsewhere).expect("mkdir");
    std::fs::write(elsewhere.join("scenario.resolved.toml"), sc.to_toml()).expect("write");
    let again =
        Scenario::from_path(&elsewhere.join("scenario.resolved.toml")).expect("the resolved file reads");
    assert_eq!(again, sc);
    let spraysim::scenario::TargetShape::Mesh(spraysim::scenario::MeshTarget { mesh, .. }) =
        &again.targets()[0].shape
    else {
        panic!("a mesh")
    };
    assert!(Path::new(&mesh.file).is_absolute(), "{}", mesh.file);
}

/// `path` relative to the working directory when it lies under it (else as it is).
fn pathdiff(path: &Path) -> std::path::PathBuf {
    let cwd = std::env::current_dir().expect("cwd");
    let mut up = std::path::PathBuf::new();
    for ancestor in cwd.ancestors() {
        if let Ok(rest) = path.strip_prefix(ancestor) {
            return up.join(rest);
        }
        up.push("..");
    }
    path.to_path_buf()
}

#[test]
fn issue17_07_type_errors_and_bad_values_name_the_key() {
    for (text, key) in [
        ("[simulation]\ndt = abc\n", "simulation.dt"),
        ("[simulation]\ndt = 1e\n", "simulation.dt"),
        ("[emitter]\nshape = circle\n", "emitter.shape"),
        ("[process]\npreset = shotcrete\n", "process.preset"),
        ("[[target]]\nname = \"a\"\n[[target]]\nname = wall\n", "target[1].name"),
        ("[simulation]\nseed = 99999999999999999999999\n", "simulation.seed"),
        ("[simulation]\ngravity = [0, 0,\n  -9.81 x]\n", "simulation.gravity"),
        ("[simulation]\ndt = \"x\"\n", "simulation.dt"),
        ("[emitter]\nshape = \"hexagon\"\n", "emitter.shape"),
    ] {
        let (named, message) = refusal(Scenario::from_toml(text, "t.toml"), text);
        assert_eq!(named, key, "{text}: {message}");
    }
}

#[test]
fn issue17_08_repeated_tool_path_column_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    std::fs::write(tmp.path().join("p.csv"), "t,t,x,y,z,qx,qy,qz,qw\n0,0,-1,0,1,0,0.7071068,0,0.7071068\n")
        .expect("write");
    std::fs::write(tmp.path().join("s.toml"), format!("{WALL}\n[nozzle]\npath_csv = \"p.csv\"\n"))
        .expect("write");
    let Err(e) = Scenario::from_path(&tmp.path().join("s.toml")) else { panic!("accepted") };
    assert!(e.to_string().contains("column `t` appears twice"), "{e}");
}

#[test]
fn issue17_08_binary_stl_with_a_wrong_facet_count_is_refused() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let mut stl = vec![0u8; 80];
    stl.extend_from_slice(&3u32.to_le_bytes()); // says 3 facets…
    stl.extend_from_slice(&[0u8; 12]);
    for c in [0.0f32, -1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0] {
        stl.extend_from_slice(&c.to_le_bytes());
    }
    stl.extend_from_slice(&[0u8; 2]);
    stl.extend_from_slice(&[7u8; 60]); // …but holds one and some bytes
    std::fs::write(tmp.path().join("m.stl"), &stl).expect("write");
    let text = format!("{WALL}\n[[obstacle]]\nname = \"o\"\nshape = \"mesh\"\nfile = \"m.stl\"\n");
    std::fs::write(tmp.path().join("s.toml"), text).expect("write");
    let (key, message) = refusal(Scenario::from_path(&tmp.path().join("s.toml")), "wrong count");
    assert_eq!(key, "obstacle[0].file");
    assert!(message.contains("counts 3 facets"), "{message}");
}

#[test]
fn issue17_08_calibration_with_the_nozzle_pointing_away_is_an_error() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let sc = Scenario::from_path(&root.join("calibrate.toml"))
        .and_then(|s| {
            s.with_all(&[
                ("nozzle.waypoints[0].axis".into(), [0.0, 0.0, 1.0].into()),
                ("nozzle.waypoints[1].axis".into(), [0.0, 0.0, 1.0].into()),
                ("emitter.spawn_rate".into(), 2e4.into()),
            ])
        })
        .expect("valid");
    let measured =
        spraysim_calibrate::MeasuredProfile::from_path(&root.join("profile.csv")).expect("profile");
    let settings = spraysim_calibrate::CalibrationSettings { threads: 1, ..Default::default() };
    let Err(e) = spraysim_calibrate::calibrate(&sc, &measured, &settings, |_| {}) else {
        panic!("a fit of nothing reported as a result")
    };
    assert!(e.to_string().contains("nothing to fit"), "{e}");
}

/// The files in `dir`, sorted, dot-files included.
fn listing(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Checks that `dir` holds exactly the set its `metrics.json` lists, each file with its size
/// and hash, beside the list of names; returns the set's names.
pub fn assert_one_complete_set(dir: &Path) -> Vec<String> {
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
    let names: Vec<String> = listing(dir).into_iter().filter(|n| n != LOCK_FILE && n != RUN_RECORD).collect();
    assert_eq!(names, expected);
    expected
}

#[test]
fn issue17_09_stale_outputs_of_an_earlier_run_are_removed() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path().join("out");
    let floor = "\n[[target]]\nname = \"floor\"\ncenter = [-1.5, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n\
                 up = [1.0, 0.0, 0.0]\nsize = [4.0, 3.0]\nresolution = [16, 16]\n[output]\nimpact_log = 0.5\n";
    let first = Scenario::from_toml(&format!("{WALL}{floor}"), "first.toml").expect("valid");
    write_outputs(&run_steps(&first, 50), &first, &dir).expect("first run");
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
    let text = format!("{WALL}{}", floor.replace("\"floor\"", "\"ground\"").replace("0.5", "0"));
    let second = Scenario::from_toml(&text, "second.toml").expect("valid");
    write_outputs(&run_steps(&second, 50), &second, &dir).expect("second run");
    let names = assert_one_complete_set(&dir);
    assert!(names.iter().any(|n| n.starts_with("ground_")));
    assert!(!names.iter().any(|n| n.starts_with("floor_") || n == "impacts.csv" || n.starts_with("ghost")));
}

/// A scenario that exercises every part of the state: slump, cohesion and its failures, a
/// mesh target, an obstacle, erosion, the impact log, a moving nozzle with a circle, and
/// the exact integrator's sleeping particles.
fn busy_scenario(dir: &Path) -> Scenario {
    std::fs::write(dir.join("panel.stl"), ascii_stl([[0.5, -1.0, 0.0], [0.5, 1.0, 0.0], [0.5, 0.0, 2.0]]))
        .expect("write");
    let text = r#"
[simulation]
duration = 0.3
dt = 0.002
integrator = "exact"
[process]
preset = "shotcrete"
[process.slump]
interval = 0.02
[process.cohesion]
interval = 0.02
tensile_strength = 5.0
shear_strength = 5.0
[emitter]
spawn_rate = 30000.0
[nozzle]
position = [-0.6, 0.0, 1.0]
axis = [1.0, 0.0, 0.3]
circle_radius = 0.05
circle_frequency = 3.0
[[target]]
name = "wall"
center = [0.0, 0.0, 1.0]
normal = [-1.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
size = [1.0, 1.0]
resolution = [48, 48]
splat_radius = 0.02
coating = 1e-4
[[target]]
name = "floor"
role = "collector"
center = [-0.5, 0.0, 0.0]
normal = [0.0, 0.0, 1.0]
up = [1.0, 0.0, 0.0]
size = [1.5, 1.5]
resolution = [24, 24]
[[target]]
name = "panel"
shape = "mesh"
file = "panel.stl"
[[obstacle]]
name = "bar"
shape = "cylinder"
start = [-0.05, -1.0, 1.0]
end = [-0.05, 1.0, 1.0]
radius = 0.01
[output]
impact_log = 0.2
"#;
    std::fs::write(dir.join("busy.toml"), text).expect("write");
    Scenario::from_path(&dir.join("busy.toml"))
        .and_then(|s| s.with("process.erosion.model", "finnie"))
        .expect("valid")
}

#[test]
fn issue17_11_a_checkpoint_restores_the_whole_state_and_continues_bit_for_bit() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let sc = busy_scenario(tmp.path());
    let mut original = sc.build().expect("builds");
    original.set_threads(2).expect("threads");
    for _ in 0..70 {
        original.step();
    }
    let saved = original.save_state();
    let mut restored = sc.build().expect("builds");
    restored.set_threads(1).expect("threads");
    restored.restore_state(&saved).expect("restores");
    // Every field of the state, not only those a checkpoint was written for.
    assert_eq!(restored.state_debug(), original.state_debug());
    assert_eq!(restored.save_state(), saved);
    original.run(|_| {});
    restored.run(|_| {});
    assert!(!original.failures().is_empty() && !original.impact_log().is_empty(), "the scenario is busy");
    let outputs = |sim: &Simulation| spraysim::output::outputs(sim, &sc).expect("outputs");
    assert!(outputs(&original) == outputs(&restored), "outputs differ after a restore");
    // A damaged or foreign state is refused, leaving the simulation as it was.
    let mut fresh = sc.build().expect("builds");
    let before = fresh.state_debug();
    for bad in [&saved[..saved.len() / 2], &saved[..0], &[saved.as_slice(), &[0u8]].concat()[..]] {
        assert!(fresh.restore_state(bad).is_err());
        assert_eq!(fresh.state_debug(), before);
    }
    let other = Scenario::from_toml(WALL, "wall.toml").expect("valid");
    assert!(other.build().expect("builds").restore_state(&saved).is_err());
}
