//! Run control: what a run is told from outside while it steps and writes.
//!
//! - **Ctrl-C.** The first press stops the run at the end of its step, to write the outputs so
//!   far; the second aborts at once, unless files are being moved into place, in which case the
//!   run exits as soon as they are in. Every set the command writes goes through
//!   [`RunControl`], which the output directory's writer asks before it moves files and holds
//!   until they are in.
//! - **Pause points.** For the fault tests: the environment variable [`PAUSE_VARIABLE`] names
//!   points (comma-separated) at which the run says `spraysim: paused at POINT` on stderr and
//!   waits, up to 60 s, for an interrupt, so that a test can send a signal at exactly that
//!   point: `step:N` after step N, `staged` once a set is staged, `commit:K` once the K-th file
//!   of a set has moved in. The variable is read once; without it nothing is formatted or
//!   compared as the run steps.

use anyhow::{Context, Result};
use spraysim::output::directory::{CommitHooks, CommitPoint, MovingGuard};
use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Exit status of a run stopped by Ctrl-C (128 + SIGINT).
pub const INTERRUPTED: i32 = 130;

/// The environment variable that names the pause points.
pub const PAUSE_VARIABLE: &str = "SPRAYSIM_PAUSE_AT";

/// Interrupts received (Ctrl-C presses).
static INTERRUPTS: AtomicUsize = AtomicUsize::new(0);
/// What the writers and the interrupt handler agree on: how many writers are moving files into
/// place (which an abort must not cut short; several threads of one process may write sets
/// into different directories at once), or [`ABORTING`] (the process is exiting, and nothing
/// may start moving files).
static PHASE: AtomicUsize = AtomicUsize::new(0);
/// [`PHASE`] once an abort has been claimed.
const ABORTING: usize = usize::MAX;

/// Starts counting Ctrl-C presses (once per process): the first asks the run to stop at the
/// end of its step ([`stop_requested`]), a later one aborts at once, unless files are being
/// moved into place, in which case the run exits as soon as they are ([`abort_requested`]).
pub fn watch_interrupts() -> Result<()> {
    static SET: std::sync::Once = std::sync::Once::new();
    let mut result = Ok(());
    SET.call_once(|| {
        result = ctrlc::set_handler(|| {
            // A later press claims the abort before it is counted: a run waiting for the count
            // to move (at a pause point) must not start moving files in between.
            if interrupts() >= 1 && try_abort() {
                eprintln!("\naborted: the output directory holds what it held before");
                std::process::exit(INTERRUPTED);
            }
            if interrupt() == 1 {
                eprintln!("\ninterrupted: stopping at the end of this step to write the outputs so far (Ctrl-C again to abort)");
            }
        });
    });
    result.context("cannot watch for Ctrl-C")
}

/// Whether Ctrl-C has been pressed: the run stops at the end of its step.
pub fn stop_requested() -> bool {
    interrupts() >= 1
}

/// Whether Ctrl-C has been pressed again while files moved into place: once they are in, the
/// process exits.
pub fn abort_requested() -> bool {
    interrupts() >= 2
}

/// Counts one interrupt; returns how many there have been.
fn interrupt() -> usize {
    INTERRUPTS.fetch_add(1, Ordering::SeqCst) + 1
}

/// Interrupts received so far.
fn interrupts() -> usize {
    INTERRUPTS.load(Ordering::SeqCst)
}

/// Claims the right to abort: true when no writer is moving files into place, and then none
/// will start; false while one is (the caller lets it finish and exits after it).
fn try_abort() -> bool {
    PHASE.compare_exchange(0, ABORTING, Ordering::SeqCst, Ordering::SeqCst).is_ok()
}

/// The command's hooks into the output directory's writer: no moves once an abort is claimed,
/// none cut short by one, and the pause points `staged` and `commit:K`.
pub struct RunControl;

/// Marks the stretch in which files move into place, until it drops.
struct Moving;

