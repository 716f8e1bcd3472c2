//! Robot tool paths from CSV: `t,x,y,z,qx,qy,qz,qw[,spray]`, one pose a row: the time (s),
//! the tool's position in the world frame (z up; in metres or millimetres, as the scenario
//! says) and its orientation as a quaternion (no unit), its z axis the spray axis.

use crate::error::ScenarioError;
use crate::input::{InputKind, read_input};
use crate::params::LengthUnit;
use crate::reader::{Choice, MAX_COORD, Num};

/// One pose of a tool path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Pose {
    /// Time, s.
    pub time: f64,
    /// Position, m.
    pub position: [f64; 3],
    /// Spray axis: the tool's z axis.
    pub axis: [f64; 3],
    /// Whether the nozzle sprays from here to the next pose.
    pub spray: bool,
}
use glam::{DQuat, DVec3};
use std::path::Path;

const COLUMNS: [&str; 8] = ["t", "x", "y", "z", "qx", "qy", "qz", "qw"];

/// Latest time a pose may have, s (as for a waypoint).
const MAX_TIME: f64 = 1e6;

/// Reads a tool path, a regular file of at most [`InputKind::ToolPath`]'s cap, its positions in
/// `units` (converted to metres before anything is checked). Columns are found by their header
/// names (any order); `spray` is optional (`1`/`0` or `true`/`false`, default on). The spray
/// axis is the tool's z axis rotated by the quaternion. Times must increase from row to row,
/// positions lie within [`MAX_COORD`] of the origin, and the axis may not turn by 180° from one
/// row to the next. Errors name the file, the line and the column.
pub(crate) fn read(path: &Path, units: LengthUnit) -> Result<Vec<Pose>, ScenarioError> {
    let origin = path.display().to_string();
    let syntax = |line: Option<u64>, message: String| ScenarioError::Syntax {
        location: line.map_or(origin.clone(), |l| format!("{origin}:{l}")),
        message,
    };
    let bytes = read_input(path, InputKind::ToolPath)
        .map_err(|e| syntax(None, format!("cannot read the tool path: {}", e.problem)))?;
    let mut reader =
        csv::ReaderBuilder::new().trim(csv::Trim::All).comment(Some(b'#')).from_reader(bytes.as_slice());
    let headers = reader.headers().map_err(|e| syntax(Some(1), e.to_string()))?.clone();
    // A repeated column would leave it ambiguous which of the two holds the value.
    for (i, h) in headers.iter().enumerate() {
        if headers.iter().take(i).any(|earlier| earlier == h) {
            return Err(syntax(Some(1), format!("column `{h}` appears twice in the header")));
        }
    }
    let find = |name: &str| headers.iter().position(|h| h == name);
    let mut index = [0usize; 8];
    for (k, name) in COLUMNS.iter().enumerate() {
        index[k] = find(name).ok_or_else(|| {
            syntax(Some(1), format!("missing column `{name}` (the header must name t,x,y,z,qx,qy,qz,qw)"))
        })?;
    }
    let spray_col = find("spray");
    let mut out: Vec<Pose> = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| syntax(e.position().map(|p| p.line()), e.to_string()))?;
        let line = record.position().map(|p| p.line());
        let pose =
            pose(&record, &index, spray_col, units, out.last()).map_err(|message| syntax(line, message))?;
        out.push(pose);
    }
    if out.is_empty() {
        return Err(syntax(None, "the tool path has no rows".into()));
    }
    Ok(out)
}

