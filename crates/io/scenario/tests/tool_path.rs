//! A robot tool path (`nozzle.path_csv`) is checked row by row, and every refusal names the
//! CSV file and its line.

use spraysim_scenario::scenes::wall_scene;
use spraysim_scenario::{NozzleMotion, Scenario, ScenarioError};

const HEADER: &str = "t,x,y,z,qx,qy,qz,qw\n";
/// A pose spraying along +x: the tool's z axis turned a quarter about y.
const ALONG_X: &str = "0,0.7071068,0,0.7071068";

/// The wall scene with the tool path `rows` (after the header), read from files.
fn with_path(rows: &str) -> Result<Scenario, ScenarioError> {
    let dir = tempfile::tempdir().expect("a temporary folder");
    std::fs::write(dir.path().join("path.csv"), format!("{HEADER}{rows}")).expect("written");
    let scene = format!("{}[nozzle]\npath_csv = \"path.csv\"\n", wall_scene(0.05, 32));
    std::fs::write(dir.path().join("s.toml"), scene).expect("written");
    Scenario::from_path(&dir.path().join("s.toml"))
}

/// The message of a refusal, which must name the CSV file at `line`.
fn refused_at(rows: &str, line: usize) -> String {
    let err = with_path(rows).expect_err("refused");
    let text = err.to_string();
    assert!(text.contains(&format!("path.csv:{line}: ")), "not at line {line}: {text}");
    text
}

#[test]
fn a_repeated_or_earlier_time_is_blamed_on_its_csv_row() {
    let text = refused_at(&format!("0,-1,0,1,{ALONG_X}\n0.5,-1,0,1,{ALONG_X}\n0.5,-1,0,1,{ALONG_X}\n"), 4);
    assert!(text.contains("column `t`: 0.5 s is not later than the previous row's 0.5 s"), "{text}");
    let text = refused_at(
        &format!("0,-1,0,1,{ALONG_X}\n# a comment\n0.5,-1,0,1,{ALONG_X}\n0.25,-1,0,1,{ALONG_X}\n"),
        5,
    );
    assert!(text.contains("0.25 s is not later"), "{text}");
    let text = refused_at(&format!("-1,-1,0,1,{ALONG_X}\n"), 2);
    assert!(text.contains("column `t`: -1 s is not between 0 and 1000000 s"), "{text}");
}

#[test]
fn a_position_beyond_the_coordinate_limit_is_blamed_on_its_csv_row() {
    let text = refused_at(&format!("0,-1,0,1,{ALONG_X}\n0.5,-1,2e4,1,{ALONG_X}\n"), 3);
    assert!(text.contains("column `y`: 20000 m is beyond ±10000 m"), "{text}");
    let text = refused_at(&format!("0,-1e308,0,1,{ALONG_X}\n"), 2);
    assert!(text.contains("column `x`: -1e308 m"), "{text}");
}

