//! Measured deposition profiles (CSV) and the matching profile of a simulated layer.
//!
//! A profile file has a header naming two columns with their units in brackets, then one
//! measurement a row; lines starting with `#` are comments:
//!
//! ```text
//! # wet-mix shotcrete, nozzle 1 m from the panel, 10 s
//! radius [mm],thickness [mm]
//! 0,41.2
//! 10,39.8
//! ```
//!
//! The position is a distance along a line or a radius (units `m`, `cm`, `mm`); the value is a
//! thickness (`m`, `cm`, `mm`, `um` or `µm`) or a mass per area (`kg/m²`, `kg/m2`, `g/m²`,
//! `g/m2`). The unit decides which; the names are free text, kept for plots.

use super::CalibrationError;
use spraysim_engine::deposit::HeightField;
use std::path::Path;

/// What a profile's values measure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Layer thickness, m.
    Thickness,
    /// Deposited mass per area, kg/m² (thickness × the process density).
    MassPerArea,
}

impl Quantity {
    /// Unit of the SI values, e.g. for tables.
    pub fn si_unit(self) -> &'static str {
        match self {
            Quantity::Thickness => "m",
            Quantity::MassPerArea => "kg/m²",
        }
    }
}

/// A measured profile in SI units: positions in m, values in m or kg/m².
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredProfile {
    /// Where it came from (file name), for messages.
    pub origin: String,
    /// Name of the position column, without its unit.
    pub position_name: String,
    /// Name of the value column, without its unit.
    pub value_name: String,
    /// What the values measure.
    pub quantity: Quantity,
    /// Positions, m, strictly increasing.
    pub positions: Vec<f64>,
    /// Values, m (thickness) or kg/m² (mass per area), ≥ 0.
    pub values: Vec<f64>,
}

/// Splits `name [unit]` into its parts.
fn name_and_unit(header: &str) -> Option<(String, String)> {
    let open = header.rfind('[')?;
    let close = header.rfind(']')?;
    (close > open).then(|| (header[..open].trim().to_string(), header[open + 1..close].trim().to_string()))
}

fn length_factor(unit: &str) -> Option<f64> {
    match unit {
        "m" => Some(1.0),
        "cm" => Some(1e-2),
        "mm" => Some(1e-3),
        "um" | "µm" | "μm" => Some(1e-6),
        _ => None,
    }
}

fn value_factor(unit: &str) -> Option<(Quantity, f64)> {
    match unit {
        "kg/m²" | "kg/m2" | "kg/m^2" => Some((Quantity::MassPerArea, 1.0)),
        "g/m²" | "g/m2" | "g/m^2" => Some((Quantity::MassPerArea, 1e-3)),
        // A thickness in micrometres is common for paint films, so µm is allowed here only.
        _ => length_factor(unit).map(|f| (Quantity::Thickness, f)),
    }
}

impl MeasuredProfile {
    /// Reads a profile file: a regular file within the profile size limit
    /// ([`spraysim_scenario::InputKind::Profile`]), in UTF-8.
    pub fn from_path(path: &Path) -> Result<MeasuredProfile, CalibrationError> {
        let read = |source| CalibrationError::Read { path: path.to_path_buf(), source };
        let bytes = spraysim_scenario::read_input(path, spraysim_scenario::InputKind::Profile)
            .map_err(|e| read(e.problem.into_io_error()))?;
        let text = String::from_utf8(bytes)
            .map_err(|_| read(std::io::Error::new(std::io::ErrorKind::InvalidData, "not UTF-8 text")))?;
        MeasuredProfile::from_csv(&text, &path.display().to_string())
    }

