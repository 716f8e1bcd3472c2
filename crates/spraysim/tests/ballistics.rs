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

/// Particles coast through the steps their flight certainly clears: on the reference wall (a
/// spray, a rebar mesh, a collector floor) most particle-steps are coasted, not searched, and
/// the run ends with the same particles, layers and metrics, to the bit, as one that searches
/// every step, for both kinds
/// of integrator.
#[test]
fn coasting_skips_most_searches_without_changing_anything() {
    use spraysim::deposit::DepositSurface;
    use spraysim_bench::ReferenceScene;
    for integrator in [Integrator::Euler, Integrator::Exact] {
        let sc = ReferenceScene {
            spawn_rate: 2e5,
            duration: 0.3,
            resolution: 256,
            integrator,
            ..Default::default()
        }
        .scenario()
        .expect("the reference scene is valid");
        let run = |coasting: bool| {
            let mut sim = sc.build().expect("valid");
            sim.set_coasting(coasting);
            sim.run(|_| {});
            sim
        };
        let (coasted, searched) = (run(true), run(false));
        assert_eq!(searched.particle_updates(), searched.particle_steps());
        assert_eq!(coasted.particle_steps(), searched.particle_steps());
        assert!(
            coasted.particle_updates() * 5 < searched.particle_updates(),
            "{integrator:?}: {} searches with coasting, {} without",
            coasted.particle_updates(),
            searched.particle_updates()
        );
        assert!(coasted.swarm() == searched.swarm(), "{integrator:?}: the particles differ");
        assert!(
            format!("{:?}", coasted.metrics()) == format!("{:?}", searched.metrics()),
            "{integrator:?}: the metrics differ"
        );
        for (a, b) in coasted.targets().iter().zip(searched.targets()) {
            assert!(
                a.surface.thickness() == b.surface.thickness() && a.surface.hits() == b.surface.hits(),
                "{integrator:?}: {} differs",
                a.name
            );
        }
    }
}
