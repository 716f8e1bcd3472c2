//! One call at a time: a value that Python threads take turns with, in the order they asked.
//!
//! A thread that finds the value in use by another thread waits for its turn with the
//! interpreter released (so the holder, which may need the interpreter to finish its call, is
//! never blocked by the waiter), re-attaching about every [`work::SLICE`](crate::work::SLICE) to
//! let signal handlers run (Ctrl-C raises `KeyboardInterrupt` in a waiting main thread). Turns
//! are served first come, first served, so that a thread calling in a loop cannot keep the
//! others out. A thread that asks for the value while it already holds it (a callback of its
//! own call, such as `Simulation.run`'s `progress`) is refused with a `RuntimeError` instead of
//! waiting for itself forever.

use crate::work::SLICE;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use std::sync::{Condvar, Mutex, MutexGuard, PoisonError, TryLockError};
use std::thread::ThreadId;

/// A value used by one thread at a time; `what` names it in errors (`"this Simulation"`).
pub struct Exclusive<T> {
    value: Mutex<T>,
    /// Whose turn it is and who waits.
    line: Mutex<Line>,
    /// Signalled when a turn ends.
    freed: Condvar,
    what: &'static str,
}

/// The threads that asked for the value: a ticket each, served in order.
#[derive(Default)]
struct Line {
    /// The thread whose turn it is, if any.
    holder: Option<ThreadId>,
    /// The ticket the next thread to ask gets.
    next: u64,
    /// The ticket whose turn it is (or comes next, when `holder` is None).
    serving: u64,
    /// Tickets of threads that stopped waiting (interrupted) before their turn came.
    abandoned: Vec<u64>,
}

impl Line {
    /// Ends the turn being served and moves on to the next ticket still waiting.
    fn advance(&mut self) {
        self.holder = None;
        self.serving += 1;
        while let Some(i) = self.abandoned.iter().position(|&t| t == self.serving) {
            self.abandoned.swap_remove(i);
            self.serving += 1;
        }
    }
}

/// A thread's turn with the value: derefs to it; the turn ends when this is dropped.
pub struct Turn<'a, T> {
    /// The value; declared first, so that it is released before the turn is handed on.
    value: MutexGuard<'a, T>,
    _turn: TurnToken<'a>,
}

/// Hands the turn on when dropped.
struct TurnToken<'a> {
    line: &'a Mutex<Line>,
    freed: &'a Condvar,
}

impl Drop for TurnToken<'_> {
    fn drop(&mut self) {
        lock_line(self.line).advance();
        self.freed.notify_all();
    }
}

/// The line's lock: held for instants only, by threads that never wait for anything while
/// holding it, so that taking it attached cannot deadlock with the interpreter.
fn lock_line(line: &Mutex<Line>) -> MutexGuard<'_, Line> {
    // The line holds plain numbers, which a panic cannot leave half-written.
    line.lock().unwrap_or_else(PoisonError::into_inner)
}

/// What a wait for a turn found.
enum Wait {
    /// The turn is this thread's now.
    Taken,
    /// This thread's ticket is not served yet after one slice of waiting.
    Waiting(u64),
}

impl<T: Send> Exclusive<T> {
    /// `value`, to be used one thread at a time; `what` names it in errors.
    pub fn new(value: T, what: &'static str) -> Self {
        Exclusive { value: Mutex::new(value), line: Mutex::new(Line::default()), freed: Condvar::new(), what }
    }

    /// Waits for this thread's turn (detached, see the module's docs) and takes it. Raises
    /// `RuntimeError` when this thread already has it, or when an earlier call stopped in an
    /// internal error (a panic) that left the value unusable; `KeyboardInterrupt` (or another
    /// signal handler's exception) while waiting.
    pub fn lock(&self, py: Python<'_>) -> PyResult<Turn<'_, T>> {
        let me = std::thread::current().id();
        let mut wait = {
            let mut line = lock_line(&self.line);
            if line.holder == Some(me) {
                return Err(PyRuntimeError::new_err(format!(
                    "{} is busy in this same thread: a callback of one of its calls (such as `run`'s \
                     `progress`) cannot use it; read what you need after the call returns",
                    self.what
                )));
            }
            let ticket = line.next;
            line.next += 1;
            if line.holder.is_none() && line.serving == ticket {
                line.holder = Some(me);
                Wait::Taken
            } else {
                Wait::Waiting(ticket)
            }
        };
        while let Wait::Waiting(ticket) = wait {
            wait = py.detach(|| self.wait_for(ticket, me));
            if let Wait::Waiting(ticket) = wait
                && let Err(e) = py.check_signals()
            {
                self.abandon(ticket);
                return Err(e);
            }
        }
        let turn = TurnToken { line: &self.line, freed: &self.freed };
        // The turn is this thread's, so no other thread holds the value: `try_lock` only fails
        // when an earlier turn ended in a panic. On an error `turn` hands the turn on.
        match self.value.try_lock() {
            Ok(value) => Ok(Turn { value, _turn: turn }),
            Err(TryLockError::Poisoned(_)) => Err(PyRuntimeError::new_err(format!(
                "{} stopped in an internal error during an earlier call and cannot be used any more: \
                 make a new one",
                self.what
            ))),
            Err(TryLockError::WouldBlock) => {
                Err(PyRuntimeError::new_err(format!("{} is in use by another thread", self.what)))
            }
        }
    }

    /// Waits up to one slice for `ticket` to be served, and takes the turn if it was.
    fn wait_for(&self, ticket: u64, me: ThreadId) -> Wait {
        let line = lock_line(&self.line);
        let (mut line, _) = self
            .freed
            .wait_timeout_while(line, SLICE, |l| l.holder.is_some() || l.serving != ticket)
            .unwrap_or_else(PoisonError::into_inner);
        if line.holder.is_none() && line.serving == ticket {
            line.holder = Some(me);
            Wait::Taken
        } else {
            Wait::Waiting(ticket)
        }
    }

    /// Gives up `ticket` before its turn was taken, so that the line moves past it.
    fn abandon(&self, ticket: u64) {
        let mut line = lock_line(&self.line);
        if line.holder.is_none() && line.serving == ticket {
            // Its turn came meanwhile: pass it on.
            line.advance();
            drop(line);
            self.freed.notify_all();
        } else {
            line.abandoned.push(ticket);
        }
    }
}

impl<T> std::ops::Deref for Turn<'_, T> {
    type Target = T;

    fn deref(&self) -> &T {
        &self.value
    }
}

impl<T> std::ops::DerefMut for Turn<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.value
    }
}