    /// Parses a profile from CSV text; `origin` names it in errors.
    pub fn from_csv(text: &str, origin: &str) -> Result<MeasuredProfile, CalibrationError> {
        let err = |line: Option<u64>, message: String| CalibrationError::Profile {
            location: line.map_or(origin.to_string(), |l| format!("{origin}:{l}")),
            message,
        };
        let mut reader =
            csv::ReaderBuilder::new().trim(csv::Trim::All).comment(Some(b'#')).from_reader(text.as_bytes());
        let headers = reader.headers().map_err(|e| err(None, e.to_string()))?.clone();
        let header_line = headers.position().map(|p| p.line());
        if headers.len() != 2 {
            return Err(err(
                header_line,
                format!(
                    "the header must name two columns, position and value, e.g. `radius [mm],thickness [mm]`; \
                     found {} column(s)",
                    headers.len()
                ),
            ));
        }
        let (position_name, position_unit) = name_and_unit(&headers[0]).ok_or_else(|| {
            err(header_line, format!("column `{}` has no unit, e.g. `radius [mm]`", &headers[0]))
        })?;
        let position_factor = length_factor(&position_unit).ok_or_else(|| {
            err(header_line, format!("position unit `{position_unit}` is not one of m, cm, mm"))
        })?;
        let (value_name, value_unit) = name_and_unit(&headers[1]).ok_or_else(|| {
            err(header_line, format!("column `{}` has no unit, e.g. `thickness [mm]`", &headers[1]))
        })?;
        let (quantity, factor) = value_factor(&value_unit).ok_or_else(|| {
            err(
                header_line,
                format!("value unit `{value_unit}` is neither a thickness (m, cm, mm, µm) nor a mass per area (kg/m², g/m²)"),
            )
        })?;
        let (mut positions, mut values) = (Vec::new(), Vec::new());
        for record in reader.records() {
            let record = record.map_err(|e| err(e.position().map(|p| p.line()), e.to_string()))?;
            let line = record.position().map(|p| p.line());
            let field = |i: usize, what: &str| -> Result<f64, CalibrationError> {
                let raw = record.get(i).unwrap_or("");
                let x: f64 = raw.parse().map_err(|_| err(line, format!("{what} `{raw}` is not a number")))?;
                if !x.is_finite() {
                    return Err(err(line, format!("{what} must be finite, got {raw}")));
                }
                Ok(x)
            };
            let p = field(0, "position")? * position_factor;
            let v = field(1, "value")? * factor;
            if v < 0.0 {
                return Err(err(line, format!("value must not be negative, got {}", v / factor)));
            }
            if let Some(&last) = positions.last()
                && p <= last
            {
                return Err(err(line, "positions must increase strictly from row to row".into()));
            }
            positions.push(p);
            values.push(v);
        }
        if positions.len() < 3 {
            return Err(err(None, format!("needs at least 3 measurements, found {}", positions.len())));
        }
        if !values.iter().any(|&v| v > 0.0) {
            return Err(err(None, "every value is zero: nothing to fit".into()));
        }
        Ok(MeasuredProfile {
            origin: origin.to_string(),
            position_name,
            value_name,
            quantity,
            positions,
            values,
        })
    }

    /// Largest measured value, m or kg/m²: errors are reported as percentages of it.
    pub fn peak(&self) -> f64 {
        self.values.iter().copied().fold(0.0, f64::max)
    }
}

/// Which way a profile runs across a target.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ProfileShape {
    /// Distance from the centre (annulus averages); positions must be ≥ 0.
    Radial,
    /// Signed distance along the target's `right` axis (its width), within a band.
    Right,
    /// Signed distance along the target's `up` axis (its height), within a band.
    Up,
}

/// Averages a heightfield over the bins of a profile. Bin `i` reaches halfway to the
/// neighbouring positions (as far again past the ends), so each measurement stands for the
/// cells nearest to it.
#[derive(Clone, Debug)]
pub struct ProfileSampler {
    /// Bin of each cell, `u32::MAX` for cells outside every bin.
    bin_of_cell: Vec<u32>,
    /// Cells in each bin.
    cells: Vec<u32>,
}

impl ProfileSampler {
    /// Bins for `positions` (m) of a profile of `shape` through `center` (m, in-face `right`,
    /// `up` coordinates); line profiles take cells within `band / 2` (m) of the line. Fails
    /// when a bin holds no cell (a position off the target, or bins finer than the cells).
    pub fn new(
        field: &HeightField,
        positions: &[f64],
        shape: ProfileShape,
        center: (f64, f64),
        band: f64,
    ) -> Result<ProfileSampler, String> {
        let n = positions.len();
        if n < 2 {
            return Err("a profile needs at least two positions".into());
        }
        if shape == ProfileShape::Radial && positions[0] < 0.0 {
            return Err(format!("a radial profile starts at radius ≥ 0, not {} m", positions[0]));
        }
        let mut edges = Vec::with_capacity(n + 1);
        edges.push(positions[0] - 0.5 * (positions[1] - positions[0]));
        edges.extend(positions.windows(2).map(|w| 0.5 * (w[0] + w[1])));
        edges.push(positions[n - 1] + 0.5 * (positions[n - 1] - positions[n - 2]));
        let count = field.cols() * field.rows();
        let mut bin_of_cell = vec![u32::MAX; count];
        let mut cells = vec![0u32; n];
        for (cell, bin) in bin_of_cell.iter_mut().enumerate() {
            let (u, v) = field.cell_center(cell as u32);
            let (du, dv) = (u - center.0, v - center.1);
            let coord = match shape {
                ProfileShape::Radial => du.hypot(dv),
                ProfileShape::Right if dv.abs() <= 0.5 * band => du,
                ProfileShape::Up if du.abs() <= 0.5 * band => dv,
                _ => continue,
            };
            // The first edge below `coord`, by bisection over the sorted edges.
            let k = edges.partition_point(|&e| e <= coord);
            if k >= 1 && k <= n {
                *bin = (k - 1) as u32;
                cells[k - 1] += 1;
            }
        }
        if let Some(empty) = cells.iter().position(|&c| c == 0) {
            let (dx, dy) = field.cell_size();
            return Err(format!(
                "no cell of the target falls in the bin of the measurement at {} m: the position is off the \
                 target, the bins are finer than its {:.4} m × {:.4} m cells, or the band is too narrow",
                positions[empty], dx, dy
            ));
        }
        Ok(ProfileSampler { bin_of_cell, cells })
    }

