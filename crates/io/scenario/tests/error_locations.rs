//! Every refusal points at where the mistake was made: the override that made it, the line
//! and key of the file, the row of a tool path; and prints its numbers compactly.

use spraysim_scenario::scenes::wall_scene;
use spraysim_scenario::{Scenario, ScenarioError};

/// The wall scene the tests change: 0.05 s onto the wall at 32 × 32 cells.
fn wall() -> String {
    wall_scene(0.05, 32)
}

/// The location, key and message of a refusal that names a key.
fn invalid(result: Result<Scenario, ScenarioError>) -> (String, String, String) {
    match result {
        Err(ScenarioError::Invalid { location, key, message }) => (location, key, message),
        Err(other) => panic!("refused without a key: {other}"),
        Ok(_) => panic!("accepted"),
    }
}

#[test]
fn an_unknown_key_given_as_an_override_is_blamed_on_the_override() {
    let file = Scenario::from_toml(&wall(), "wall.toml").expect("valid");
    for base in [Scenario::default_scene(), file] {
        let err = base.with_assignment("foo.bar=1").expect_err("no such key");
        assert!(err.to_string().starts_with("--set foo.bar=1: `foo` is not a key of a scenario"), "{err}");
        let err = base.with_assignment("simulation.foo.bar=1").expect_err("no such key");
        assert!(
            err.to_string().starts_with("--set simulation.foo.bar=1: `simulation.foo` is not a key"),
            "{err}"
        );
    }
}

