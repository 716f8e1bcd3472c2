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

/// Overrides are applied together and checked once: a circle's radius and frequency (each
/// refused alone) may come in either order, and a table set whole takes the keys set inside it
/// whichever comes first.
#[test]
fn overrides_are_applied_together_so_their_order_does_not_matter() {
    use spraysim_scenario::NozzleMotion;
    let base = Scenario::default_scene();
    let radius = ("nozzle.circle_radius".to_string(), Value::Number(0.05));
    let frequency = ("nozzle.circle_frequency".to_string(), Value::Number(2.0));
    let one = base.with_all(&[radius.clone(), frequency.clone()]).unwrap_or_else(|e| panic!("{e}"));
    let other = base.with_all(&[frequency.clone(), radius.clone()]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(one, other);
    assert!(matches!(one.nozzle().motion, NozzleMotion::Circling { circle_radius: 0.05, .. }));
    // As the command line gives them.
    for set in [
        ["nozzle.circle_radius=0.05", "nozzle.circle_frequency=2"],
        ["nozzle.circle_frequency=2", "nozzle.circle_radius=0.05"],
    ] {
        assert_eq!(base.with_assignments(&set).unwrap_or_else(|e| panic!("{set:?}: {e}")), one);
    }
    // A whole table and a key inside it, either way round.
    let table = "nozzle={raster={target=\"wall\"}}";
    let speed = "nozzle.raster.speed=2";
    let a = base.with_assignments(&[table, speed]).unwrap_or_else(|e| panic!("{e}"));
    let b = base.with_assignments(&[speed, table]).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(a, b);
    let NozzleMotion::Raster { raster } = &a.nozzle().motion else { panic!("a raster") };
    assert_eq!((raster.target.as_str(), raster.plan.speed), ("wall", 2.0));
    // A key set twice takes the later value.
    let twice = base.with_assignments(&["simulation.seed=3", "simulation.seed=4"]).expect("valid");
    assert_eq!(twice.simulation().seed, 4);
}

/// The default scene's nozzle is static: a raster set into its table is refused (a nozzle moves
/// one way), naming the override rather than the built-in file's `position` and `axis`, and
/// saying how to replace the table; the table set whole is a raster nozzle.
#[test]
fn a_motion_of_another_kind_replaces_the_whole_nozzle_table() {
    use spraysim_scenario::NozzleMotion;
    let base = Scenario::default_scene();
    let err = base.with("nozzle.raster", Value::Toml("{target=\"wall\"}".into())).expect_err("refused");
    let ScenarioError::Invalid { location, key, message } = &err else { panic!("{err}") };
    assert_eq!(location, "--set nozzle.raster={target=\"wall\"}");
    assert_eq!(key, "nozzle.raster");
    assert_eq!(
        message,
        "belongs to a raster nozzle, but [nozzle] also has `nozzle.position` and `nozzle.axis`, keys of a static or \
         circling nozzle: a nozzle moves one way only; to change how it moves, set the whole table, \
         which replaces the scenario's: nozzle={raster = {target = \"wall\"}}"
    );
    let sc = base
        .with("nozzle", Value::Toml("{raster={target=\"wall\"}}".into()))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(&sc.nozzle().motion, NozzleMotion::Raster { raster } if raster.target == "wall"));
    // In a file, the same conflict names the file's line and asks for one motion.
    let text = format!("{}\n[nozzle.raster]\ntarget = \"wall\"\n", spraysim_scenario::DEFAULT_SCENE);
    let err = Scenario::from_toml(&text, "wall.toml").expect_err("refused").to_string();
    assert!(err.starts_with("wall.toml:"), "{err}");
    assert!(
        err.contains("`nozzle.raster` belongs to a raster nozzle")
            && err.ends_with("give the keys of one motion only"),
        "{err}"
    );
}

/// A refusal whose key the file gave, caused by an override, names the override: the file was
/// valid without it.
#[test]
fn a_refusal_of_a_files_key_caused_by_an_override_names_the_override() {
    let raster =
        format!("{}[nozzle.raster]\ntarget = \"wall\"\n", spraysim_scenario::scenes::wall_scene(0.05, 32));
    let base = Scenario::from_toml(&raster, "raster.toml").unwrap_or_else(|e| panic!("{e}"));
    let err = base
        .with_assignments(&["simulation.seed=3", "target[0].name=panel", "simulation.dt=0.0005"])
        .expect_err("refused");
    let ScenarioError::Invalid { location, key, .. } = &err else { panic!("{err}") };
    assert_eq!(
        (location.as_str(), key.as_str()),
        ("--set target[0].name=\"panel\"", "nozzle.raster.target"),
        "{err}"
    );
}