    /// Mean thickness (m) in each bin.
    pub fn sample(&self, thickness: &[f64]) -> Vec<f64> {
        let mut sum = vec![0.0; self.cells.len()];
        for (&bin, &t) in self.bin_of_cell.iter().zip(thickness) {
            if bin != u32::MAX {
                sum[bin as usize] += t;
            }
        }
        sum.iter().zip(&self.cells).map(|(s, &c)| s / f64::from(c)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_converted_to_si() {
        let p = MeasuredProfile::from_csv("# note\nradius [mm], mass [g/m²]\n0,5\n10,4\n20,1\n", "p.csv")
            .expect("valid");
        assert_eq!(p.quantity, Quantity::MassPerArea);
        assert_eq!(p.positions, vec![0.0, 0.01, 0.02]);
        assert!((p.values[0] - 5e-3).abs() < 1e-15);
        assert_eq!(p.position_name, "radius");
        let t = MeasuredProfile::from_csv("x [cm],thickness [µm]\n-1,5\n0,6\n1,5\n", "t.csv").expect("valid");
        assert_eq!(t.quantity, Quantity::Thickness);
        assert!((t.positions[0] + 0.01).abs() < 1e-15 && (t.values[1] - 6e-6).abs() < 1e-18);
    }

    #[test]
    fn bad_profiles_name_the_line_and_the_problem() {
        let cases = [
            ("r,t\n0,1\n1,1\n2,1\n", "p.csv:1", "no unit"),
            ("r [in],t [mm]\n0,1\n1,1\n2,1\n", "p.csv:1", "`in`"),
            ("r [mm],t [N]\n0,1\n1,1\n2,1\n", "p.csv:1", "`N`"),
            ("r [mm],t [mm]\n0,1\n1,x\n2,1\n", "p.csv:3", "`x` is not a number"),
            ("r [mm],t [mm]\n0,1\n1,-1\n2,1\n", "p.csv:3", "negative"),
            ("r [mm],t [mm]\n0,1\n2,1\n1,1\n", "p.csv:4", "increase"),
            ("r [mm],t [mm]\n0,1\n1,NaN\n2,1\n", "p.csv:3", "finite"),
            ("r [mm],t [mm]\n0,1\n1,1\n", "p.csv", "at least 3"),
            ("r [mm],t [mm]\n0,0\n1,0\n2,0\n", "p.csv", "zero"),
            ("r [mm],t [mm],w [mm]\n0,1,1\n", "p.csv:1", "two columns"),
        ];
        for (text, location, words) in cases {
            let e = MeasuredProfile::from_csv(text, "p.csv").expect_err(text).to_string();
            assert!(e.starts_with(location) && e.contains(words), "{text:?} gave: {e}");
        }
    }

    #[test]
    fn radial_bins_average_their_annuli() {
        // 1 cm cells on a 1 m square; thickness = radius from the centre, so the mean over the
        // annulus [a, b] is the area-weighted mean radius (2/3)(b³ − a³)/(b² − a²).
        let mut field = HeightField::new(1.0, 1.0, 100, 100, 0.0);
        let area = field.cell_area();
        for cell in 0..10_000u32 {
            let (u, v) = field.cell_center(cell);
            field.deposit(cell, u.hypot(v) * area);
        }
        let positions = [0.1, 0.2, 0.3, 0.4];
        let s = ProfileSampler::new(&field, &positions, ProfileShape::Radial, (0.0, 0.0), 0.0).expect("bins");
        for (m, r) in s.sample(field.thickness()).iter().zip(positions) {
            let (a, b) = (r - 0.05, r + 0.05);
            let expected = 2.0 / 3.0 * (b.powi(3) - a.powi(3)) / (b * b - a * a);
            assert!((m - expected).abs() < 0.002, "annulus at {r}: mean {m}, expected {expected}");
        }
        // A line along `up` through u = 0.2, bins 0.3 m long: the mean of √(0.2² + v²) over each.
        let line =
            ProfileSampler::new(&field, &[-0.3, 0.0, 0.3], ProfileShape::Up, (0.2, 0.0), 0.02).expect("bins");
        let got = line.sample(field.thickness());
        for (m, p) in got.iter().zip([-0.3, 0.0, 0.3]) {
            let expected =
                (0..3000).map(|k| 0.2f64.hypot(p - 0.15 + (k as f64 + 0.5) * 1e-4)).sum::<f64>() / 3000.0;
            assert!((m - expected).abs() < 0.002, "bin at {p}: mean {m}, expected {expected}");
        }
        // Off the target: refused.
        assert!(
            ProfileSampler::new(&field, &[0.4, 0.6, 0.8], ProfileShape::Right, (0.0, 0.0), 0.02).is_err()
        );
    }
}