#[test]
fn an_override_with_a_quoted_key_reads_it_as_toml_does() {
    let base = Scenario::default_scene();
    // Quoted parts are keys like bare ones.
    let sc = base.with_assignment(r#"simulation."dt"=0.002"#).expect("the key simulation.dt");
    assert_eq!(sc.simulation().dt, 0.002);
    let sc = base.with_assignment(r#"'target'[1]."resolution"=[40, 30]"#).expect("target[1].resolution");
    assert_eq!(sc, base.with_assignment("target[1].resolution=[40, 30]").expect("valid"));
    // A quoted key with a dot in it is one key, which no scenario has: the override is blamed.
    let (location, key, message) = invalid(base.with_assignment(r#""simulation.dt"=0.001"#));
    assert_eq!(location, r#"--set "simulation.dt"=0.001"#);
    assert_eq!(key, r#""simulation.dt""#);
    assert!(
        message.contains("is not a key of a scenario") && message.contains("without quotes"),
        "{message}"
    );
    let err = base.with_assignment(r#""simulation=0.001"#).expect_err("a quote left open");
    assert!(err.to_string().starts_with(r#"--set "simulation=0.001: "#), "{err}");
    assert!(err.to_string().contains("quote"), "{err}");
}

#[test]
fn a_table_or_key_given_twice_is_refused_naming_it() {
    for (text, line, key) in [
        ("[simulation]\ndt = 0.001\n[simulation]\nseed = 3\n", 3, "simulation"),
        ("[simulation]\ndt = 0.001\nseed = 3\ndt = 0.002\n", 4, "simulation.dt"),
        ("[[target]]\nname = \"a\"\nname = \"b\"\n", 3, "target[0].name"),
        ("seed = 1\n[nozzle.raster]\nspeed = 1\n[nozzle.raster]\n", 4, "nozzle.raster"),
    ] {
        let (location, named, message) = invalid(Scenario::from_toml(text, "t.toml"));
        assert_eq!(location, format!("t.toml:{line}"), "{text}");
        assert_eq!(named, key, "{text}");
        assert!(message.contains("given twice"), "{message}");
    }
}

#[test]
fn a_nul_byte_is_refused_at_its_line_as_not_allowed_in_toml() {
    let text = format!("{}splat_radius = 0.01\0\n", wall());
    let err = Scenario::from_toml(&text, "t.toml").expect_err("a NUL byte");
    let ScenarioError::Syntax { location, message } = &err else { panic!("{err}") };
    assert_eq!(location, &format!("t.toml:{}", text.lines().count()));
    assert!(message.contains("NUL") && message.contains("TOML does not allow"), "{message}");
    assert!(message.contains("column 20"), "{message}");
    // In a comment, too.
    let err = Scenario::from_toml("# a\0b\n[simulation]\n", "t.toml").expect_err("a NUL byte");
    assert!(
        err.to_string().starts_with("t.toml:1: column 4 holds the control character U+0000 (NUL)"),
        "{err}"
    );
}

#[test]
fn an_integer_beyond_64_bits_is_refused_as_such_naming_the_key() {
    for (text, key) in [
        ("[simulation]\nseed = 18446744073709551615\n", "simulation.seed"),
        ("[simulation]\nseed = 99999999999999999999999\n", "simulation.seed"),
        ("[simulation]\nduration = 18446744073709551615\n", "simulation.duration"),
        ("[simulation]\ngravity = [0, 0, -18446744073709551615]\n", "simulation.gravity"),
    ] {
        let (location, named, message) = invalid(Scenario::from_toml(text, "t.toml"));
        assert_eq!((location.as_str(), named.as_str()), ("t.toml:2", key), "{text}");
        assert!(message.contains("TOML integers are 64-bit"), "{text}: {message}");
        assert!(!message.contains("string"), "{text}: {message}");
    }
    let (_, _, message) = invalid(Scenario::from_toml("[simulation]\nseed = 18446744073709551615\n", "t"));
    assert!(message.contains("between 0 and 9223372036854775807"), "{message}");
}

#[test]
fn numbers_in_messages_print_compactly_at_any_magnitude() {
    for (text, shown) in [
        ("[simulation]\ndt = 1e308\n", "got 1e308"),
        ("[simulation]\nduration = -1e300\n", "got -1e300"),
        ("[simulation]\ndt = 1e-300\n", "got 1e-300"),
        ("[simulation]\nseed = 1e308\n", "got the number 1e308"),
        ("[simulation]\ndt = 1e400\n", "1e400, beyond the largest 64-bit float"),
        ("[simulation]\ngravity = [0, 0, 1e308]\n", "got 1e308"),
    ] {
        let (_, _, message) = invalid(Scenario::from_toml(text, "t.toml"));
        assert!(message.contains(shown), "{text}: {message}");
        assert!(message.len() < 200, "{text}: {message}");
    }
    // Everyday numbers as written.
    let (_, _, message) = invalid(Scenario::from_toml("[simulation]\ndt = 0.5\n", "t.toml"));
    assert!(message.contains("between 0 and 0.1 s, got 0.5"), "{message}");
}

#[test]
fn a_refused_override_is_blamed_on_the_override_even_in_a_table_it_made() {
    let base = Scenario::from_toml(&wall(), "wall.toml").expect("valid");
    let (location, key, _) = invalid(base.with("target[0].size", [-1.0, 1.0]));
    assert_eq!((location.as_str(), key.as_str()), ("--set target[0].size=[-1.0, 1.0]", "target[0].size"));
    let (location, key, _) = invalid(base.with("process.impact.no_such_key", 1.0));
    assert_eq!(
        (location.as_str(), key.as_str()),
        ("--set process.impact.no_such_key=1.0", "process.impact.no_such_key")
    );
    // A key of the file that an override replaced is the override's; the others stay the file's.
    let (location, _, _) = invalid(base.with("simulation.duration", -1.0));
    assert_eq!(location, "--set simulation.duration=-1.0");
    let text = wall().replace("resolution = [32, 32]", "resolution = [32, 0]");
    let line = text.lines().position(|l| l.starts_with("resolution")).map_or(0, |i| i + 1);
    let (location, key, _) = invalid(Scenario::from_toml(&text, "wall.toml"));
    assert_eq!((location, key.as_str()), (format!("wall.toml:{line}"), "target[0].resolution"));
}
