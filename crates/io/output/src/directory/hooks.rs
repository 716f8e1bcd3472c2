//! What the caller of a set's writer may learn and decide while the set goes into place: hooks
//! as a trait, called by [`super::OutputDir::write_set_with`].
//!
//! The writer knows nothing of signals or of the process it runs in. A program that must not
//! be cut short while files move (the command line, which counts Ctrl-C presses) implements
//! [`CommitHooks`]; everyone else writes with [`NoHooks`] through
//! [`super::OutputDir::write_set`].

use std::any::Any;

/// Held by the writer while files move into place (see [`CommitHooks::begin_moving`]) and
/// dropped once every file has moved in, or back after a failure.
pub type MovingGuard = Box<dyn Any>;

/// A point a set's write passes, reported to [`CommitHooks::reached`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CommitPoint {
    /// Every file of the new set is written into the staging folder; nothing in the directory
    /// has changed yet.
    Staged,
    /// The `k`-th file of the new set (counting from 1, the set's index not counted: it moves
    /// in last) has just moved into the directory, which holds a mix of the two sets until the
    /// swap ends.
    MovedIn(usize),
}

/// Hooks into a set's write. Both methods have defaults that change nothing.
pub trait CommitHooks {
    /// Asked once the set is staged and its journal written, just before the first file moves.
    /// `None` refuses: nothing moves, the directory keeps the previous set and the write fails
    /// with an `Interrupted` error. Otherwise the guard returned is held until every file has
    /// moved in (or, after a failure, back).
    fn begin_moving(&self) -> Option<MovingGuard> {
        Some(Box::new(()))
    }

    /// Told when the write reaches `point`; the write goes on when this returns.
    fn reached(&self, _point: CommitPoint) {}
}

/// The hooks of a caller that needs none: every move allowed, no point reported.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoHooks;

impl CommitHooks for NoHooks {}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::OutputDir;
    use std::cell::RefCell;
    use std::rc::Rc;

    /// Hooks that note what they are told and asked, and refuse when `refuse` is set.
    #[derive(Default)]
    struct Notes {
        seen: Rc<RefCell<Vec<String>>>,
        refuse: bool,
    }

    /// Notes "moved" when the writer drops it.
    struct Moving(Rc<RefCell<Vec<String>>>);

    impl Drop for Moving {
        fn drop(&mut self) {
            self.0.borrow_mut().push("moved".into());
        }
    }

    impl CommitHooks for Notes {
        fn begin_moving(&self) -> Option<MovingGuard> {
            self.seen.borrow_mut().push("begin".into());
            (!self.refuse).then(|| Box::new(Moving(self.seen.clone())) as MovingGuard)
        }

        fn reached(&self, point: CommitPoint) {
            self.seen.borrow_mut().push(format!("{point:?}"));
        }
    }

    fn set(tag: &str) -> Vec<(String, Vec<u8>)> {
        ["metrics.json", "a_hits.npy", "b_hits.npy"].iter().map(|n| (n.to_string(), tag.into())).collect()
    }

    #[test]
    fn hooks_hear_the_staging_each_file_moved_in_and_hold_the_moves_in_between() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let dir = OutputDir::lock(tmp.path()).expect("lock");
        let hooks = Notes::default();
        dir.write_set_with(&set("new"), &hooks).expect("written");
        assert_eq!(*hooks.seen.borrow(), ["Staged", "begin", "MovedIn(1)", "MovedIn(2)", "moved"]);
    }

    #[test]
    fn hooks_that_refuse_the_moves_leave_the_previous_set_in_place() {
        let tmp = tempfile::tempdir().expect("tempdir");
        let dir = OutputDir::lock(tmp.path()).expect("lock");
        dir.write_set(&set("old")).expect("first set, without hooks");
        let hooks = Notes { refuse: true, ..Notes::default() };
        let err = dir.write_set_with(&set("new"), &hooks).expect_err("refused");
        assert!(err.to_string().contains("aborted before moving files into place"), "{err}");
        assert_eq!(*hooks.seen.borrow(), ["Staged", "begin"]);
        for name in ["metrics.json", "a_hits.npy", "b_hits.npy"] {
            assert_eq!(std::fs::read(tmp.path().join(name)).expect("read"), b"old", "{name}");
        }
    }
}
