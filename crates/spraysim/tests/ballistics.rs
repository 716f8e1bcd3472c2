//! Flight under gravity against its closed form: the exact integrator to rounding, forward and
//! semi-implicit Euler at first order in Δt. (`spraysim validate` runs the same experiment over
//! more steps.)

use spraysim::motion::Integrator;
use spraysim_validate::checks::{landing_x, landing_x_closed_form};

#[test]
fn exact_integrator_lands_where_the_closed_form_says_at_any_step() {
    let exact = landing_x_closed_form();
    for dt in [1e-4, 1e-3, 7e-3, 0.05] {
        let x = landing_x(dt, Integrator::Exact);
        assert!((x - exact).abs() < 1e-12, "dt = {dt}: {x} vs {exact}");
    }
}

#[test]
fn euler_schemes_converge_at_first_order() {
    for scheme in [Integrator::Euler, Integrator::SemiImplicitEuler] {
        let errors: Vec<f64> = [4e-3, 2e-3, 1e-3, 5e-4]
            .iter()
            .map(|&dt| (landing_x(dt, scheme) - landing_x_closed_form()).abs())
            .collect();
        for w in errors.windows(2) {
            let ratio = w[0] / w[1];
            // Halving Δt halves the error: first order (ratio 2), not zeroth (1) or second (4).
            assert!((1.6..2.5).contains(&ratio), "{scheme:?}: errors {errors:?}");
        }
        assert!(errors[0] > 1e-4, "{scheme:?} suspiciously exact: {errors:?}");
    }
}

/// The exact integrator skips the steps of free flight: on the reference wall (a spray, a
/// rebar mesh, a collector floor) it updates particles several times less often than it
/// simulates particle-steps, and lands them where stepping through every step does: the same
/// fates to within a few particles, and the same layer to within sampling noise.
#[test]
fn exact_flights_skip_open_space_without_changing_where_particles_land() {
    use spraysim::Scenario;
    use spraysim::deposit::DepositSurface;
    use spraysim_bench::ReferenceScene;
    let sc = ReferenceScene {
        spawn_rate: 2e5,
        duration: 0.3,
        resolution: 256,
        integrator: Integrator::Exact,
        ..Default::default()
    }
    .scenario()
    // The field curve alone: the cushion law reads the layer, so one outcome tipped by rounding
    // would change the layer later particles meet, and the two runs would drift apart by chance.
    .and_then(|sc| sc.with("process.impact.rebound_model", "polynomial"))
    .expect("the reference scene is valid");
    let run = |lazy: bool, sc: &Scenario| {
        let mut sim = sc.build().expect("valid");
        sim.set_lazy_flight(lazy);
        sim.run(|_| {});
        sim
    };
    let (lazy, every) = (run(true, &sc), run(false, &sc));
    assert_eq!(every.particle_updates(), every.particle_steps());
    let (ls, es) = (lazy.particle_steps(), every.particle_steps());
    assert!(ls.abs_diff(es) * 1000 < es, "the same flights are simulated: {ls} vs {es} particle-steps");
    assert!(
        lazy.particle_updates() * 2 < every.particle_updates(),
        "{} updates with skipping, {} without",
        lazy.particle_updates(),
        every.particle_updates()
    );
    let (a, b) = (lazy.metrics(), every.metrics());
    assert_eq!(a.emitted.count, b.emitted.count);
    // Skipping moves a particle by rounding only (1e-15 m), which can tip a borderline random
    // draw of the impact model for a handful of particles.
    let close = |x: u64, y: u64| x.abs_diff(y) <= 1 + y / 500;
    assert!(
        close(a.fates.stuck_on_targets.count, b.fates.stuck_on_targets.count),
        "{:?} vs {:?}",
        a.fates,
        b.fates
    );
    assert!(
        close(a.fates.stuck_on_obstacles.count, b.fates.stuck_on_obstacles.count),
        "{:?} vs {:?}",
        a.fates,
        b.fates
    );
    assert!(close(a.fates.left_domain.count, b.fates.left_domain.count), "{:?} vs {:?}", a.fates, b.fates);
    let (wa, wb) = (&lazy.targets()[0].surface, &every.targets()[0].surface);
    assert!((wa.volume() - wb.volume()).abs() <= 0.005 * wb.volume(), "{} vs {}", wa.volume(), wb.volume());
}
