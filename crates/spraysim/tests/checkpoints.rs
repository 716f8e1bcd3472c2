//! A checkpoint's state, edited at random with its checksum made anew (as anyone can): a
//! resumed run either refuses it with a reason or runs to its end, and never panics, hangs or
//! reports a negative or non-finite amount.

use proptest::prelude::*;
use spraysim::{Simulation, SimulationConfig};

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
