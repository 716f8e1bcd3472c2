//! Flight under gravity against its closed form: the exact integrator to rounding, forward and
//! semi-implicit Euler at first order in Δt. (`spraysim validate` runs the same experiment over
//! more steps.)

use spraysim::integrator::Integrator;
use spraysim::validation::checks::{landing_x, landing_x_closed_form};

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