/// The pose of one row, its columns at `index` (in the order of [`COLUMNS`]), its position in
/// `units`, and `spray` at `spray_col`, checked against the row before it; or what is wrong
/// with it.
fn pose(
    record: &csv::StringRecord,
    index: &[usize; 8],
    spray_col: Option<usize>,
    units: LengthUnit,
    previous: Option<&Pose>,
) -> Result<Pose, String> {
    let mut v = [0.0; 8];
    for (k, name) in COLUMNS.iter().enumerate() {
        let cell = record.get(index[k]).unwrap_or("");
        v[k] = cell
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| format!("column `{name}`: {cell:?} is not a finite number"))?;
    }
    let time = v[0];
    if !(0.0..=MAX_TIME).contains(&time) {
        return Err(format!("column `t`: {} s is not between 0 and {} s", Num(time), Num(MAX_TIME)));
    }
    if let Some(p) = previous
        && time <= p.time
    {
        return Err(format!(
            "column `t`: {} s is not later than the previous row's {} s; times must increase from row to row",
            Num(time),
            Num(p.time)
        ));
    }
    // In metres before any check: a division, so that a whole number of millimetres gives the
    // metres a file in metres would (1500 mm is 1.5 m exactly).
    let position = [v[1], v[2], v[3]].map(|c| c / units.per_metre());
    if let Some(k) = position.iter().position(|c| c.abs() > MAX_COORD) {
        let (column, given) = (COLUMNS[k + 1], Num(v[k + 1]));
        let (metres, limit) = (Num(position[k]), Num(MAX_COORD));
        return Err(match units {
            LengthUnit::Metres => format!(
                "column `{column}`: {metres} m is beyond ±{limit} m, farther than any coordinate may be \
                 (for a file in millimetres, set nozzle.path_csv = {{ file = \"…\", units = \"mm\" }})"
            ),
            LengthUnit::Millimetres => format!(
                "column `{column}`: {given} {} ({metres} m) is beyond ±{limit} m, farther than any coordinate \
                 may be",
                units.name()
            ),
        });
    }
    let axis = spray_axis([v[4], v[5], v[6], v[7]])
        .ok_or("the quaternion (qx, qy, qz, qw) is zero (or too small to give a direction)")?;
    if let Some(p) = previous
        && DVec3::from_array(p.axis).dot(DVec3::from_array(axis)) < -0.9999
    {
        return Err("the spray axis turns by 180° from the previous row's; the rotation is ambiguous".into());
    }
    let spray = match spray_col.map(|c| record.get(c).unwrap_or("")) {
        None | Some("1" | "true") => true,
        Some("0" | "false") => false,
        Some(other) => return Err(format!("column `spray`: {other:?} is not 0, 1, true or false")),
    };
    Ok(Pose { time, position, axis, spray })
}

/// The tool's z axis rotated by the quaternion `(x, y, z, w)` of finite components, a unit
/// vector; `None` for a quaternion of (nearly) zero length. The components are scaled by the
/// largest first, so that no product overflows or underflows whatever their magnitude.
fn spray_axis(q: [f64; 4]) -> Option<[f64; 3]> {
    let largest = q.iter().fold(0.0_f64, |m, c| m.max(c.abs()));
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let scaled = DQuat::from_array(q.map(|c| c / largest));
    // The length before scaling, compared without forming it (it may overflow).
    if scaled.length() * largest < 1e-9 {
        return None;
    }
    let axis = scaled.normalize() * DVec3::Z;
    (axis.is_finite() && axis.length() > 0.5).then(|| axis.to_array())
}

#[cfg(test)]
mod tests {
    use super::spray_axis;

    #[test]
    fn a_quaternion_of_huge_or_tiny_components_gives_a_unit_axis() {
        // A half turn about x, written at three scales: z turns to -z.
        for s in [1e308, 1.0, 1e-3] {
            let axis = spray_axis([s, 0.0, 0.0, 0.0]).expect("a direction");
            assert!((axis[2] + 1.0).abs() < 1e-12, "{s}: {axis:?}");
        }
        let axis = spray_axis([1e308, 1e308, 0.0, 0.0]).expect("a direction");
        assert!((axis.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() < 1e-12, "{axis:?}");
        assert_eq!(spray_axis([0.0; 4]), None);
        assert_eq!(spray_axis([1e-12, 0.0, 0.0, 0.0]), None);
    }
}
