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
    let report = spraysim_validate::report(spraysim_validate::Size::times(10.0), 0, |_| {});
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

/// `docs/architecture.md` describes every crate of the workspace, and every path it names exists.
#[test]
fn the_architecture_document_matches_the_workspace() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let doc = std::fs::read_to_string(format!("{root}/docs/architecture.md")).expect("docs/architecture.md");
    let manifest = std::fs::read_to_string(format!("{root}/Cargo.toml")).expect("Cargo.toml");
    let members: Vec<&str> = manifest
        .split("members = [")
        .nth(1)
        .and_then(|rest| rest.split(']').next())
        .expect("workspace members")
        .split(',')
        .map(|m| m.trim().trim_matches('"'))
        .filter(|m| !m.is_empty())
        .collect();
    assert!(members.len() >= 8, "{members:?}");
    for m in &members {
        assert!(doc.contains(&format!("(`{m}`)")), "docs/architecture.md does not describe {m}");
    }
    // Every `crates/…` or `engine/src/…` path in backquotes exists.
    for quoted in doc.split('`').skip(1).step_by(2) {
        let path = if quoted.starts_with("crates/") {
            quoted.to_string()
        } else if quoted.starts_with("engine/src/") || quoted.starts_with("io/scenario/src/") {
            format!("crates/{quoted}")
        } else {
            continue;
        };
        assert!(
            std::path::Path::new(&format!("{root}/{path}")).exists(),
            "docs/architecture.md names {path}, which does not exist"
        );
    }
}
