//! The documentation matches the code: its scenarios are valid, and the validation report is
//! what `spraysim validate` writes.

use spraysim::Scenario;

fn toml_blocks(markdown: &str) -> Vec<String> {
    markdown
        .split("```toml\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap_or_default().to_string())
        .collect()
}

#[test]
fn readme_and_reference_examples_are_valid_scenarios() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    for doc in ["README.md", "docs/scenario.md"] {
        let text = std::fs::read_to_string(format!("{root}/{doc}")).expect("doc exists");
        let blocks = toml_blocks(&text);
        assert!(!blocks.is_empty(), "{doc} has no example");
        for b in blocks {
            Scenario::from_toml(&b, doc).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

#[test]
fn the_reference_shows_the_default_scene_as_shipped() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let text = std::fs::read_to_string(format!("{root}/docs/scenario.md")).expect("doc exists");
    let shipped = spraysim::scenario::DEFAULT_SCENE;
    let body: String = shipped
        .lines()
        .skip_while(|l| l.starts_with('#') || l.is_empty())
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(toml_blocks(&text).contains(&body), "docs/scenario.md is out of date with the default scene");
}

#[test]
fn the_committed_validation_report_is_what_validate_writes_and_every_check_passes() {
    // The same experiments at the same size as `spraysim validate --output docs`.
    let report = spraysim::validation::report(spraysim::validation::Size::times(10.0), 0, |_| {});
    let failed: Vec<_> = report.verdicts.iter().filter(|v| !v.passed).collect();
    assert!(failed.is_empty(), "failed checks: {failed:#?}");
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let committed =
        std::fs::read_to_string(format!("{root}/docs/validation.md")).expect("docs/validation.md");
    assert!(
        committed == report.markdown,
        "docs/validation.md is out of date: regenerate it with `cargo run --release -- validate --output docs`"
    );
    for (stem, _) in &report.charts {
        assert!(
            std::path::Path::new(&format!("{root}/docs/validation/{stem}.png")).is_file(),
            "{stem}.png missing"
        );
    }
}
