//! What a run is told from outside while it writes: interrupts (Ctrl-C), and the pause points
//! at which the fault tests stop a run to send it a signal.
//!
//! The command's signal handler counts interrupts here; the writers read the count, and tell
//! the handler when they are moving files into place, which must not be cut short by a
//! second Ctrl-C.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// Interrupts received (Ctrl-C presses).
static INTERRUPTS: AtomicUsize = AtomicUsize::new(0);
/// What the writers and the interrupt handler agree on: how many writers are moving files into
/// place (which an abort must not cut short; several threads of one process may write sets
/// into different directories at once), or [`ABORTING`] (the process is exiting, and nothing
/// may start moving files).
static PHASE: AtomicUsize = AtomicUsize::new(0);
const ABORTING: usize = usize::MAX;

/// The environment variable that names a pause point (see [`pause_point`]).
pub const PAUSE_VARIABLE: &str = "SPRAYSIM_PAUSE_AT";

/// Counts one interrupt; returns how many there have been.
pub fn interrupt() -> usize {
    INTERRUPTS.fetch_add(1, Ordering::SeqCst) + 1
}

/// Interrupts received so far.
pub fn interrupts() -> usize {
    INTERRUPTS.load(Ordering::SeqCst)
}

/// Claims the right to abort: true when no writer is moving files into place, and then none
/// will start; false while one is (the caller lets it finish and exits after it).
pub fn try_abort() -> bool {
    PHASE.compare_exchange(0, ABORTING, Ordering::SeqCst, Ordering::SeqCst).is_ok()
}

/// Marks the stretch in which files are moved into place, until the guard drops.
pub(crate) struct Committing;

impl Committing {
    /// Enters the stretch; `None` when the process is aborting and must not start it.
    pub fn start() -> Option<Committing> {
        PHASE
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| (n != ABORTING).then_some(n + 1))
            .ok()
            .map(|_| Committing)
    }
}

impl Drop for Committing {
    fn drop(&mut self) {
        // Never ABORTING here: an abort waits for every writer to leave.
        PHASE.fetch_sub(1, Ordering::SeqCst);
    }
}

/// A fault-test hook: when the environment variable [`PAUSE_VARIABLE`] names `point` (e.g.
/// `step:40`, `commit:2`, `staged`; several separated by commas), says so on stderr and waits, up to 60 s, for an
/// interrupt, so that a test can send a signal at exactly this point. Does nothing otherwise.
pub fn pause_point(point: &str) {
    if std::env::var(PAUSE_VARIABLE).is_ok_and(|v| v.split(',').any(|p| p == point)) {
        let seen = interrupts();
        eprintln!("spraysim: paused at {point}");
        let start = Instant::now();
        while interrupts() == seen && start.elapsed() < Duration::from_secs(60) {
            std::thread::sleep(Duration::from_millis(5));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writers_on_several_threads_commit_at_once_and_an_abort_waits_for_them() {
        let a = Committing::start().expect("first writer");
        let b = Committing::start().expect("a second writer, on another thread, at the same time");
        assert!(!try_abort(), "no abort while files move into place");
        drop(a);
        assert!(!try_abort());
        drop(b);
        assert!(try_abort(), "an abort once no writer is moving files");
        assert!(Committing::start().is_none(), "nothing starts moving once aborting");
        PHASE.store(0, Ordering::SeqCst);
    }
}
