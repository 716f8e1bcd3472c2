//! Generated scenarios, valid and mutated, through parse → validate → a few steps of a
//! `Simulation`: no panic, every refusal names a key, and what an accepted scenario allocates
//! stays under its memory limit and under the estimate it was checked with; a scenario beyond
//! the limit is refused before it allocates.
//!
//! A counting allocator measures the memory; the tests of this file take turns so that each
//! sees only its own allocations.

use proptest::prelude::*;
use spraysim::Scenario;
use spraysim::scenario::ScenarioError;
use spraysim::scenario::scenes::{NOZZLE_AT_WALL, floor, refusal, wall, wall_scene};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting the bytes in use and their peak.
struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded to the system allocator unchanged; only counters are added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = IN_USE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) };
        IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: same contract as the caller's.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            let now = if new_size >= layout.size() {
                IN_USE.fetch_add(new_size - layout.size(), Ordering::Relaxed) + new_size - layout.size()
            } else {
                IN_USE.fetch_sub(layout.size() - new_size, Ordering::Relaxed) - (layout.size() - new_size)
            };
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One test at a time, so the counters see one test's allocations.
static TURN: Mutex<()> = Mutex::new(());

/// Runs `f` and returns its result and the most memory it had allocated at once, bytes.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = IN_USE.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    let out = f();
    (out, PEAK.load(Ordering::SeqCst).saturating_sub(base))
}

/// Memory limit of the generated scenarios, bytes.
const LIMIT: f64 = 4e8;

/// Valid scenarios to mutate: shotcrete on a wall and floor; painting a shell with a fan and
/// drag; blasting a coated wall behind a mesh obstacle.
fn templates(mesh: &str) -> [String; 3] {
    let wall = wall().resolution(32, 32);
    [
        format!(
            "[simulation]\nduration = 0.02\nmax_memory = {LIMIT:e}\n[process]\npreset = \"shotcrete\"\n\
             [process.impact]\nalpha = 1.0\n[process.slump]\ninterval = 0.01\n[emitter]\nspawn_rate = 20000.0\n\
             {NOZZLE_AT_WALL}{wall}{floor}\
             [domain]\nmin = [-4.0, -3.0, -1.0]\nmax = [1.0, 3.0, 3.0]\n[output]\nimpact_log = 0.1\n",
            floor = floor().resolution(20, 15),
        ),
        format!(
            "[simulation]\nduration = 0.02\ndt = 0.0005\nmax_memory = {LIMIT:e}\n[process]\npreset = \"painting\"\n\
             drag = 2.0\n[emitter]\nshape = \"rectangle\"\ndirection = \"fan\"\n[nozzle]\nposition = [0.0, 0.0, 0.5]\n\
             axis = [0.0, 1.0, 0.0]\n[[target]]\nname = \"shell\"\nshape = \"cylinder\"\ncenter = [0.0, 0.0, 0.0]\n\
             axis = [1.0, 0.0, 0.0]\nradius = 1.5\nlength = 2.0\nresolution = [64, 32]\n"
        ),
        format!(
            "[simulation]\nduration = 0.02\nintegrator = \"exact\"\nmax_memory = {LIMIT:e}\n[process]\n\
             preset = \"blasting\"\n[process.erosion]\nmodel = \"oka\"\n[emitter]\nspawn_rate = 5000.0\n{coated}\
             [[obstacle]]\nname = \"grille\"\nshape = \"mesh\"\nfile = \"{mesh}\"\n",
            coated = wall.coating(1e-4),
        ),
    ]
}

/// `(section header, key)` pairs a mutation sets, the keys of every shape and model included.
const KEYS: &[(&str, &str)] = &[
    ("[simulation]", "dt"),
    ("[simulation]", "duration"),
    ("[simulation]", "seed"),
    ("[simulation]", "integrator"),
    ("[simulation]", "max_impacts_per_step"),
    ("[simulation]", "gravity"),
    ("[process]", "preset"),
    ("[process]", "density"),
    ("[process]", "flow_rate"),
    ("[process]", "drag"),
    ("[process]", "max_lifetime"),
    ("[process.impact]", "alpha"),
    ("[process.impact]", "restitution"),
    ("[process.impact]", "rebound_model"),
    ("[process.impact]", "scatter_angle"),
    ("[process.slump]", "interval"),
    ("[process.cohesion]", "interval"),
    ("[process.erosion]", "model"),
    ("[emitter]", "shape"),
    ("[emitter]", "diameter"),
    ("[emitter]", "width"),
    ("[emitter]", "inner_diameter"),
    ("[emitter]", "spawn_rate"),
    ("[emitter]", "speed"),
    ("[emitter]", "cone_angle"),
    ("[emitter]", "direction"),
    ("[emitter]", "mu"),
    ("[emitter]", "fan_wide_angle"),
    ("[nozzle]", "position"),
    ("[nozzle]", "axis"),
    ("[nozzle]", "circle_radius"),
    ("[nozzle]", "circle_frequency"),
    ("[[target]]", "name"),
    ("[[target]]", "shape"),
    ("[[target]]", "center"),
    ("[[target]]", "normal"),
    ("[[target]]", "size"),
    ("[[target]]", "resolution"),
    ("[[target]]", "splat_radius"),
    ("[[target]]", "radius"),
    ("[[target]]", "coating"),
    ("[domain]", "min"),
    ("[domain]", "max"),
    ("[output]", "impact_log"),
    ("[output]", "colormap"),
];

