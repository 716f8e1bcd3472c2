//! Checkpoints: a saved state restores the whole state of a busy run, which then continues bit
//! for bit, and a damaged or foreign one is refused. A state edited at random with its checksum
//! made anew (as anyone can) is either refused with a reason or resumes to its end, and never
//! panics, hangs or reports a negative or non-finite amount.

use proptest::prelude::*;
use spraysim::scenario::scenes::{bar, floor, triangle_stl, wall, wall_scene};
use spraysim::{Scenario, Simulation, SimulationConfig};
use std::path::Path;

/// The saved state of the example wall 60 ms into a 0.1 s run, and its configuration.
fn saved() -> (SimulationConfig, Vec<u8>) {
    let config = SimulationConfig::example_wall(0.1);
    let mut sim = Simulation::new(config.clone()).expect("valid");
    for _ in 0..60 {
        sim.step();
    }
    (config, sim.save_state())
}

/// Values an edit writes: the ones that broke resumed runs, and their kin.
const NASTY: [f64; 8] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e300, -1e300, -1.0, 1e12, 0.0];

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn an_edited_state_is_refused_or_resumes_to_its_end(
        edits in proptest::collection::vec((0.0f64..1.0, 0usize..NASTY.len(), any::<bool>()), 1..4),
    ) {
        let (config, mut bytes) = saved();
        for (at, value, as_integer) in edits {
            let offset = ((bytes.len() - 8) as f64 * at) as usize;
            let word = if as_integer { u64::MAX.to_le_bytes() } else { NASTY[value].to_le_bytes() };
            bytes[offset..offset + 8].copy_from_slice(&word);
        }
        let mut sim = Simulation::new(config).expect("valid");
        if sim.restore_state(&bytes).is_ok() {
            let mut steps = 0;
            while !sim.is_finished() {
                sim.step();
                steps += 1;
                prop_assert!(steps <= 100, "ran past its end");
            }
            let m = sim.metrics();
            let volumes = [m.emitted.volume, m.fates.stuck_on_targets.volume, m.fates.left_domain.volume, m.fates.in_flight.volume];
            prop_assert!(volumes.iter().all(|v| v.is_finite() && *v >= 0.0), "{volumes:?}");
        }
    }
}

/// A scenario that exercises every part of the state: slump, cohesion and its failures, a
/// mesh target, an obstacle, erosion, the impact log, a moving nozzle with a circle, and
/// the exact integrator's sleeping particles.
fn busy_scenario(dir: &Path) -> Scenario {
    std::fs::write(dir.join("panel.stl"), triangle_stl([[0.5, -1.0, 0.0], [0.5, 1.0, 0.0], [0.5, 0.0, 2.0]]))
        .expect("write");
    let text = format!(
        r#"
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
{wall}{floor}[[target]]
name = "panel"
shape = "mesh"
file = "panel.stl"
{bar}[output]
impact_log = 0.2
"#,
        wall = wall().size(1.0, 1.0).resolution(48, 48).splat_radius(0.02).coating(1e-4),
        floor = floor().at([-0.5, 0.0, 0.0]).size(1.5, 1.5).resolution(24, 24),
        bar = bar("bar", [-0.05, -1.0, 1.0], [-0.05, 1.0, 1.0], 0.01),
    );
    std::fs::write(dir.join("busy.toml"), text).expect("write");
    Scenario::from_path(&dir.join("busy.toml"))
        .and_then(|s| s.with("process.erosion.model", "finnie"))
        .expect("valid")
}

#[test]
fn a_checkpoint_restores_the_whole_state_and_continues_bit_for_bit() {
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
    let other = Scenario::from_toml(&wall_scene(0.05, 32), "wall.toml").expect("valid");
    assert!(other.build().expect("builds").restore_state(&saved).is_err());
}
