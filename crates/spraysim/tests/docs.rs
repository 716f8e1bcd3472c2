//! The documentation matches the code: its scenarios are valid, the validation report is what
//! `spraysim validate` writes, the architecture names every crate, its links lead somewhere, and
//! the README stays a front page. (The README's commands and the default run's printed output
//! are checked against the command itself in `crates/apps/cli/tests/readme.rs`; its Rust
//! examples run as doctests of the `spraysim` crate.)

use spraysim::Scenario;

/// The repository's root.
const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// The README and every page of `docs/`, as (path from the root, text).
fn markdown_pages() -> Vec<(String, String)> {
    let mut pages = vec!["README.md".to_string()];
    let mut docs: Vec<String> = std::fs::read_dir(format!("{ROOT}/docs"))
        .expect("docs/")
        .map(|e| e.expect("docs/ entry").file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".md"))
        .map(|name| format!("docs/{name}"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(format!("{ROOT}/{p}")).unwrap_or_else(|e| panic!("{p}: {e}"));
            (p, text)
        })
        .collect()
}

fn toml_blocks(markdown: &str) -> Vec<String> {
    markdown
        .split("```toml\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap_or_default().to_string())
        .collect()
}

/// Every TOML block of the README and of `docs/` is a valid scenario; the usage guide (which
/// holds the README's former example) and the reference have at least one.
#[test]
fn readme_and_reference_examples_are_valid_scenarios() {
    let pages = markdown_pages();
    for must in ["docs/usage.md", "docs/scenario.md"] {
        let (_, text) = pages.iter().find(|(p, _)| p == must).unwrap_or_else(|| panic!("{must} missing"));
        assert!(!toml_blocks(text).is_empty(), "{must} has no example");
    }
    for (doc, text) in &pages {
        for b in toml_blocks(text) {
            Scenario::from_toml(&b, doc).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}

#[test]
fn the_reference_shows_the_default_scene_as_shipped() {
    let text = std::fs::read_to_string(format!("{ROOT}/docs/scenario.md")).expect("doc exists");
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
    let committed =
        std::fs::read_to_string(format!("{ROOT}/docs/validation.md")).expect("docs/validation.md");
    assert!(
        committed == report.markdown,
        "docs/validation.md is out of date: regenerate it with `cargo run --release -- validate --output docs`"
    );
    for (stem, _) in &report.charts {
        assert!(
            std::path::Path::new(&format!("{ROOT}/docs/validation/{stem}.png")).is_file(),
            "{stem}.png missing"
        );
    }
}

/// `docs/architecture.md` lists every crate of the workspace in its table, one row per crate
/// with its folder, and every path it or `docs/engine.md` (the crates' internals) names exists.
#[test]
fn the_architecture_document_matches_the_workspace() {
    let doc = std::fs::read_to_string(format!("{ROOT}/docs/architecture.md")).expect("docs/architecture.md");
    let engine = std::fs::read_to_string(format!("{ROOT}/docs/engine.md")).expect("docs/engine.md");
    let manifest = std::fs::read_to_string(format!("{ROOT}/Cargo.toml")).expect("Cargo.toml");
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
        let rows = doc.lines().filter(|l| l.starts_with('|') && l.contains(&format!("| `{m}` |"))).count();
        assert_eq!(rows, 1, "docs/architecture.md's crate table has {rows} rows for {m}, not one");
    }
    // Every `crates/…` or `engine/src/…` path in backquotes exists.
    for (name, text) in [("docs/architecture.md", &doc), ("docs/engine.md", &engine)] {
        for quoted in text.split('`').skip(1).step_by(2) {
            let path = if quoted.starts_with("crates/") {
                quoted.to_string()
            } else if quoted.starts_with("engine/src/") || quoted.starts_with("io/scenario/src/") {
                format!("crates/{quoted}")
            } else {
                continue;
            };
            assert!(
                std::path::Path::new(&format!("{ROOT}/{path}")).exists(),
                "{name} names {path}, which does not exist"
            );
        }
    }
}

/// GitHub's anchor for a heading: lower case, spaces to hyphens, other punctuation dropped.
fn anchor(heading: &str) -> String {
    heading
        .trim()
        .chars()
        .filter_map(|c| match c {
            ' ' | '-' => Some('-'),
            '_' => Some('_'),
            c if c.is_alphanumeric() => Some(c),
            _ => None,
        })
        .flat_map(char::to_lowercase)
        .collect()
}

/// The lines of a page outside its code blocks (a line beginning with ```` ``` ```` opens or
/// closes one, and is itself left out).
fn prose(text: &str) -> impl Iterator<Item = &str> {
    let mut fenced = false;
    text.lines().filter(move |line| {
        if line.starts_with("```") {
            fenced = !fenced;
            return false;
        }
        !fenced
    })
}

/// The anchors of a page's headings (outside code blocks).
fn anchors(text: &str) -> Vec<String> {
    prose(text)
        .filter(|line| line.starts_with('#'))
        .map(|line| anchor(line.trim_start_matches('#')))
        .collect()
}

/// The targets of a page's Markdown links and images, `](target)`, outside code blocks.
fn links(text: &str) -> Vec<String> {
    prose(text)
        .flat_map(|line| line.split("](").skip(1))
        .filter_map(|part| part.find(')').map(|end| part[..end].to_string()))
        .collect()
}

/// Every relative link of the README and `docs/` leads to a file that exists, and every
/// `#anchor` to a heading of its page, so that nothing points into a section that moved.
#[test]
fn the_documents_links_lead_somewhere() {
    let root = std::path::Path::new(ROOT);
    let mut broken = Vec::new();
    for (page, text) in markdown_pages() {
        let dir = root.join(&page).parent().expect("a page's folder").to_path_buf();
        for link in links(&text) {
            if link.starts_with("http://") || link.starts_with("https://") || link.starts_with("mailto:") {
                continue;
            }
            let (file, fragment) = link.split_once('#').map_or((link.as_str(), None), |(f, a)| (f, Some(a)));
            let target = if file.is_empty() { root.join(&page) } else { dir.join(file) };
            if !target.exists() {
                broken.push(format!("{page}: {link} (no such file)"));
                continue;
            }
            if let Some(fragment) = fragment {
                let heads = std::fs::read_to_string(&target).map(|t| anchors(&t)).unwrap_or_default();
                if !heads.iter().any(|h| h == fragment) {
                    broken.push(format!("{page}: {link} (no such heading)"));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
}

/// The README is a front page: short, with the two commands, a picture and the commands table
/// on its first screen (the first 60 lines).
#[test]
fn the_readme_is_a_front_page() {
    let text = std::fs::read_to_string(format!("{ROOT}/README.md")).expect("README.md");
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.len() <= 200, "README.md has {} lines; move detail into docs/", lines.len());
    let first = lines[..lines.len().min(60)].join("\n");
    for must in ["cargo run --release -- run", "cargo test", "![", "| command | what it does |"] {
        assert!(first.contains(must), "the README's first screen lacks {must:?}");
    }
}

/// The README's test command is the line `.ci/run` runs, and it builds only the core: nothing
/// in the dependency tree of the workspace's default members (normal, dev and build
/// dependencies) is wgpu, eframe or pyo3.
#[test]
fn the_readme_test_command_is_what_ci_runs_and_builds_no_gpu_window_or_python_crate() {
    let readme = std::fs::read_to_string(format!("{ROOT}/README.md")).expect("README.md");
    let command = readme
        .lines()
        .find(|l| l.starts_with("cargo test"))
        .and_then(|l| l.split('#').next())
        .map(str::trim)
        .expect("the README gives a test command");
    let ci = std::fs::read_to_string(format!("{ROOT}/.ci/run")).expect(".ci/run");
    assert!(ci.lines().any(|l| l.trim() == command), ".ci/run does not run the README's `{command}`");
    let tree = std::process::Command::new(env!("CARGO"))
        .args(["tree", "--offline", "-e", "normal,dev,build", "--prefix", "none", "--format", "{p}"])
        .current_dir(ROOT)
        .output()
        .expect("cargo tree runs");
    assert!(tree.status.success(), "cargo tree: {}", String::from_utf8_lossy(&tree.stderr));
    let tree = String::from_utf8_lossy(&tree.stdout);
    let heavy: Vec<&str> = tree
        .lines()
        .filter(|l| ["wgpu ", "eframe ", "pyo3 "].iter().any(|name| l.starts_with(name)))
        .collect();
    assert!(heavy.is_empty(), "the core's test build pulls in {heavy:?}");
}
