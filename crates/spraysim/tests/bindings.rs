//! What language bindings rely on: `Simulation::particle_now` gives every particle's state at
//! the present time, also for the particles that the exact integrator lets sleep through free
//! flight; a deposit surface's maps keep their storage while it runs (so they can be viewed
//! without a copy).

use spraysim::deposit::DepositSurface;
use spraysim::motion::Integrator;
use spraysim::particles::flags;
use spraysim::{Scenario, Simulation, SimulationConfig};

fn exact_wall(lazy: bool) -> Simulation {
    let mut config = SimulationConfig::example_wall(0.2);
    config.motion.integrator = Integrator::Exact;
    let mut sim = Simulation::new(config).expect("the example wall is valid");
    sim.set_lazy_flight(lazy);
    sim
}

#[test]
fn sleeping_particles_are_reported_where_they_are_now() {
    let (mut lazy, mut eager) = (exact_wall(true), exact_wall(false));
    for _ in 0..30 {
        lazy.step();
        eager.step();
    }
    let (ls, es) = (lazy.swarm(), eager.swarm());
    assert_eq!(ls.id, es.id, "both runs hold the same particles");
    let mut asleep = 0;
    for i in 0..ls.len() {
        if ls.flags[i] & flags::ALIVE == 0 {
            continue;
        }
        asleep += usize::from(ls.pos[i] != es.pos[i]);
        let (pos, vel, age) = lazy.particle_now(i);
        assert!((pos - es.pos[i]).length() < 1e-9, "slot {i}: {pos} against {}", es.pos[i]);
        assert!((vel - es.vel[i]).length() < 1e-9, "slot {i}: {vel} against {}", es.vel[i]);
        assert!((age - f64::from(es.age[i])).abs() < 1e-5, "slot {i}: age {age} against {}", es.age[i]);
        // Awake particles are reported exactly as stored.
        assert_eq!(eager.particle_now(i), (es.pos[i], es.vel[i], f64::from(es.age[i])));
    }
    assert!(asleep > 100, "the lazy run must have particles asleep ahead of time, found {asleep}");
}

#[test]
fn deposit_maps_keep_their_storage_while_layers_grow_and_fail() {
    // A weak, barely cohesive layer fails as it grows (analysed every 0.1 s).
    let scenario = Scenario::default_scene()
        .with_all(&[
            ("simulation.duration".into(), 0.6.into()),
            ("process.cohesion.interval".into(), 0.1.into()),
            ("process.cohesion.shear_strength".into(), 300.0.into()),
            ("process.cohesion.cohesion".into(), 1.0.into()),
        ])
        .expect("valid overrides");
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
