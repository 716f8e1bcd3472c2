//! What a run of a scenario costs before it starts: its steps, its particles and a bound on
//! the memory it needs, each part of it with the key that drives it, so that a scenario the
//! machine cannot hold is refused before the run, naming that key.

use crate::scenario::Scenario;
use spraysim_engine::particles::Swarm;

/// Memory assumed when the machine's cannot be read, bytes.
const FALLBACK_MEMORY: f64 = 8.0 * GIB;
/// Bytes in a gibibyte.
const GIB: f64 = 1024.0 * 1024.0 * 1024.0;
/// What every run takes whatever its size (program, threads, the broad phase's grid of at
/// most 2²¹ cells), bytes.
const BASE: f64 = 96.0 * 1024.0 * 1024.0;
/// Bytes per particle slot over its life: the swarm's arrays at up to twice their length (a
/// vector doubles as it grows) and the step's impact records.
const PER_SLOT: f64 = 2.0 * Swarm::BYTES_PER_PARTICLE as f64 + 32.0;
/// Bytes per particle emitted in one step: its sampled pose and its slot while the swarm grows.
const PER_BIRTH: f64 = 48.0 + 2.0 * Swarm::BYTES_PER_PARTICLE as f64;
/// Bytes per cell of a heightfield over the run and while its outputs are written (thickness,
/// impacts, failure and erosion maps, the arrays and images written).
pub(crate) const PER_CELL: f64 = 96.0;
/// Bytes per triangle of a mesh: its geometry, its scene entry, its index and, for a target,
/// its deposit and outputs.
pub(crate) const PER_TRIANGLE: f64 = 600.0;
/// Bytes per logged impact, kept and written as a CSV line.
const PER_LOGGED: f64 = 96.0 + 200.0;

/// One part of a run's memory and the key that drives it.
#[derive(Clone, Debug, PartialEq)]
pub struct MemoryPart {
    /// The dotted key that sets its size, e.g. `emitter.spawn_rate`.
    pub key: String,
    /// What it is, for messages.
    pub what: String,
    /// Its size, bytes.
    pub bytes: f64,
}

/// The size of a run: steps, particles and a bound on its memory.
#[derive(Clone, Debug, PartialEq)]
pub struct Budget {
    /// Time steps the duration takes.
    pub steps: u64,
    /// Particles emitted over the run (an upper bound when the nozzle pauses).
    pub particles: f64,
    /// Most particles in flight at once (bounded by the lifetime), an upper bound.
    pub in_flight: f64,
    /// The parts of the memory bound, largest first, bytes.
    pub parts: Vec<MemoryPart>,
    /// Sum of the parts and the base, bytes.
    pub memory: f64,
    /// The limit the memory is held to, bytes (`simulation.max_memory`, or its default).
    pub limit: f64,
}

impl Budget {
    /// The part of the memory that is largest.
    pub fn largest(&self) -> Option<&MemoryPart> {
        self.parts.first()
    }
}

/// The machine's physical memory, bytes, when it can be read.
pub fn machine_memory() -> Option<f64> {
    static MEMORY: std::sync::OnceLock<Option<f64>> = std::sync::OnceLock::new();
    *MEMORY.get_or_init(|| {
        let text = std::fs::read_to_string("/proc/meminfo").ok()?;
        let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
        let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kib * 1024.0)
    })
}

/// The default memory limit: half of the machine's memory (8 GiB when it cannot be read).
pub fn default_memory_limit() -> f64 {
    machine_memory().map_or(FALLBACK_MEMORY, |m| 0.5 * m)
}

/// A byte count for people: `1.5 GB`.
pub fn bytes_text(bytes: f64) -> String {
    let (value, unit) = match bytes {
        b if b >= 1e12 => (b / 1e12, "TB"),
        b if b >= 1e9 => (b / 1e9, "GB"),
        b if b >= 1e6 => (b / 1e6, "MB"),
        b => (b / 1e3, "kB"),
    };
    format!("{value:.1} {unit}")
}

/// The memory a surface's geometry takes in a run, as its kind reports it.
pub(crate) struct Storage {
    /// The key of the surface's table that drives it (`resolution`, `file`).
    pub key: &'static str,
    /// What takes it, counted (`262144 cells`).
    pub what: String,
    /// Its size, bytes.
    pub bytes: f64,
}

impl Storage {
    /// The part of the budget for the surface at `path` (`target[0]`) described as `surface`
    /// (``target `wall` ``).
    fn part(self, path: &str, surface: &str) -> MemoryPart {
        MemoryPart {
            key: format!("{path}.{}", self.key),
            what: format!("{} of {surface}", self.what),
            bytes: self.bytes,
        }
    }
}

impl Scenario {
    /// The steps, particles and memory a run of this scenario implies.
    pub fn budget(&self) -> Budget {
        let (s, e, p) = (self.simulation(), self.emitter(), self.process());
        let steps = (s.duration / s.dt).ceil().max(1.0) as u64;
        let per_step = (e.spawn_rate * s.dt).ceil();
        let particles = e.spawn_rate * steps as f64 * s.dt;
        let in_flight = (e.spawn_rate * (p.max_lifetime + s.dt)).min(particles) + per_step;
        let mut parts = vec![MemoryPart {
            key: "emitter.spawn_rate".into(),
            what: format!(
                "{in_flight:.3e} particles in flight at once ({} 1/s for up to {} s, the shorter of \
                 simulation.duration and process.max_lifetime)",
                e.spawn_rate,
                s.duration.min(p.max_lifetime)
            ),
            bytes: in_flight * PER_SLOT + per_step * PER_BIRTH,
        }];
        for (i, t) in self.targets().iter().enumerate() {
            let s = t.shape.as_dyn().storage();
            parts.push(s.part(&format!("target[{i}]"), &format!("target `{}`", t.name)));
        }
        for (i, o) in self.obstacles().iter().enumerate() {
            if let Some(s) = o.shape.as_dyn().storage() {
                parts.push(s.part(&format!("obstacle[{i}]"), &format!("obstacle `{}`", o.name)));
            }
        }
        let log = self.output().impact_log;
        if log > 0.0 {
            // Most particles strike a surface once or twice.
            let logged = log * 2.0 * particles;
            parts.push(MemoryPart {
                key: "output.impact_log".into(),
                what: format!("{logged:.3e} logged impacts"),
                bytes: logged * PER_LOGGED,
            });
        }
        parts.sort_by(|a, b| b.bytes.total_cmp(&a.bytes));
        let memory = BASE + parts.iter().map(|p| p.bytes).sum::<f64>();
        let limit = if s.max_memory > 0.0 { s.max_memory } else { default_memory_limit() };
        Budget { steps, particles, in_flight, parts, memory, limit }
    }
}