#[test]
fn a_quaternion_of_huge_components_gives_the_same_axis_as_a_small_one() {
    let axis = |rows: &str| {
        let sc = with_path(rows).unwrap_or_else(|e| panic!("{e}"));
        let NozzleMotion::Waypoints { waypoints } = &sc.nozzle().motion else { panic!("waypoints") };
        waypoints[0].axis
    };
    let huge = axis("0,-1,0,1,1e308,1e308,0,0\n");
    let small = axis("0,-1,0,1,1,1,0,0\n");
    for (h, s) in huge.iter().zip(small) {
        assert!((h - s).abs() < 1e-12, "{huge:?} against {small:?}");
    }
    assert!((huge.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() < 1e-12, "{huge:?}");
    let text = refused_at("0,-1,0,1,0,0,0,0\n", 2);
    assert!(text.contains("the quaternion (qx, qy, qz, qw) is zero"), "{text}");
}

#[test]
fn an_axis_that_turns_by_half_a_turn_between_rows_is_blamed_on_its_csv_row() {
    // Along +x, then along -x (a quarter about y the other way).
    let text = refused_at(&format!("0,-1,0,1,{ALONG_X}\n0.5,-1,0,1,0,-0.7071068,0,0.7071068\n"), 3);
    assert!(text.contains("turns by 180°"), "{text}");
}

/// The wall scene with the tool path `rows` (after the header) named by the `[nozzle]` line
/// `path_csv`, read from files.
fn with_path_as(path_csv: &str, rows: &str) -> Result<Scenario, ScenarioError> {
    let dir = tempfile::tempdir().expect("a temporary folder");
    std::fs::write(dir.path().join("path.csv"), format!("{HEADER}{rows}")).expect("written");
    let scene = format!("{}[nozzle]\npath_csv = {path_csv}\n", wall_scene(0.05, 32));
    std::fs::write(dir.path().join("s.toml"), scene).expect("written");
    Scenario::from_path(&dir.path().join("s.toml"))
}

/// A path in millimetres, so marked, gives the same waypoints as the path in metres; the
/// conversion comes before the checks, so a position within reach in metres is accepted however
/// many millimetres it is.
#[test]
fn a_tool_path_in_millimetres_is_read_in_metres() {
    let metres =
        with_path_as("\"path.csv\"", &format!("0,-1,0.25,1.5,{ALONG_X}\n0.5,-1,-0.25,1,{ALONG_X}\n"))
            .unwrap_or_else(|e| panic!("{e}"));
    let millimetres = with_path_as(
        "{ file = \"path.csv\", units = \"mm\" }",
        &format!("0,-1000,250,1500,{ALONG_X}\n0.5,-1000,-250,1000,{ALONG_X}\n"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(millimetres, metres);
    let NozzleMotion::Waypoints { waypoints } = &millimetres.nozzle().motion else { panic!("waypoints") };
    assert_eq!(waypoints[0].position, [-1.0, 0.25, 1.5]);
    // Metres by default, and as the table says.
    let explicit = with_path_as(
        "{ file = \"path.csv\", units = \"m\" }",
        &format!("0,-1,0.25,1.5,{ALONG_X}\n0.5,-1,-0.25,1,{ALONG_X}\n"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(explicit, metres);
    // 12 m from the origin, in millimetres: beyond the limit as a number, within it in metres.
    let far =
        with_path_as("{ file = \"path.csv\", units = \"mm\" }", &format!("0,-12000,0,1000,{ALONG_X}\n"))
            .unwrap_or_else(|e| panic!("{e}"));
    let NozzleMotion::Waypoints { waypoints } = &far.nozzle().motion else { panic!("waypoints") };
    assert_eq!(waypoints[0].position, [-12.0, 0.0, 1.0]);
}

/// A path in millimetres read as metres lands far beyond the limit: the refusal says how to
/// mark the file's units; one beyond the limit in millimetres gives both units.
#[test]
fn a_position_beyond_the_limit_names_its_units() {
    let err = with_path_as("\"path.csv\"", &format!("0,-1000,0,15000,{ALONG_X}\n"))
        .expect_err("refused")
        .to_string();
    assert!(
        err.contains(
            "path.csv:2: column `z`: 15000 m is beyond ±10000 m, farther than any coordinate may be (for a file \
             in millimetres, set nozzle.path_csv = { file = \"…\", units = \"mm\" })"
        ),
        "{err}"
    );
    let err = with_path_as("{ file = \"path.csv\", units = \"mm\" }", &format!("0,-1000,0,2e7,{ALONG_X}\n"))
        .expect_err("refused")
        .to_string();
    assert!(err.contains("column `z`: 20000000 mm (20000 m) is beyond ±10000 m"), "{err}");
}

/// The table's keys are checked like any other: a unit other than m or mm, a missing file, an
/// unknown key.
#[test]
fn the_path_csv_table_is_checked() {
    let rows = format!("0,-1,0,1,{ALONG_X}\n");
    for (path_csv, expect) in [
        (
            "{ file = \"path.csv\", units = \"cm\" }",
            "`nozzle.path_csv.units` must be one of \"m\", \"mm\", got \"cm\"",
        ),
        ("{ units = \"mm\" }", "`nozzle.path_csv.file` is required"),
        ("{ file = \"path.csv\", unit = \"mm\" }", "`nozzle.path_csv.unit` is not a key of nozzle.path_csv"),
    ] {
        let err = with_path_as(path_csv, &rows).expect_err("refused").to_string();
        assert!(err.contains(expect), "{path_csv}: {err}");
    }
}
