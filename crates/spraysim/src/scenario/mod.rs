//! Scenario files: TOML in, a fully resolved and validated [`Scenario`] out.
//!
//! A file names a process preset in `[process]` and overrides any of its values; every other
//! section has fixed defaults. Unknown keys, wrong types and impossible values are refused with
//! the file, the line and the key.

mod params;
mod presets;
mod tool_path;
mod validate;

pub use params::*;
pub use presets::{SHOTCRETE_REBOUND_POLYNOMIAL, presets_toml};
pub use validate::Invalid;

use serde::Deserialize;
use std::path::Path;

/// The built-in default scene: shotcrete onto a 2 m × 2 m wall from 1 m, with a floor that
/// collects rebound.
pub const DEFAULT_SCENE: &str = include_str!("../../scenes/default.toml");

/// Why a scenario was refused.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The file could not be read.
    #[error("{origin}: cannot read the scenario: {source}")]
    Read {
        /// File name.
        origin: String,
        /// Underlying error.
        #[source]
        source: std::io::Error,
    },
    /// Not valid TOML, an unknown key, a missing key or a wrong type.
    #[error("{location}: {message}")]
    Syntax {
        /// `file:line` (or just the file when the position is unknown).
        location: String,
        /// What is wrong.
        message: String,
    },
    /// A value out of its allowed range or inconsistent with another.
    #[error("{location}: `{key}` {message}")]
    Invalid {
        /// `file:line` of the key, or of its section, or just the file.
        location: String,
        /// Dotted path of the key, e.g. `target[0].normal` (0-based index).
        key: String,
        /// What is wrong.
        message: String,
    },
}

/// A scenario as a file gives it, before the preset fills the gaps.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct ScenarioFile {
    #[serde(default)]
    simulation: SimulationParams,
    #[serde(default)]
    process: ProcessOverride,
    #[serde(default)]
    emitter: EmitterOverride,
    #[serde(default)]
    nozzle: NozzleParams,
    #[serde(default, rename = "obstacle")]
    obstacles: Vec<ObstacleParams>,
    #[serde(default, rename = "target")]
    targets: Vec<TargetParams>,
    domain: Option<DomainParams>,
    #[serde(default)]
    output: OutputParams,
}

impl ScenarioFile {
    fn resolve(self) -> Scenario {
        let preset = self.process.preset.unwrap_or_default();
        let mut process = preset.process();
        let p = &self.process;
        process.density = p.density.unwrap_or(process.density);
        process.flow_rate = p.flow_rate.unwrap_or(process.flow_rate);
        process.drag = p.drag.unwrap_or(process.drag);
        process.max_lifetime = p.max_lifetime.unwrap_or(process.max_lifetime);
        process.coverage_threshold = p.coverage_threshold.unwrap_or(process.coverage_threshold);
        process.impact.apply(&p.impact);
        process.cohesion.apply(&p.cohesion);
        process.erosion.apply(&p.erosion);
        process.window.apply(&p.window);
        process.sag_threshold = p.sag_threshold.unwrap_or(process.sag_threshold);
        process.drip_interval = p.drip_interval.unwrap_or(process.drip_interval);
        let mut emitter = preset.emitter();
        emitter.apply(&self.emitter);
        let domain =
            self.domain.unwrap_or_else(|| default_domain(&self.nozzle, &self.targets, &self.obstacles));
        Scenario {
            simulation: self.simulation,
            process,
            emitter,
            nozzle: self.nozzle,
            obstacles: self.obstacles,
            targets: self.targets,
            domain,
            output: self.output,
        }
    }
}

/// Bounding box of the nozzle path, the targets and the bounded obstacles, grown by 1 m.
fn default_domain(
    nozzle: &NozzleParams,
    targets: &[TargetParams],
    obstacles: &[ObstacleParams],
) -> DomainParams {
    let mut points: Vec<[f64; 3]> = vec![nozzle.position];
    points.extend(nozzle.waypoints.iter().map(|w| w.position));
    for t in targets {
        let r = t.size[0].hypot(t.size[1]) / 2.0;
        points.push(t.center.map(|c| c - r));
        points.push(t.center.map(|c| c + r));
    }
    for o in obstacles {
        if o.shape == ObstacleShape::Plane {
            continue;
        }
        let reach = o.radius.unwrap_or(0.0)
            + o.size.as_ref().map_or(0.0, |s| s.iter().map(|v| v * v).sum::<f64>().sqrt());
        for p in [o.center, o.start, o.end].into_iter().flatten() {
            points.push(p.map(|c| c - reach));
            points.push(p.map(|c| c + reach));
        }
    }
    let mut min = [f64::INFINITY; 3];
    let mut max = [f64::NEG_INFINITY; 3];
    for p in points {
        for i in 0..3 {
            min[i] = min[i].min(p[i] - 1.0);
            max[i] = max[i].max(p[i] + 1.0);
        }
    }
    DomainParams { min, max }
}

