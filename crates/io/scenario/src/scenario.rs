//! The validated scenario: reading, resolving, overriding and writing it back.

use crate::error::ScenarioError;
use crate::input::{InputKind, read_input};
use crate::overrides::{self, Value};
use crate::params::*;
use crate::reader::{Invalid, Read, Section, Table};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The built-in default scene: shotcrete onto a 2 m × 2 m wall from 1 m, with a floor that
/// collects rebound.
pub const DEFAULT_SCENE: &str = include_str!("../scenes/default.toml");

/// Where a scenario's text came from.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Source {
    /// The text as given, before overrides; shared by every scenario made from it.
    text: Arc<str>,
    /// Its name in errors.
    origin: String,
    /// The folder its relative paths start from.
    base: PathBuf,
    /// `(dotted key, TOML value)` overrides, in the order given (their index names them in
    /// errors).
    overrides: Vec<(String, String)>,
}

/// A complete, validated scenario: every default filled in. It cannot be changed in place;
/// [`Scenario::with`] makes a new one with a value overridden, checked like the file's. Two
/// scenarios are equal when they resolve to the same values, whatever text they came from.
#[derive(Clone, Debug)]
pub struct Scenario {
    source: Source,
    simulation: SimulationParams,
    process: ProcessParams,
    emitter: EmitterParams,
    air: AirParams,
    nozzle: NozzleParams,
    obstacles: Vec<ObstacleParams>,
    targets: Vec<TargetParams>,
    domain: DomainParams,
    output: OutputParams,
}

impl PartialEq for Scenario {
    fn eq(&self, o: &Scenario) -> bool {
        self.simulation == o.simulation
            && self.process == o.process
            && self.emitter == o.emitter
            && self.air == o.air
            && self.nozzle == o.nozzle
            && self.obstacles == o.obstacles
            && self.targets == o.targets
            && self.domain == o.domain
            && self.output == o.output
    }
}

/// The scenario's sections in file order, for writing it out.
#[derive(Serialize)]
struct Resolved<'a> {
    simulation: &'a SimulationParams,
    process: &'a ProcessParams,
    emitter: &'a EmitterParams,
    air: &'a AirParams,
    nozzle: &'a NozzleParams,
    #[serde(rename = "obstacle", skip_serializing_if = "<[_]>::is_empty")]
    obstacles: &'a [ObstacleParams],
    #[serde(rename = "target", skip_serializing_if = "<[_]>::is_empty")]
    targets: &'a [TargetParams],
    domain: &'a DomainParams,
    output: &'a OutputParams,
}

