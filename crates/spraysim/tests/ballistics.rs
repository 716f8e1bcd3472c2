//! Flight under gravity against its closed form: the exact integrator to rounding, forward and
//! semi-implicit Euler at first order in Δt.

use spraysim::integrator::Integrator;
use spraysim::{Scenario, Simulation};

/// A single horizontal shot from 1.2 m onto a floor collector: where does it land?
fn landing_x(dt: f64, integrator: Integrator) -> f64 {
    let mut sc = Scenario::from_toml(
        &format!(
            r#"
            [simulation]
            dt = {dt}
            duration = {dt}
            [emitter]
            shape = "point"
            cone_angle = 0.0
            speed = [7.0, 7.0]
            spawn_rate = {rate}
            [process.impact]
            rebound_model = "never"
            # One particle: spraying during the first step only.
            [[nozzle.waypoints]]
            time = 0.0
            position = [0.0, 0.0, 1.2]
            axis = [1.0, 0.0, 0.0]
            [[nozzle.waypoints]]
            time = {half}
            position = [0.0, 0.0, 1.2]
            axis = [1.0, 0.0, 0.0]
            spray = false
            [[target]]
            name = "floor"
            center = [5.0, 0.0, 0.0]
            normal = [0.0, 0.0, 1.0]
            up = [1.0, 0.0, 0.0]
            size = [2.0, 10.0] # 2 m wide (y), 10 m along up (x)
            resolution = [8, 8]
            "#,
            rate = 1.0 / dt,
            half = dt / 2.0
        ),
        "shot",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    sc.simulation.integrator = integrator;
    let mut sim = Simulation::new(&sc).expect("valid");
    sim.step(); // emits the one particle
    while sim.swarm().alive() > 0 {
        sim.step();
    }
    let m = sim.metrics();
    assert_eq!(m.emitted.count, 1);
    assert_eq!(m.targets[0].stuck.count, 1, "the shot must land on the floor");
    // The particle's last position is where it stuck.
    sim.swarm().pos[0].x
}

/// Closed form: x = v √(2h/g).
fn exact_x() -> f64 {
    7.0 * (2.0 * 1.2 / 9.81_f64).sqrt()
}

#[test]
fn exact_integrator_lands_where_the_closed_form_says_at_any_step() {
    for dt in [1e-4, 1e-3, 7e-3, 0.05] {
        let x = landing_x(dt, Integrator::Exact);
        assert!((x - exact_x()).abs() < 1e-12, "dt = {dt}: {x} vs {}", exact_x());
    }
}

#[test]
fn euler_schemes_converge_at_first_order() {
    for scheme in [Integrator::Euler, Integrator::SemiImplicitEuler] {
        let errors: Vec<f64> =
            [4e-3, 2e-3, 1e-3, 5e-4].iter().map(|&dt| (landing_x(dt, scheme) - exact_x()).abs()).collect();
        for w in errors.windows(2) {
            let ratio = w[0] / w[1];
            // Halving Δt halves the error: first order (ratio 2), not zeroth (1) or second (4).
            assert!((1.6..2.5).contains(&ratio), "{scheme:?}: errors {errors:?}");
        }
        assert!(errors[0] > 1e-4, "{scheme:?} suspiciously exact: {errors:?}");
    }
}
