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