impl Scenario {
    /// Reads and validates a scenario file. Paths it names (meshes, tool paths) are read
    /// relative to the file's folder.
    ///
    /// The file must be a regular file of at most [`InputKind::Scenario`]'s cap (see
    /// [`read_input`]) and UTF-8 text.
    pub fn from_path(path: &Path) -> Result<Scenario, ScenarioError> {
        let origin = path.display().to_string();
        let bytes = read_input(path, InputKind::Scenario)
            .map_err(|e| ScenarioError::Read { origin: origin.clone(), source: e.problem.into_io_error() })?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            ScenarioError::Syntax {
                location: location(&origin, Some(line_of_bytes(e.as_bytes(), at))),
                message: format!("the file is not UTF-8 text (byte {at} is not), as TOML must be"),
            }
        })?;
        let text = Arc::from(text);
        let base = path.parent().unwrap_or(Path::new("."));
        let base = std::path::absolute(base).unwrap_or_else(|_| base.to_path_buf());
        Scenario::parse(Source { text, origin, base, overrides: Vec::new() })
    }

    /// Parses and validates scenario text; `origin` names it in errors. Paths it names are read
    /// relative to the working directory.
    pub fn from_toml(text: &str, origin: &str) -> Result<Scenario, ScenarioError> {
        let base = std::path::absolute(".").unwrap_or_else(|_| PathBuf::from("."));
        Scenario::parse(Source {
            text: Arc::from(text),
            origin: origin.to_string(),
            base,
            overrides: Vec::new(),
        })
    }

    /// The built-in default scene (see [`DEFAULT_SCENE`]).
    pub fn default_scene() -> Scenario {
        Scenario::from_toml(DEFAULT_SCENE, "<default scene>")
            .unwrap_or_else(|e| panic!("the built-in default scene is invalid: {e}"))
    }

    /// This scenario with `key` (dotted, as in errors: `emitter.spawn_rate`,
    /// `target[0].resolution`, `nozzle.raster.speed`; each part a bare or quoted TOML key, so
    /// `simulation."dt"` is `simulation.dt` and `"simulation.dt"` one key of that name) set to
    /// `value`, validated as if the file had said so: a bad value is refused with the same
    /// message, naming the key, and located at the override (`--set KEY=VALUE`).
    pub fn with(&self, key: &str, value: impl Into<Value>) -> Result<Scenario, ScenarioError> {
        self.with_all(&[(key.to_string(), value.into())])
    }

    /// [`Scenario::with`] for several keys at once: they are applied together and the result
    /// checked once, so their order does not matter (`nozzle.circle_radius` and
    /// `nozzle.circle_frequency` may come either way round). A table set whole
    /// (`nozzle={raster={target="wall"}}`, which replaces the file's table, keys of another
    /// motion and all) takes the keys set inside it by the others; a key set twice takes the
    /// later value. A refusal is located at the override it comes from, even when the key it
    /// names is the file's (a raster set into a file's static nozzle names the raster's
    /// override, not the file's `axis`).
    pub fn with_all(&self, overrides: &[(String, Value)]) -> Result<Scenario, ScenarioError> {
        let mut source = self.source.clone();
        source.overrides.extend(overrides.iter().map(|(k, v)| (k.clone(), v.to_toml())));
        Scenario::parse(source)
    }

    /// [`Scenario::with_all`] from `KEY=VALUE` texts, as the command line's `--set`s give them
    /// (see [`Scenario::with_assignment`]): applied together and checked once.
    pub fn with_assignments<S: AsRef<str>>(&self, assignments: &[S]) -> Result<Scenario, ScenarioError> {
        let overrides =
            assignments.iter().map(|a| overrides::split(a.as_ref())).collect::<Result<Vec<_>, _>>()?;
        self.with_all(&overrides)
    }

    /// [`Scenario::with`] from `KEY=VALUE` text, as the command line's `--set` gives it: the
    /// value is TOML (`3`, `2e4`, `[0.0, 1.0, 0.0]`, `"painting"`), or a bare word taken as a
    /// string (`painting`).
    pub fn with_assignment(&self, assignment: &str) -> Result<Scenario, ScenarioError> {
        let (key, value) = overrides::split(assignment)?;
        self.with(&key, value)
    }

    fn parse(source: Source) -> Result<Scenario, ScenarioError> {
        Scenario::parse_with(source, true)
    }

    /// Parses and validates `source`. A refusal is located at the key's line, or at the
    /// override that set it; with overrides, one whose key is the file's (or nobody's) is put
    /// on the override it comes from (found by leaving each out, when `find_override`): the
    /// text alone was a valid scenario, so the overrides made it wrong.
    fn parse_with(source: Source, find_override: bool) -> Result<Scenario, ScenarioError> {
        let (text, origin) = (&*source.text, source.origin.as_str());
        control_characters(text, origin)?;
        // One parse, kept with the spans of every key and value: errors found while reading
        // are put on their lines from it, without parsing the text again.
        let mut doc =
            toml::de::DeTable::parse(text).map_err(|e| syntax_error(text, origin, &e))?.into_inner();
        overrides::apply(&mut doc, &source.overrides)?;
        Scenario::resolve(&doc, &source).map_err(|inv| {
            let place = match locate(&doc, text, &inv.key) {
                Place::Line(_) | Place::Nowhere if find_override && !source.overrides.is_empty() => {
                    Place::Override(cause(&source, &inv))
                }
                place => place,
            };
            let location = match place {
                Place::Override(i) => match source.overrides.get(i) {
                    Some((k, v)) => format!("--set {k}={v}"),
                    None => origin.to_string(),
                },
                Place::Line(l) => location(origin, Some(l)),
                Place::Nowhere => origin.to_string(),
            };
            ScenarioError::Invalid { location, key: inv.key, message: inv.message }
        })
    }

    fn resolve(table: &Table<'_>, source: &Source) -> Read<Scenario> {
        let root = Section::root(table);
        let process = read::process(&root.table_or_empty("process")?, Preset::defaults)?;
        let simulation = read::simulation(&root.table_or_empty("simulation")?, process.drag)?;
        let (emitter, air) = spray(&root, &process, &simulation)?;
        let mut names = Vec::new();
        let targets = (root.tables("target")?.iter())
            .map(|t| read::target(t, &mut names, &process.impact, &source.base))
            .collect::<Read<Vec<_>>>()?;
        let obstacles = (root.tables("obstacle")?.iter())
            .map(|o| read::obstacle(o, &mut names, &process.impact, &source.base))
            .collect::<Read<Vec<_>>>()?;
        let nozzle =
            read::nozzle(&root.table_or_empty("nozzle")?, &source.base, &targets, simulation.duration)?;
        let domain =
            read::domain(root.table("domain")?.as_ref(), || default_domain(&nozzle, &targets, &obstacles))?;
        let output = read::output(&root.table_or_empty("output")?, process.preset, simulation.duration)?;
        root.finish("a scenario")?;
        stable_drag(&simulation, &process, &emitter)?;
        let mut scenario = Scenario {
            source: source.clone(),
            simulation,
            process,
            emitter,
            air,
            nozzle,
            obstacles,
            targets,
            domain,
            output,
        };
        // A target without a splat radius gets one from the particles expected per cell.
        let radii = crate::splat::derived_radii(&scenario);
        for (t, radius) in scenario.targets.iter_mut().zip(radii) {
            if let (Some(splat), Some((radius, expected))) = (t.shape.splat_radius_mut(), radius) {
                splat.radius = radius;
                splat.expected_particles = Some(expected);
            }
        }
        fits_in_memory(&scenario)?;
        Ok(scenario)
    }

    /// The scenario as TOML with every value explicit; reading it back gives the same scenario.
    pub fn to_toml(&self) -> String {
        let resolved = Resolved {
            simulation: &self.simulation,
            process: &self.process,
            emitter: &self.emitter,
            air: &self.air,
            nozzle: &self.nozzle,
            obstacles: &self.obstacles,
            targets: &self.targets,
            domain: &self.domain,
            output: &self.output,
        };
        toml::to_string(&resolved).unwrap_or_else(|e| panic!("a resolved scenario always serialises: {e}"))
    }

    /// Where the scenario came from (a file name, or the name given to [`Scenario::from_toml`]).
    pub fn origin(&self) -> &str {
        &self.source.origin
    }

    /// `[simulation]`: the time step, duration, seed, gravity and memory limit.
    pub fn simulation(&self) -> &SimulationParams {
        &self.simulation
    }

    /// `[process]`: the material and its models.
    pub fn process(&self) -> &ProcessParams {
        &self.process
    }

    /// `[emitter]`: the particles' start, number, speed and directions.
    pub fn emitter(&self) -> &EmitterParams {
        &self.emitter
    }

    /// `[air]`: the gun's air, or still air.
    pub fn air(&self) -> &AirParams {
        &self.air
    }

    /// `[nozzle]`: the nozzle's motion.
    pub fn nozzle(&self) -> &NozzleParams {
        &self.nozzle
    }

    /// The `[[obstacle]]`s, in file order.
    pub fn obstacles(&self) -> &[ObstacleParams] {
        &self.obstacles
    }

    /// The `[[target]]`s, in file order.
    pub fn targets(&self) -> &[TargetParams] {
        &self.targets
    }

    /// `[domain]`: the box beyond which particles are retired, m.
    pub fn domain(&self) -> &DomainParams {
        &self.domain
    }

    /// `[output]`: what is written, and where.
    pub fn output(&self) -> &OutputParams {
        &self.output
    }
}