/// Values a mutation writes, as TOML text: out of range, non-finite, of the wrong type, of
/// the wrong shape, words of other keys, and text that is not TOML at all.
const VALUES: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "0",
    "-1",
    "0.5",
    "2",
    "3000",
    "1e9",
    "1e308",
    "-1e308",
    "1e-300",
    "1e-7",
    "4096",
    "99999999999999999999",
    "true",
    "\"\"",
    "\"bogus\"",
    "\"circle\"",
    "\"exact\"",
    "\"mesh\"",
    "\"cylinder\"",
    "\"fan\"",
    "\"annulus\"",
    "\"painting\"",
    "\"oka\"",
    "[]",
    "[1, 2]",
    "[1, 2, 3]",
    "[nan, 0, 0]",
    "[1e30, 0, 0]",
    "[0, 0, 0]",
    "[4096, 4096]",
    "[-1e4, -1e4, -0.005]",
    "{}",
    "abc",
    "1e",
    "[1, \"a\"]",
    "2024-01-01",
];

/// `text` with `key = value` set in the first section `header` (added when missing).
fn mutate(text: &str, header: &str, key: &str, value: &str) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let line = format!("{key} = {value}");
    match lines.iter().position(|l| l == header) {
        Some(h) => {
            let end = (h + 1..lines.len()).find(|&i| lines[i].starts_with('[')).unwrap_or(lines.len());
            lines.retain_mut_range(h + 1..end, |l| !l.starts_with(&format!("{key} =")));
            lines.insert(h + 1, line);
        }
        None => {
            lines.push(header.to_string());
            lines.push(line);
        }
    }
    lines.join("\n") + "\n"
}

/// `retain` over a range of a vector.
trait RetainRange {
    fn retain_mut_range(&mut self, range: std::ops::Range<usize>, keep: impl FnMut(&String) -> bool);
}

impl RetainRange for Vec<String> {
    fn retain_mut_range(&mut self, range: std::ops::Range<usize>, mut keep: impl FnMut(&String) -> bool) {
        let tail = self.split_off(range.end);
        let middle: Vec<String> = self.split_off(range.start).into_iter().filter(|l| keep(l)).collect();
        self.extend(middle);
        self.extend(tail);
    }
}

/// What the property test saw.
#[derive(Debug, Default)]
struct Seen {
    inputs: usize,
    accepted: usize,
    refused: usize,
    largest_peak: usize,
}

static SEEN: Mutex<Seen> = Mutex::new(Seen { inputs: 0, accepted: 0, refused: 0, largest_peak: 0 });

/// Parses `text`, and runs a few steps of it if it is accepted, checking the three properties.
fn check(text: &str) -> Result<(), TestCaseError> {
    let parsed = std::panic::catch_unwind(|| Scenario::from_toml(text, "generated.toml"));
    let parsed = parsed.map_err(|_| TestCaseError::fail(format!("parsing panicked on\n{text}")))?;
    let mut seen = SEEN.lock().unwrap_or_else(|e| e.into_inner());
    seen.inputs += 1;
    let sc = match parsed {
        Err(ScenarioError::Invalid { key, .. }) if !key.is_empty() => {
            seen.refused += 1;
            return Ok(());
        }
        Err(e) => return Err(TestCaseError::fail(format!("a refusal without a key: {e}\n{text}"))),
        Ok(sc) => sc,
    };
    seen.accepted += 1;
    let budget = sc.budget();
    prop_assert!(budget.memory <= budget.limit);
    let (ran, peak) = peak_of(|| {
        std::panic::catch_unwind(|| {
            let mut sim = sc.build().map_err(|e| e.to_string())?;
            sim.set_threads(1).map_err(|e| e.to_string())?;
            for _ in 0..4 {
                sim.step();
            }
            Ok::<u64, String>(sim.metrics().emitted.count)
        })
    });
    let ran = ran.map_err(|_| TestCaseError::fail(format!("the simulation panicked on\n{text}")))?;
    prop_assert!(ran.is_ok(), "an accepted scenario did not set up: {:?}\n{}", ran, text);
    seen.largest_peak = seen.largest_peak.max(peak);
    prop_assert!((peak as f64) <= budget.limit, "{peak} bytes over the limit {}\n{text}", budget.limit);
    prop_assert!((peak as f64) <= budget.memory, "{peak} bytes over the estimate {}\n{text}", budget.memory);
    Ok(())
}

