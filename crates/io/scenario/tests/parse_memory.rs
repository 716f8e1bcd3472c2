//! Reading a scenario takes memory in proportion to its size, with a bounded factor: the text
//! is parsed once, and a refusal is located without parsing it again. Counted by this test
//! program's allocator (allocation counts do not depend on the machine or its load).

use spraysim_scenario::Scenario;
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, keeping the bytes in use and their peak since the last reset.
struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is passed on to the system allocator unchanged; only counters are kept.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let now = IN_USE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
        PEAK.fetch_max(now, Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        IN_USE.fetch_sub(layout.size(), Ordering::Relaxed);
        // SAFETY: the caller's contract is passed on.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size > layout.size() {
            let now =
                IN_USE.fetch_add(new_size - layout.size(), Ordering::Relaxed) + new_size - layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        } else {
            IN_USE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
        }
        // SAFETY: the caller's contract is passed on.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Peak bytes allocated while `f` runs, beyond those in use when it started.
fn peak_of<T>(f: impl FnOnce() -> T) -> (usize, T) {
    let before = IN_USE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let out = f();
    (PEAK.load(Ordering::Relaxed) - before, out)
}

/// Most bytes of memory reading may take per byte of text. The parser keeps a token and an
/// event (24 bytes each) per token and a 56-byte node per value while it builds the tree; a
/// file of one-character values (`1,`) has one of each every two bytes or so.
const FACTOR: usize = 96;

// One test in this program, so that no other thread allocates while it counts.
#[test]
fn reading_a_scenario_takes_memory_linear_in_its_size() {
    let waypoint =
        "[[nozzle.waypoints]]\ntime = 0.000010\nposition = [-1.0, 0.0, 1.0]\naxis = [1.0, 0.0, 0.0]\n";
    let mut waypoints = String::from("[simulation]\nduration = 1.0\n");
    for i in 0..20_000 {
        waypoints.push_str(&waypoint.replace("0.000010", &format!("{:.6}", i as f64 * 1e-5)));
    }
    // An unknown key holding a long array of short values: refused, and located, at the end.
    let unknown = format!("[simulation]\nduration = 0.1\nbogus = [{}]\n", "1,".repeat(1_000_000));
    let cases: [(&str, &str, Option<&str>, bool); 4] = [
        ("waypoints", &waypoints, None, true),
        ("waypoints with an override", &waypoints, Some("simulation.seed=3"), true),
        ("an unknown array", &unknown, None, false),
        ("waypoints with an unknown key as an override", &waypoints, Some("simulation.bogus=1"), false),
    ];
    for (what, text, set, valid) in cases {
        let (peak, result) = peak_of(|| {
            let sc = Scenario::from_toml(text, "big.toml");
            match set {
                Some(assignment) => sc.and_then(|sc| sc.with_assignment(assignment)),
                None => sc,
            }
        });
        // The text the test made is not counted: `from_toml` takes one copy of its own.
        let factor = peak as f64 / text.len() as f64;
        println!("{what}: {} bytes of text, peak {peak} bytes, {factor:.1}×", text.len());
        assert_eq!(result.is_ok(), valid, "{what}");
        assert!(
            peak < FACTOR * text.len(),
            "{what}: {peak} bytes for {} bytes of text ({factor:.1}×)",
            text.len()
        );
    }
}
