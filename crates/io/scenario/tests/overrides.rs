//! Overrides by dotted key: checked like the file, named in errors, and reproducible.

use spraysim_scenario::{RectangleTarget, Scenario, ScenarioError, TargetShape, Value};

#[test]
fn an_override_changes_one_value_and_keeps_the_rest() {
    let base = Scenario::default_scene();
    let sc = base.with("emitter.spawn_rate", 2e4).expect("valid");
    assert_eq!(sc.emitter().spawn_rate, 2e4);
    assert_eq!(sc.emitter().speed, base.emitter().speed);
    let sc = sc.with("target[1].resolution", Value::Toml("[40, 30]".into())).expect("valid");
    let TargetShape::Rectangle(RectangleTarget { resolution, .. }) = sc.targets()[1].shape else {
        panic!("a rectangle")
    };
    assert_eq!(resolution, [40, 30]);
    // A table the file does not have is created.
    let sc = sc.with("process.cohesion.interval", 0.0).expect("valid");
    assert_eq!(sc.process().cohesion.interval, 0.0);
    // A word, as the command line gives it.
    let sc = base.with_assignment("process.preset=painting").expect("valid");
    assert_eq!(sc.process().preset.name(), "painting");
    assert_eq!(sc.with_assignment("simulation.seed=3").expect("valid").simulation().seed, 3);
}

#[test]
fn a_bad_override_is_refused_naming_the_key_and_the_assignment() {
    let base = Scenario::default_scene();
    let err = base.with("emitter.spawn_rate", -1.0).expect_err("refused");
    let ScenarioError::Invalid { location, key, message } = &err else { panic!("{err}") };
    assert_eq!(key, "emitter.spawn_rate");
    assert!(location.starts_with("--set emitter.spawn_rate=-1"), "{location}");
    assert!(message.contains("greater than 0"), "{message}");
    let err = base.with("emitter.no_such_key", 1.0).expect_err("refused").to_string();
    assert!(err.contains("`emitter.no_such_key` is not a key"), "{err}");
    let err = base.with("target[9].size", [1.0, 1.0]).expect_err("refused").to_string();
    assert!(err.contains("`target[9].size`") && err.contains("has 2"), "{err}");
    let err = base.with_assignment("simulation.seed").expect_err("refused").to_string();
    assert!(err.contains("KEY=VALUE"), "{err}");
}

#[test]
fn numbers_survive_the_round_trip_through_text_exactly() {
    let base = Scenario::default_scene();
    for x in [0.1 + 0.2, 1.0 / 3.0, 2.5e-7, 2_345.678_901_234_57] {
        let sc = base.with("process.density", x).expect("valid");
        assert_eq!(sc.process().density.to_bits(), x.to_bits(), "{x}");
    }
}
