//! The README tells the truth about the command: the default run prints what the README shows,
//! and the commands tables (the README's and the fuller one of `docs/usage.md`) name only
//! subcommands and flags that `spraysim` has.

mod common;

use common::{spraysim, stderr};

/// The repository's root.
const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../..");

fn read(page: &str) -> String {
    std::fs::read_to_string(format!("{ROOT}/{page}")).unwrap_or_else(|e| panic!("{page}: {e}"))
}

/// The README's printed output of `cargo run --release -- run`: its `text` block that starts
/// with `simulated`.
fn readme_default_run() -> Vec<String> {
    let text = read("README.md");
    let block = text
        .split("```text\n")
        .skip(1)
        .map(|b| b.split("```").next().unwrap_or_default())
        .find(|b| b.starts_with("simulated "))
        .expect("the README shows the default run's output");
    block.lines().map(str::to_string).collect()
}

/// `spraysim run` without arguments, in an empty folder, prints the README's lines: all of them
/// as they are, but the wall-clock time and speed of the first, which vary from run to run.
#[test]
fn the_default_run_prints_what_the_readme_shows() {
    let shown = readme_default_run();
    let tmp = tempfile::tempdir().expect("tempdir");
    let o = spraysim(&["run"], tmp.path());
    assert!(o.status.success(), "{}", stderr(&o));
    let printed: Vec<String> = String::from_utf8_lossy(&o.stdout).lines().map(str::to_string).collect();
    assert_eq!(printed.len(), shown.len(), "printed:\n{}\nREADME:\n{}", printed.join("\n"), shown.join("\n"));
    // "simulated 2.000 s in 0.16 s (12.18× real time)": the simulated time is fixed, the rest is
    // the machine's.
    let fixed = |line: &str| line.split(" in ").next().unwrap_or_default().to_string();
    assert_eq!(fixed(&printed[0]), fixed(&shown[0]), "first line");
    for (i, (p, s)) in printed.iter().zip(&shown).enumerate().skip(1) {
        assert_eq!(p, s, "line {} of the README's default run differs from the command's", i + 1);
    }
}

/// The command cells (`spraysim SUBCOMMAND …`) of a page's commands table.
fn command_cells(page: &str) -> Vec<String> {
    read(page)
        .lines()
        .filter(|l| l.starts_with("| `spraysim "))
        .map(|l| l.trim_start_matches("| `").split('`').next().unwrap_or_default().replace("\\|", "|"))
        .collect()
}

/// Every subcommand in the README's and `docs/usage.md`'s tables exists, and every flag they
/// give it is in its `--help`.
#[test]
fn the_commands_tables_name_real_subcommands_and_flags() {
    let tmp = tempfile::tempdir().expect("tempdir");
    for page in ["README.md", "docs/usage.md"] {
        let cells = command_cells(page);
        assert!(cells.len() >= 9, "{page}: {} commands in its table", cells.len());
        for cell in cells {
            let sub = cell.split_whitespace().nth(1).expect("a subcommand");
            let o = spraysim(&[sub, "--help"], tmp.path());
            assert!(o.status.success(), "{page}: `spraysim {sub} --help` fails: {}", stderr(&o));
            let help = String::from_utf8_lossy(&o.stdout).into_owned();
            let flags = cell
                .split(|c: char| c.is_whitespace() || "[]|…,".contains(c))
                .filter(|w| w.starts_with('-') && w.len() > 1)
                .map(|w| w.split('=').next().unwrap_or(w));
            for flag in flags {
                let known = help.contains(&format!("{flag} ")) || help.contains(&format!("{flag},"));
                assert!(known, "{page}: `spraysim {sub}` has no flag {flag}:\n{help}");
            }
        }
    }
}
