//! Bad scenarios are refused with the file, the line and the key.

use spraysim::{Scenario, ScenarioError};

const GOOD: &str = r#"[simulation]
dt = 0.001
duration = 1.0

[process]
preset = "shotcrete"

[emitter]
spawn_rate = 1000.0

[nozzle]
position = [-1.0, 0.0, 1.0]
axis = [1.0, 0.0, 0.0]

[[target]]
name = "wall"
center = [0.0, 0.0, 1.0]
normal = [-1.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
size = [2.0, 2.0]
resolution = [64, 64]
"#;

/// `GOOD` with the line that starts with `key =` replaced (or, if absent, `line` appended after
/// the section header `section`).
fn with(section: &str, key: &str, line: &str) -> String {
    let mut out = Vec::new();
    let mut replaced = false;
    for l in GOOD.lines() {
        if !replaced && l.starts_with(&format!("{key} =")) {
            out.push(line.to_string());
            replaced = true;
        } else {
            out.push(l.to_string());
        }
    }
    if !replaced {
        let at = out.iter().position(|l| l == section).unwrap_or_else(|| panic!("no {section}"));
        out.insert(at + 1, line.to_string());
    }
    out.join("\n")
}

fn refused(text: &str) -> String {
    match Scenario::from_toml(text, "scene.toml") {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines()
        .position(|l| l.contains(needle))
        .map(|i| i + 1)
        .unwrap_or_else(|| panic!("{needle} not in text"))
}

#[test]
fn the_good_scenario_is_accepted() {
    let sc = Scenario::from_toml(GOOD, "scene.toml").unwrap_or_else(|e| panic!("{e}"));
    let spraysim::scenario::TargetShape::Rectangle(spraysim::scenario::RectangleTarget {
        resolution, ..
    }) = sc.targets()[0].shape
    else {
        panic!("a rectangle")
    };
    assert_eq!(resolution, [64, 64]);
    assert_eq!(sc.emitter().spawn_rate, 1000.0);
    assert_eq!(sc.emitter().speed, [20.0, 30.0]); // from the preset
}

#[test]
fn invalid_values_name_file_line_and_key() {
    let cases: &[(&str, &str, &str, &str, &str)] = &[
        ("[simulation]", "dt", "dt = -0.001", "simulation.dt", "greater than 0"),
        ("[simulation]", "dt", "dt = 0.0", "simulation.dt", "greater than 0"),
        ("[simulation]", "dt", "dt = nan", "simulation.dt", "finite"),
        ("[simulation]", "duration", "duration = inf", "simulation.duration", "finite"),
        ("[simulation]", "dt", "dt = 5.0", "simulation.dt", "between"),
        ("[emitter]", "spawn_rate", "spawn_rate = -5.0", "emitter.spawn_rate", "greater than 0"),
        ("[emitter]", "speed", "speed = [30.0, 20.0]", "emitter.speed", "min ≤ max"),
        ("[emitter]", "cone_angle", "cone_angle = 200.0", "emitter.cone_angle", "between"),
        ("[process]", "flow_rate", "flow_rate = 0.0", "process.flow_rate", "greater than 0"),
        ("[nozzle]", "axis", "axis = [0.0, 0.0, 0.0]", "nozzle.axis", "zero-length"),
        ("[[target]]", "normal", "normal = [0.0, 0.0, 0.0]", "target[0].normal", "zero-length"),
        ("[[target]]", "up", "up = [-2.0, 0.0, 0.0]", "target[0].up", "parallel"),
        ("[[target]]", "resolution", "resolution = [0, 64]", "target[0].resolution", "between 1 and 4096"),
        ("[[target]]", "resolution", "resolution = [64, 5000]", "target[0].resolution", "between 1 and 4096"),
        ("[[target]]", "size", "size = [2.0, -1.0]", "target[0].size", "greater than 0"),
        ("[[target]]", "name", "name = \"my wall\"", "target[0].name", "letters"),
    ];
    for &(section, key, line, path, why) in cases {
        let text = with(section, key, line);
        let msg = refused(&text);
        let at = line_of(&text, line);
        assert!(msg.starts_with(&format!("scene.toml:{at}: `{path}`")), "{line}: got {msg}");
        assert!(msg.contains(why), "{line}: got {msg}");
    }
}

#[test]
fn process_impact_overrides_are_checked() {
    let text = format!("{GOOD}\n[process.impact]\nrestitution = 1.5\n");
    let msg = refused(&text);
    let at = line_of(&text, "restitution = 1.5");
    assert!(
        msg.starts_with(&format!("scene.toml:{at}: `process.impact.restitution` must be between 0 and 1")),
        "{msg}"
    );
}

/// Unknown keys, wrong types and unknown words name their key and line, like range errors.
#[test]
fn unknown_keys_wrong_types_and_unknown_presets_name_the_key() {
    for (section, key, line, expect) in [
        ("[simulation]", "dtt", "dtt = 0.001", "`simulation.dtt` is not a key of [simulation]"),
        ("[[target]]", "colour", "colour = \"red\"", "`target[0].colour` is not a key of a rectangle target"),
        (
            "[simulation]",
            "dt",
            "dt = \"fast\"",
            "`simulation.dt` must be a number (s), got the string \"fast\"",
        ),
        ("[simulation]", "dt", "dt = [0.001]", "`simulation.dt` must be a number (s), got an array"),
        ("[[target]]", "name", "name = [\"wall\"]", "`target[0].name` must be a string, got an array"),
        ("[process]", "preset", "preset = \"gunite\"", "`process.preset` must be one of \"shotcrete\""),
        ("[[target]]", "size", "size = [2.0, 2.0, 2.0]", "`target[0].size` must be an array of 2 numbers"),
        ("[emitter]", "spawn_rate", "shape = \"triangle\"", "`emitter.shape` must be one of \"point\""),
    ] {
        let text = with(section, key, line);
        let msg = refused(&text);
        let at = line_of(&text, line);
        assert!(msg.starts_with(&format!("scene.toml:{at}:")), "{line}: got {msg}");
        assert!(msg.contains(expect), "{line}: got {msg}");
    }
    let missing = GOOD.replace("up = [0.0, 0.0, 1.0]\n", "");
    let msg = refused(&missing);
    assert!(msg.contains("`target[0].up` is required"), "{msg}");
}

/// Keys the chosen shape or model does not use are refused, NaN or not: they would otherwise be
/// silently ignored.
#[test]
fn keys_of_another_shape_are_refused() {
    for (section, line, expect) in [
        ("[emitter]", "width = nan", "`emitter.width` is not a key of an emitter with shape = \"circle\""),
        ("[emitter]", "fan_wide_angle = 30.0", "`emitter.fan_wide_angle` is not a key of an emitter"),
        (
            "[process]",
            "erosion.oka_hv = 2.0",
            "`process.erosion.oka_hv` is not a key of [process.erosion] with model = \"none\"",
        ),
        ("[nozzle]", "circle_frequency = nan", "`nozzle.circle_frequency` must be a finite number"),
    ] {
        let text = with(section, "no such key", line);
        let msg = refused(&text);
        assert!(msg.contains(expect), "{line}: got {msg}");
    }
}

#[test]
fn obstacles_need_the_keys_of_their_shape_and_no_others() {
    let base = format!(
        "{GOOD}\n[[obstacle]]\nname = \"bar\"\nshape = \"cylinder\"\nstart = [0.0, 0.0, 0.0]\nend = [0.0, 0.0, 1.0]\n"
    );
    let msg = refused(&base);
    assert!(msg.contains("`obstacle[0].radius` is required for a cylinder"), "{msg}");
    let msg = refused(&format!("{base}radius = 0.01\nnormal = [1.0, 0.0, 0.0]\n"));
    assert!(msg.contains("`obstacle[0].normal` is not a key of a cylinder obstacle"), "{msg}");
    let msg =
        refused(&format!("{base}radius = 0.01\n").replace("end = [0.0, 0.0, 1.0]", "end = [0.0, 0.0, 0.0]"));
    assert!(msg.contains("`obstacle[0].end` must differ from start"), "{msg}");
    let dup = format!("{base}radius = 0.01\n").replace("name = \"bar\"", "name = \"wall\"");
    assert!(refused(&dup).contains("used twice"));
}

#[test]
fn a_missing_file_is_named() {
    let err = Scenario::from_path(std::path::Path::new("/nonexistent/scene.toml")).expect_err("no such file");
    assert!(matches!(err, ScenarioError::Read { .. }));
    assert!(err.to_string().starts_with("/nonexistent/scene.toml: cannot read"));
}

#[test]
fn the_resolved_scenario_round_trips() {
    let sc = Scenario::default_scene();
    let again = Scenario::from_toml(&sc.to_toml(), "resolved").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sc, again);
}
