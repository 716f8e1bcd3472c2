//! Same scenario and seed, same bytes: whatever the thread count.

use spraysim::Scenario;
use spraysim::scenario::scenes::{floor, wall};
use std::collections::BTreeMap;
use std::path::Path;

/// A busy scene: rebounds, rebar, a collector, enough particles for many update chunks.
fn busy_scene(seed: u64) -> Scenario {
    scene_with_bars(seed, 5)
}

fn scene_with_bars(seed: u64, bars: u32) -> Scenario {
    let mut text = format!(
        r#"
        [simulation]
        duration = 0.6
        seed = {seed}
        [output]
        impact_log = 0.3
        [emitter]
        spawn_rate = 40000.0
        cone_angle = 18.0
        direction = "uniform_solid_angle"
        {wall}{floor}
        "#,
        wall = wall().resolution(256, 256).splat_radius(0.01),
        floor = floor().resolution(128, 96),
    );
    for i in 0..bars {
        let y = -0.3 + 0.15 * f64::from(i);
        text.push_str(&format!(
            "[[obstacle]]\nname = \"bar{i}\"\nshape = \"cylinder\"\nstart = [-0.05, {y}, 0.0]\nend = [-0.05, {y}, 2.0]\nradius = 0.008\n[obstacle.impact]\nrestitution = 0.3\n"
        ));
    }
    Scenario::from_toml(&text, "busy").unwrap_or_else(|e| panic!("{e}"))
}

fn outputs(sc: &Scenario, threads: usize, dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut sim = sc.build().expect("valid");
    sim.set_threads(threads).expect("pool");
    sim.run(|_| {});
    written(&sim, sc, dir)
}

/// The files `sim`'s outputs for `sc` are written to, by name.
fn written(sim: &spraysim::Simulation, sc: &Scenario, dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let files = spraysim::output::write_outputs(sim, sc, dir).expect("written");
    files
        .iter()
        .map(|f| {
            (
                f.file_name().unwrap_or_default().to_string_lossy().into_owned(),
                std::fs::read(f).expect("readable"),
            )
        })
        .collect()
}

#[test]
fn outputs_are_bit_identical_across_thread_counts_and_runs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let sc = busy_scene(11);
    let one = outputs(&sc, 1, &tmp.path().join("t1"));
    // Maps, images, metrics, impacts and scenario (no failure maps: nothing failed).
    assert_eq!(one.len(), 11, "{:?}", one.keys());
    for threads in [2, 3, 16] {
        let other = outputs(&sc, threads, &tmp.path().join(format!("t{threads}")));
        assert_eq!(one.keys().collect::<Vec<_>>(), other.keys().collect::<Vec<_>>());
        for (name, bytes) in &one {
            assert!(bytes == &other[name], "{name} differs between 1 and {threads} threads");
        }
    }
    let again = outputs(&sc, 0, &tmp.path().join("again"));
    assert_eq!(one, again);
}

#[test]
fn a_different_seed_gives_a_different_layer() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let a = outputs(&busy_scene(1), 0, &tmp.path().join("a"));
    let b = outputs(&busy_scene(2), 0, &tmp.path().join("b"));
    assert_ne!(a["wall_thickness.npy"], b["wall_thickness.npy"]);
}

#[test]
fn the_resolved_scenario_reproduces_the_run() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let sc = busy_scene(5);
    let first = outputs(&sc, 0, &tmp.path().join("first"));
    let resolved = std::str::from_utf8(&first["scenario.resolved.toml"]).expect("utf-8");
    let again = Scenario::from_toml(resolved, "resolved").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(again, sc);
    let second = outputs(&again, 0, &tmp.path().join("second"));
    assert_eq!(first, second);
}

#[test]
fn the_exact_integrator_is_deterministic_across_thread_counts() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let sc = busy_scene(3).with("simulation.integrator", "exact").expect("valid");
    let one = outputs(&sc, 1, &tmp.path().join("e1"));
    let two = outputs(&sc, 2, &tmp.path().join("e2"));
    assert_eq!(one, two);
}

/// A run stepped one step at a time gives the bytes of one advanced an epoch at a time, and of
/// one whose particles never coast (every step searched in full), for every integrator: how an
/// epoch is split into calls, and the proofs that let a particle skip the search, never change
/// a result.
#[test]
fn stepping_advancing_and_coasting_all_give_the_same_bytes() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for integrator in ["euler", "semi_implicit_euler", "exact"] {
        let sc = busy_scene(8).with("simulation.integrator", integrator).expect("valid");
        let run = |name: &str, go: &dyn Fn(&mut spraysim::Simulation)| {
            let mut sim = sc.build().expect("valid");
            sim.set_threads(2).expect("pool");
            go(&mut sim);
            written(&sim, &sc, &tmp.path().join(format!("{integrator}-{name}")))
        };
        let advanced = run("advanced", &|sim| sim.run(|_| {}));
        let stepped = run("stepped", &|sim| {
            while !sim.is_finished() {
                sim.step();
            }
        });
        let searched = run("searched", &|sim| {
            sim.set_coasting(false);
            sim.advance(3);
            sim.advance(sim.total_steps() - 3);
        });
        for (name, bytes) in &advanced {
            assert!(bytes == &stepped[name], "{integrator}: {name} differs between stepping and advancing");
            assert!(bytes == &searched[name], "{integrator}: {name} differs with coasting off");
        }
    }
}

/// A simulation set up afresh for a scenario reproduces a new simulation of it bit for bit:
/// after a run of another seed (whose layers grew the broad phase's zones, which the exact
/// integrator's skipped flights depend on) and after a run of another geometry (whose broad
/// phase cannot be reused).
#[test]
fn a_restarted_simulation_reproduces_a_new_one() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for integrator in ["euler", "exact"] {
        let with = |sc: Scenario| sc.with("simulation.integrator", integrator).expect("valid");
        let sc = with(busy_scene(3));
        let fresh = outputs(&sc, 2, &tmp.path().join(format!("{integrator}-new")));
        for (k, before) in [with(busy_scene(4)), with(scene_with_bars(4, 2))].into_iter().enumerate() {
            let mut sim = before.build().expect("valid");
            sim.set_threads(2).expect("pool");
            sim.run(|_| {});
            sc.rebuild(&mut sim).expect("valid");
            assert_eq!(sim.time(), 0.0);
            sim.run(|_| {});
            let again = written(&sim, &sc, &tmp.path().join(format!("{integrator}-{k}")));
            for (name, bytes) in &fresh {
                assert!(bytes == &again[name], "{integrator}, after run {k}: {name} differs");
            }
        }
    }
}

/// A checkpoint of an earlier state version is refused: restored, it would continue otherwise
/// than the run that saved it (version 3 drew from other random streams; version 4 stepped
/// particles one step at a time against layers that changed every step; version 5 counted
/// overspray as left or expired).
#[test]
fn a_checkpoint_of_an_earlier_state_version_is_refused() {
    let sc = busy_scene(3);
    let mut sim = sc.build().expect("valid");
    for _ in 0..20 {
        sim.step();
    }
    for version in [3u32, 4, 5] {
        let mut saved = sim.save_state();
        saved[..4].copy_from_slice(&version.to_le_bytes());
        let mut fresh = sc.build().expect("valid");
        let before = fresh.state_debug();
        let refused = fresh.restore_state(&saved).expect_err("an earlier state is refused");
        assert_eq!(
            refused.to_string(),
            format!(
                "the saved state has version {version}, this program reads version {}",
                spraysim::checkpoint::STATE_VERSION
            )
        );
        assert_eq!(fresh.state_debug(), before);
    }
}
