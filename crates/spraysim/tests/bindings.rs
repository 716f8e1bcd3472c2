//! What language bindings rely on: `Simulation::particle_now` gives every particle's state at
//! the present time, also for the particles that the exact integrator keeps at an anchor in
//! the past (it flies them in closed form from there); a deposit surface's maps keep their
//! storage while it runs (so they can be viewed without a copy).

use spraysim::deposit::DepositSurface;
use spraysim::motion::Integrator;
use spraysim::{Simulation, SimulationConfig};

#[test]
fn every_particle_is_reported_where_it_is_now() {
    let mut config = SimulationConfig::example_wall(0.2);
    config.motion.integrator = Integrator::Exact;
    let mut sim = Simulation::new(config).expect("the example wall is valid");
    let (g, dt) = (sim.config().motion.gravity, sim.config().dt);
    sim.advance(30);
    let (mut checked, mut anchored_earlier) = (0, 0);
    for _ in 0..10 {
        let before: Vec<_> =
            (0..sim.swarm().len()).map(|i| (sim.swarm().particles[i], sim.particle_now(i))).collect();
        sim.step();
        for (i, (p, (x, v, age))) in before.into_iter().enumerate() {
            let q = sim.swarm().particles[i];
            // In flight through the whole step, without an impact: one step further along its
            // arc, one step older.
            if !(p.is_alive() && q.is_alive() && q.impacts() == p.impacts()) {
                continue;
            }
            let (x1, v1, age1) = sim.particle_now(i);
            let expected = x + v * dt + 0.5 * g * dt * dt;
            assert!((x1 - expected).length() < 1e-9, "slot {i}: {x1} against {expected}");
            assert!((v1 - (v + g * dt)).length() < 1e-9, "slot {i}: {v1}");
            assert!((age1 - age - dt).abs() < 1e-12, "slot {i}: age {age1} after {age}");
            checked += 1;
            anchored_earlier += usize::from(q.since > 1);
        }
    }
    assert!(
        checked > 1000 && anchored_earlier > 100,
        "{checked} particles checked, {anchored_earlier} anchored earlier"
    );
}

#[test]
fn deposit_maps_keep_their_storage_while_layers_grow_and_fail() {
    // A weak, barely cohesive layer fails as it grows (analysed every 0.1 s).
    let scenario = spraysim::scenario::scenes::failing_layer(0.6, 1);
    let mut sim = scenario.build().expect("the default scene builds");
    let maps = |s: &Simulation| {
        let t = &s.targets()[0].surface;
        (t.thickness().as_ptr(), t.hits().as_ptr())
    };
    let before = maps(&sim);
    sim.run(|_| {});
    assert!(!sim.failures().is_empty(), "the layer must fail for this test to mean something");
    assert_eq!(maps(&sim), before, "a deposit map moved while the simulation ran");
}
