//! Robot tool paths from CSV: `t,x,y,z,qx,qy,qz,qw[,spray]`, one pose a row.

use crate::error::ScenarioError;

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

/// Reads a tool path. Columns are found by their header names (any order); `spray` is optional
/// (`1`/`0` or `true`/`false`, default on). The spray axis is the tool's z axis rotated by the
/// quaternion. Errors name the file, the line and the column.
pub(crate) fn read(path: &Path) -> Result<Vec<Pose>, ScenarioError> {
    let origin = path.display().to_string();
    let syntax = |line: Option<u64>, message: String| ScenarioError::Syntax {
        location: line.map_or(origin.clone(), |l| format!("{origin}:{l}")),
        message,
    };
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_path(path)
        .map_err(|e| syntax(None, format!("cannot read the tool path: {e}")))?;
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
        let mut v = [0.0; 8];
        for (k, name) in COLUMNS.iter().enumerate() {
            let cell = record.get(index[k]).unwrap_or("");
            v[k] =
                cell.parse::<f64>().ok().filter(|x| x.is_finite()).ok_or_else(|| {
                    syntax(line, format!("column `{name}`: {cell:?} is not a finite number"))
                })?;
        }
        let q = DQuat::from_xyzw(v[4], v[5], v[6], v[7]);
        if q.length() < 1e-9 {
            return Err(syntax(line, "the quaternion (qx, qy, qz, qw) is zero".into()));
        }
        let spray = match spray_col.map(|c| record.get(c).unwrap_or("")) {
            None => true,
            Some("1" | "true") => true,
            Some("0" | "false") => false,
            Some(other) => {
                return Err(syntax(line, format!("column `spray`: {other:?} is not 0, 1, true or false")));
            }
        };
        let axis = q.normalize() * DVec3::Z;
        out.push(Pose { time: v[0], position: [v[1], v[2], v[3]], axis: axis.to_array(), spray });
    }
    if out.is_empty() {
        return Err(syntax(None, "the tool path has no rows".into()));
    }
    Ok(out)
}