impl Scenario {
    /// Reads, resolves and validates a scenario file. A tool path it names is read relative to
    /// the file's folder.
    pub fn from_path(path: &Path) -> Result<Scenario, ScenarioError> {
        let origin = path.display().to_string();
        let text = std::fs::read_to_string(path)
            .map_err(|source| ScenarioError::Read { origin: origin.clone(), source })?;
        Scenario::parse(&text, &origin, path.parent().unwrap_or(Path::new(".")))
    }

    /// Parses, resolves and validates scenario text; `origin` names it in errors. A tool path
    /// it names is read relative to the working directory.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scenario, ScenarioError> {
        Scenario::parse(text, origin, Path::new("."))
    }

    fn parse(text: &str, origin: &str, base: &Path) -> Result<Scenario, ScenarioError> {
        let mut file: ScenarioFile = toml::from_str(text).map_err(|e| {
            let line = e.span().map(|s| line_of(text, s.start));
            ScenarioError::Syntax {
                location: location(origin, line),
                message: e.message().trim().to_string(),
            }
        })?;
        if let Some(csv) = file.nozzle.path_csv.take() {
            if !file.nozzle.waypoints.is_empty() {
                let line = locate(text, "nozzle.path_csv");
                return Err(ScenarioError::Invalid {
                    location: location(origin, line),
                    key: "nozzle.path_csv".into(),
                    message: "cannot be combined with nozzle.waypoints".into(),
                });
            }
            file.nozzle.waypoints = tool_path::read(&base.join(csv))?;
        }
        for o in &mut file.obstacles {
            if let Some(f) = &o.file {
                o.file = Some(base.join(f).display().to_string());
            }
        }
        let scenario = file.resolve();
        scenario.validate().map_err(|inv| {
            let line = locate(text, &inv.key);
            ScenarioError::Invalid { location: location(origin, line), key: inv.key, message: inv.message }
        })?;
        // Mesh files are read now, so that a bad one is refused before any run.
        for (i, o) in scenario.obstacles.iter().enumerate() {
            if let Some(mesh) = o.mesh() {
                mesh.map_err(|e| {
                    let key = format!("obstacle[{i}].file");
                    ScenarioError::Invalid {
                        location: location(origin, locate(text, &key)),
                        key,
                        message: e.to_string(),
                    }
                })?;
            }
        }
        Ok(scenario)
    }

    /// The built-in default scene (see [`DEFAULT_SCENE`]).
    pub fn default_scene() -> Scenario {
        Scenario::from_toml(DEFAULT_SCENE, "<default scene>")
            .unwrap_or_else(|e| panic!("the built-in default scene is invalid: {e}"))
    }

    /// The scenario as TOML with every value explicit; reading it back gives the same scenario.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_else(|e| panic!("a resolved scenario always serialises: {e}"))
    }
}

fn location(origin: &str, line: Option<usize>) -> String {
    match line {
        Some(l) => format!("{origin}:{l}"),
        None => origin.to_string(),
    }
}

/// 1-based line number of byte offset `at`.
fn line_of(text: &str, at: usize) -> usize {
    text.as_bytes()[..at.min(text.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Line of the deepest part of `key` (e.g. `target[1].normal`) present in the file.
fn locate(text: &str, key: &str) -> Option<usize> {
    let doc = toml_edit::Document::parse(text).ok()?;
    let mut table = doc.as_table();
    let mut best = None;
    for part in key.split('.') {
        let (name, index) = match part.split_once('[') {
            Some((n, rest)) => (n, rest.trim_end_matches(']').parse::<usize>().ok()),
            None => (part, None),
        };
        let Some((k, item)) = table.get_key_value(name) else { break };
        best = k.span().or(item.span()).or(best);
        let next = match index {
            Some(i) => item.as_array_of_tables().and_then(|a| a.get(i)),
            None => item.as_table(),
        };
        match next {
            Some(t) => {
                best = t.span().or(best);
                table = t;
            }
            None => break,
        }
    }
    best.map(|s| line_of(text, s.start))
}