impl Drop for Moving {
    fn drop(&mut self) {
        // Never ABORTING here: an abort waits for every writer to leave.
        PHASE.fetch_sub(1, Ordering::SeqCst);
    }
}

impl CommitHooks for RunControl {
    fn begin_moving(&self) -> Option<MovingGuard> {
        PHASE
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| (n != ABORTING).then_some(n + 1))
            .ok()
            .map(|_| Box::new(Moving) as MovingGuard)
    }

    fn reached(&self, point: CommitPoint) {
        let points = pause_points();
        match point {
            CommitPoint::Staged if points.staged => pause("staged"),
            CommitPoint::MovedIn(k) if points.commits.contains(&k) => pause(&format!("commit:{k}")),
            _ => {}
        }
    }
}

/// The next step after `step` at which [`PAUSE_VARIABLE`] names a pause (`step:N`), if any.
pub fn next_pause(step: u64) -> Option<u64> {
    pause_points().steps.iter().copied().filter(|&s| s > step).min()
}

/// After step `step` (counting from 1): pauses there if [`PAUSE_VARIABLE`] names `step:N`.
pub fn after_step(step: u64) {
    if pause_points().steps.contains(&step) {
        pause(&format!("step:{step}"));
    }
}

/// The pause points [`PAUSE_VARIABLE`] names.
#[derive(Debug, Default, PartialEq)]
struct PausePoints {
    /// `step:N`: after these steps.
    steps: Vec<u64>,
    /// `staged`: once a set is staged.
    staged: bool,
    /// `commit:K`: once the K-th file of a set has moved in.
    commits: Vec<usize>,
}

impl PausePoints {
    /// The points in `names` (comma-separated). A name matches only as written, `step:` or
    /// `commit:` and a number without sign or leading zeros; others are ignored.
    fn parse(names: &str) -> PausePoints {
        /// The number after `prefix` in `name`, written as the run writes it.
        fn number<T: std::str::FromStr + ToString>(name: &str, prefix: &str) -> Option<T> {
            let digits = name.strip_prefix(prefix)?;
            digits.parse().ok().filter(|n: &T| n.to_string() == digits)
        }
        let mut points = PausePoints::default();
        for name in names.split(',') {
            points.staged |= name == "staged";
            points.steps.extend(number::<u64>(name, "step:"));
            points.commits.extend(number::<usize>(name, "commit:"));
        }
        points
    }
}

/// The pause points, read from the environment on the first call.
fn pause_points() -> &'static PausePoints {
    static POINTS: OnceLock<PausePoints> = OnceLock::new();
    POINTS.get_or_init(|| std::env::var(PAUSE_VARIABLE).map(|v| PausePoints::parse(&v)).unwrap_or_default())
}

/// Says on stderr that the run is paused at `point`, and waits, up to 60 s, for an interrupt.
fn pause(point: &str) {
    let seen = interrupts();
    eprintln!("spraysim: paused at {point}");
    let start = Instant::now();
    while interrupts() == seen && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writers_on_several_threads_commit_at_once_and_an_abort_waits_for_them() {
        let a = RunControl.begin_moving().expect("first writer");
        let b = RunControl.begin_moving().expect("a second writer, on another thread, at the same time");
        assert!(!try_abort(), "no abort while files move into place");
        drop(a);
        assert!(!try_abort());
        drop(b);
        assert!(try_abort(), "an abort once no writer is moving files");
        assert!(RunControl.begin_moving().is_none(), "nothing starts moving once aborting");
        PHASE.store(0, Ordering::SeqCst);
    }

    #[test]
    fn pause_points_match_only_the_names_the_run_writes() {
        let points = PausePoints::parse("step:40,staged,commit:2,step:077,step:-1,commit:x,other");
        assert_eq!(points, PausePoints { steps: vec![40], staged: true, commits: vec![2] });
        assert_eq!(PausePoints::parse(""), PausePoints::default());
        assert!(!PausePoints::parse(" staged").staged, "names are compared as written");
    }
}