#[test]
fn generated_scenarios_never_panic_refusals_name_a_key_memory_stays_under_the_limit() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let tmp = tempfile::tempdir().expect("tempdir");
    let mesh = tmp.path().join("grille.stl");
    std::fs::write(
        &mesh,
        "solid g\nfacet normal 1 0 0\nouter loop\nvertex -0.3 -0.5 0.5\nvertex -0.3 0.5 0.5\nvertex -0.3 0 1.5\n\
         endloop\nendfacet\nendsolid g\n",
    )
    .expect("write");
    let templates = templates(&mesh.display().to_string().replace('\\', "/"));
    for t in &templates {
        assert!(Scenario::from_toml(t, "template.toml").is_ok(), "a template is invalid:\n{t}");
    }
    let mutation = (0..KEYS.len(), 0..VALUES.len());
    let strategy = (0..templates.len(), proptest::collection::vec(mutation, 0..4));
    let config = ProptestConfig { cases: 2400, failure_persistence: None, ..ProptestConfig::default() };
    proptest!(config, |((t, mutations) in strategy)| {
        let mut text = templates[t].clone();
        for (k, v) in mutations {
            let (header, key) = KEYS[k];
            text = mutate(&text, header, key, VALUES[v]);
        }
        check(&text)?;
    });
    let seen = SEEN.lock().unwrap_or_else(|e| e.into_inner());
    eprintln!(
        "generated scenarios: {} inputs, {} accepted and stepped, {} refused naming a key; largest peak {} bytes",
        seen.inputs, seen.accepted, seen.refused, seen.largest_peak
    );
    assert!(seen.accepted > 50 && seen.refused > 50, "{seen:?}");
}

#[test]
fn a_thin_wide_domain_and_a_wide_mesh_stay_small() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let tmp = tempfile::tempdir().expect("tempdir");
    let mesh = tmp.path().join("plate.stl");
    std::fs::write(
        &mesh,
        "solid p\nfacet normal 0 0 1\nouter loop\nvertex -1e4 -1e4 0\nvertex 1e4 -1e4 0\nvertex 0 1e4 0\n\
         endloop\nendfacet\nendsolid p\n",
    )
    .expect("write");
    let thin = "[simulation]\nduration = 0.01\n[emitter]\nspawn_rate = 1000.0\n[nozzle]\nposition = [0.0, 0.0, 0.0]\n\
                [domain]\nmin = [-1e4, -1e4, -0.005]\nmax = [1e4, 1e4, 0.005]\n";
    let plate = format!(
        "[simulation]\nduration = 0.01\n[nozzle]\nposition = [0.0, 0.0, 1.0]\naxis = [0.0, 0.0, -1.0]\n\
         [[obstacle]]\nname = \"plate\"\nshape = \"mesh\"\nfile = \"{}\"\n",
        mesh.display().to_string().replace('\\', "/")
    );
    for text in [thin.to_string(), plate] {
        let (emitted, peak) = peak_of(|| {
            let mut sim = Scenario::from_toml(&text, "t.toml").expect("valid").build().expect("builds");
            sim.run(|_| {});
            sim.metrics().emitted.count
        });
        assert!(emitted >= 10);
        assert!(peak < 200_000_000, "{peak} bytes for\n{text}");
    }
}

#[test]
fn a_scenario_beyond_the_memory_limit_is_refused_naming_the_key() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let sc = Scenario::from_toml(&wall_scene(0.05, 32), "wall.toml").expect("valid");
    let (key, message) = refusal(
        sc.with_all(&[
            ("emitter.spawn_rate".into(), 1e9.into()),
            ("simulation.dt".into(), 0.1.into()),
            ("simulation.duration".into(), 2.0.into()),
        ]),
        "spawn_rate = 1e9",
    );
    assert_eq!(key, "emitter.spawn_rate");
    assert!(message.contains("of memory") && message.contains("simulation.max_memory"), "{message}");
    // The same limit, set low, refuses a heightfield too large for it, naming its resolution.
    let (key, message) = refusal(
        sc.with_all(&[
            ("simulation.max_memory".into(), 2e8.into()),
            ("target[0].resolution".into(), [4096.0, 4096.0].into()),
        ]),
        "4096² cells under 200 MB",
    );
    assert_eq!(key, "target[0].resolution", "{message}");
    // Steps and particles are reported, whatever their number.
    let b = sc.budget();
    assert_eq!((b.steps, b.particles.round()), (50, 500.0));
    assert!(b.memory < b.limit && b.memory > 0.0);
}