/// Bounding box of the nozzle's positions, every target (each as far as it reaches around its
/// anchor points, each vertex of a mesh) and the boxes of every obstacle's bounded engine shapes,
/// grown by 1 m. A raster's path lies within its target's reach grown by the standoff, the lead
/// and the circle.
fn default_domain(
    nozzle: &NozzleParams,
    targets: &[TargetParams],
    obstacles: &[ObstacleParams],
) -> DomainParams {
    let mut points: Vec<[f64; 3]> = Vec::new();
    let target_reach = |t: &TargetParams| t.shape.as_dyn().reach();
    match &nozzle.motion {
        NozzleMotion::Static { position, .. } => points.push(*position),
        NozzleMotion::Circling { position, circle_radius, .. } => {
            points.push(position.map(|c| c - circle_radius));
            points.push(position.map(|c| c + circle_radius));
        }
        NozzleMotion::Waypoints { waypoints } => points.extend(waypoints.iter().map(|w| w.position)),
        NozzleMotion::Raster { raster } => {
            if let Some(t) = targets.iter().find(|t| t.name == raster.target) {
                let p = &raster.plan;
                let (anchors, reach) = target_reach(t);
                let reach = reach + p.standoff + p.lead + p.circle_radius;
                for a in anchors {
                    points.push(a.map(|c| c - reach));
                    points.push(a.map(|c| c + reach));
                }
            }
        }
    }
    for t in targets {
        let (anchors, reach) = target_reach(t);
        for p in anchors {
            points.push(p.map(|c| c - reach));
            points.push(p.map(|c| c + reach));
        }
    }
    for b in obstacles.iter().filter_map(|o| o.shape.bounds()) {
        points.push(b.min.to_array());
        points.push(b.max.to_array());
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

fn location(origin: &str, line: Option<usize>) -> String {
    match line {
        Some(l) => format!("{origin}:{l}"),
        None => origin.to_string(),
    }
}

/// 1-based line number of byte offset `at`.
fn line_of(text: &str, at: usize) -> usize {
    line_of_bytes(text.as_bytes(), at)
}

/// 1-based line number of byte offset `at` of `bytes`.
fn line_of_bytes(bytes: &[u8], at: usize) -> usize {
    bytes[..at.min(bytes.len())].iter().filter(|&&b| b == b'\n').count() + 1
}

/// Refuses the control characters TOML allows nowhere (all but tab, line feed and carriage
/// return), naming the line and column of the first: the parser would blame a key near it.
fn control_characters(text: &str, origin: &str) -> Result<(), ScenarioError> {
    let bad = |c: char| c.is_control() && !matches!(c, '\t' | '\n' | '\r') && (c as u32) < 0x80;
    let Some(at) = text.find(bad) else { return Ok(()) };
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let column = text[line_start..at].chars().count() + 1;
    let c = text[at..].chars().next().unwrap_or('\0');
    let name = match c {
        '\0' => " (NUL)".to_string(),
        '\u{7f}' => " (DEL)".to_string(),
        _ => String::new(),
    };
    Err(ScenarioError::Syntax {
        location: location(origin, Some(line_of(text, at))),
        message: format!(
            "column {column} holds the control character U+{:04X}{name}, which TOML does not allow anywhere in a file",
            c as u32
        ),
    })
}

/// The error for text the TOML parser refused: a duplicate key or table names it; a value
/// that is not TOML (a bare word, a broken number) names its key; anything else is a syntax
/// error at its line.
fn syntax_error(text: &str, origin: &str, e: &toml::de::Error) -> ScenarioError {
    let span = e.span();
    let line = span.as_ref().map(|s| line_of(text, s.start));
    let message = e.message().trim().to_string();
    let at = location(origin, line);
    if let (true, Some(span), Some(l)) = (message.starts_with("duplicate key"), span, line) {
        let key = duplicate_key(text, span, l);
        return ScenarioError::Invalid {
            location: at,
            key,
            message: "is given twice: a key, or a table header, may appear only once".into(),
        };
    }
    match line.and_then(|l| key_at_line(text, l)) {
        Some(key) => ScenarioError::Invalid {
            location: at,
            key,
            message: format!("is not a valid TOML value: {message}"),
        },
        None => ScenarioError::Syntax { location: at, message },
    }
}

/// The dotted key that the parser found twice at `span`, on line `line`: a table header's
/// name, or the key of a `key = value` line within its table (with the inner key when the
/// duplicate is inside an inline table on that line).
fn duplicate_key(text: &str, span: std::ops::Range<usize>, line: usize) -> String {
    let name = text.get(span.clone()).map(str::trim).unwrap_or_default();
    let Some((section, is_header)) = table_at_line(text, line) else { return name.to_string() };
    if is_header {
        return section;
    }
    let start = text[..span.start.min(text.len())].rfind('\n').map_or(0, |i| i + 1);
    let on_line = &text[start..];
    let on_line = on_line.split('\n').next().unwrap_or_default();
    let key = match on_line.split_once('=') {
        // The duplicate is the line's own key.
        Some((k, _)) if span.start - start < k.len() => k.trim().to_string(),
        // Inside an inline table: the line's key, then the duplicate.
        Some((k, _)) => format!("{}.{name}", k.trim()),
        None => name.to_string(),
    };
    if section.is_empty() { key } else { format!("{section}.{key}") }
}

/// Where an error's key was given.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Place {
    /// A line of the file, 1-based.
    Line(usize),
    /// The override of this index.
    Override(usize),
    /// Neither (a key nobody gave, in a table nobody gave).
    Nowhere,
}

/// Where the deepest part of `key` (e.g. `target[1].normal`) present in `doc` was given: a
/// line of `text`, or the override that set it (or made a table on its way).
fn locate(doc: &Table<'_>, text: &str, key: &str) -> Place {
    let place = |span: std::ops::Range<usize>| match overrides::override_of(&span) {
        Some(i) => Place::Override(i),
        None => Place::Line(line_of(text, span.start)),
    };
    // A key printed quoted (`"a.b"`) is split the way an override's is.
    let Ok(steps) = overrides::parse_key(key) else { return Place::Nowhere };
    let mut table = doc;
    let mut best = Place::Nowhere;
    for step in steps {
        let Some((k, item)) = table.get_key_value(step.name.as_str()) else { break };
        best = place(k.span());
        if let Place::Override(_) = best {
            // Everything under what an override set is the override's.
            return best;
        }
        let next = match (step.index, item.get_ref()) {
            (Some(i), toml::de::DeValue::Array(a)) => a.get(i).map(|t| (t.span(), t.get_ref())),
            (None, v) => Some((item.span(), v)),
            _ => None,
        };
        match next {
            Some((span, toml::de::DeValue::Table(t))) => {
                if step.index.is_some() {
                    best = place(span);
                }
                table = t;
            }
            _ => break,
        }
    }
    best
}

/// The override (its index) that the refusal `inv` of `source` comes from, for a refusal whose
/// key the file gave (or nobody did): `source`'s text is a valid scenario alone, so one of its
/// overrides made it wrong. Those without which the refusal goes away (or changes) are the
/// suspects; of them (or of all, when leaving out any one keeps it) the one whose key shares
/// the most parts with the refusal's key, the latest given among equals.
fn cause(source: &Source, inv: &Invalid) -> usize {
    let all: Vec<usize> = (0..source.overrides.len()).collect();
    let suspects: Vec<usize> = if all.len() == 1 {
        all.clone()
    } else {
        (all.iter().copied())
            .filter(|&i| {
                let mut without = source.clone();
                without.overrides.remove(i);
                match Scenario::parse_with(without, false) {
                    Ok(_) => true,
                    Err(ScenarioError::Invalid { key, message, .. }) => {
                        key != inv.key || message != inv.message
                    }
                    Err(_) => true,
                }
            })
            .collect()
    };
    let pool = if suspects.is_empty() { &all } else { &suspects };
    (pool.iter().copied())
        .max_by_key(|&i| (overrides::shared_parts(&source.overrides[i].0, &inv.key), i))
        .unwrap_or(0)
}

/// Reads `[emitter]` and `[air]` over the defaults of the process and its gun, and refuses air
/// the run cannot use: an air-atomised gun's air too slow to atomise, air without droplet
/// sizes, with the exact integrator or with `process.drag`.
fn spray(
    root: &Section<'_>,
    process: &ProcessParams,
    simulation: &SimulationParams,
) -> Read<(EmitterParams, AirParams)> {
    let gun = process.gun;
    let air = read::air(&root.table_or_empty("air")?, &gun.map_or_else(AirDefaults::still, |g| g.air()))?;
    let emitter_defaults = process.preset.emitter_defaults();
    let air_speed = match &air {
        AirParams::Jet(j) => j.speed,
        AirParams::None => 0.0,
    };
    let sized = root.table_or_empty("emitter")?.has("sauter_mean");
    if let Some(g) =
        gun.filter(|g| g.air_atomised() && !sized && air_speed > 0.0 && air_speed < 0.25 * g.air_speed())
    {
        return crate::reader::bad(
            "air.speed",
            format!(
                "is too slow to atomise the paint: the {} gun's droplets grow as 1/U₀ from its {} m/s, and below \
             a quarter of that ({} m/s) the atomisation law no longer holds; set emitter.sauter_mean \
             with it, or switch the air off with air.model = \"none\"",
                g.name(),
                g.air_speed(),
                0.25 * g.air_speed()
            ),
        );
    }
    let emitter = read::emitter(
        &root.table_or_empty("emitter")?,
        &gun.map_or(emitter_defaults.clone(), |g| g.emitter(emitter_defaults, air_speed)),
        simulation.duration,
    )?;
    if matches!(air, AirParams::Jet(_)) {
        if emitter.droplets == DropletsLaw::None {
            return crate::reader::bad(
                "air.model",
                "needs droplet sizes: set emitter.droplets (\"fixed\", \"log_normal\" or \"rosin_rammler\")",
            );
        }
        if simulation.integrator == spraysim_engine::motion::Integrator::Exact {
            return crate::reader::bad(
                "air.model",
                "has no closed form with simulation.integrator = \"exact\": use \"euler\" or \"semi_implicit_euler\"",
            );
        }
        if process.drag > 0.0 {
            return crate::reader::bad("air.model", "replaces process.drag: set it to 0");
        }
    }
    Ok((emitter, air))
}

/// Largest k·|v|·Δt accepted with drag: beyond 1 an explicit step reverses the velocity.
const DRAG_UNSTABLE: f64 = 1.0;

/// Refuses drag that the explicit integrators cannot follow: one step changes the speed by
/// about k |v| Δt of itself, which must stay below 1 (and well below it to be accurate).
fn stable_drag(s: &SimulationParams, p: &ProcessParams, e: &EmitterParams) -> Read<()> {
    let kvt = p.drag * e.speed[1] * s.dt;
    if kvt >= DRAG_UNSTABLE {
        return crate::reader::bad(
            "process.drag",
            format!(
                "× emitter.speed (max {} m/s) × simulation.dt ({} s) = {}, which makes the explicit \
                 integrators unstable (it must stay below {DRAG_UNSTABLE}, and below 0.1 to be accurate): \
                 lower simulation.dt to at most {:.3e} s",
                crate::reader::Num(e.speed[1]),
                crate::reader::Num(s.dt),
                crate::reader::Num((kvt * 1e3).round() / 1e3),
                0.1 / (p.drag * e.speed[1])
            ),
        );
    }
    Ok(())
}

/// Refuses a scenario whose memory bound exceeds its limit, naming the key that drives it.
fn fits_in_memory(sc: &Scenario) -> Read<()> {
    let b = sc.budget();
    match b.largest() {
        Some(part) if b.memory > b.limit => crate::reader::bad(
            &part.key,
            format!(
                "makes the run need about {} of memory, mostly for {} ({}), more than the limit of {} \
                 (simulation.max_memory{})",
                crate::bytes_text(b.memory),
                part.what,
                crate::bytes_text(part.bytes),
                crate::bytes_text(b.limit),
                if sc.simulation().max_memory > 0.0 {
                    ""
                } else {
                    ", by default half of this machine's memory"
                }
            ),
        ),
        _ => Ok(()),
    }
}

/// The table whose part of `text` holds line `line` (1-based) — its dotted name, `target[1]`
/// for the second `[[target]]`, empty for the top level — and whether that line is its header.
/// Reads the text line by line, keeping nothing but the last header.
fn table_at_line(text: &str, line: usize) -> Option<(String, bool)> {
    let header = |l: &str| l.trim_start().starts_with('[');
    let (mut last, mut at) = (None, 0);
    for (n, l) in text.lines().take(line).enumerate() {
        if header(l) {
            (last, at) = (Some(l.trim()), n + 1);
        }
    }
    let Some(head) = last else { return Some((String::new(), false)) };
    let name = match head.strip_prefix("[[").and_then(|r| r.split("]]").next()) {
        Some(name) => {
            let name = name.trim();
            let opener = format!("[[{name}]]");
            let index = text.lines().take(at - 1).filter(|l| l.trim().starts_with(&opener)).count();
            format!("{name}[{index}]")
        }
        None => head.trim_start_matches('[').split(']').next()?.trim().to_string(),
    };
    Some((name, at == line))
}

/// The dotted key whose value starts at (or spans) line `line` of `text`, for a value the
/// TOML parser refused: the key on that line or the nearest one above it within its table,
/// prefixed by the table's header (`[[target]]` counted, `target[1]`). Reads the text line
/// by line.
fn key_at_line(text: &str, line: usize) -> Option<String> {
    let bare = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.';
    let mut key = None;
    for l in text.lines().take(line) {
        if l.trim_start().starts_with('[') {
            key = None;
        } else if let Some((k, _)) = l.split_once('=') {
            let k = k.trim();
            if !k.is_empty() && k.chars().all(bare) {
                key = Some(k);
            }
        }
    }
    let key = key?;
    match table_at_line(text, line)? {
        (section, _) if section.is_empty() => Some(key.to_string()),
        (section, _) => Some(format!("{section}.{key}")),
    }
}
