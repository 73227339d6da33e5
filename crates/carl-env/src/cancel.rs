//! Cancelling long native work: a check the caller installs around a call, polled by the loops
//! that can run long (rna_design's local improvement, up to 4^d folds).
//!
//! The caller (the Python binding, with PyO3's `Python::check_signals`) wraps a call:
//!
//! ```
//! use carl_env::cancel;
//! // In the binding: `with_check(|| Python::attach(|py| py.check_signals().is_err()), ...)`.
//! let stopped = cancel::with_check(|| true, || {
//!     // env.step(&action) here; a long loop inside it calls `cancel::poll()`:
//!     cancel::poll().is_err()
//! });
//! assert!(stopped);
//! assert!(cancel::poll().is_ok(), "no check outside the call");
//! ```
//!
//! * [`with_check`]`(check, f)` runs `f` with `check` (a plain function: installing it allocates
//!   nothing) installed **on the calling thread** and
//!   restores the previous check afterwards (nesting works; a panic in `f` restores it too).
//! * [`poll`] calls the installed check, if any; `Err(Interrupted)` when it returns `true`.
//!   Without a check installed (the CLI, tests) it is one thread-local read and never cancels.
//! * A loop that polls turns `Err(Interrupted)` into [`crate::EnvError::Interrupted`]; the
//!   environment is then in an unfinished episode and needs a reset before it steps again.
//!
//! Loops poll every [`POLL_EVERY`] iterations of work that costs microseconds to milliseconds
//! each, so a cancellation is seen within well under a second.
//!
//! Other threads do not see the calling thread's check. Work spread over worker threads (a
//! vector environment's pool) shares a stop flag instead: the workers install [`with_flag`]
//! once, and the calling thread runs its part under [`relay`], which asks the calling thread's
//! check and raises the flag when it says stop, so one Ctrl-C stops every thread's loops.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// How many units of work (e.g. folds) a loop does between two polls.
pub const POLL_EVERY: u64 = 16;

/// The installed check said stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Interrupted;

/// An installed check: a plain function (the binding's Ctrl-C check: installing it allocates
/// nothing, once per step) or a closure (the relays of a worker pool, once per batch job).
#[derive(Clone)]
enum Check {
    Plain(fn() -> bool),
    Closure(Rc<dyn Fn() -> bool>),
}

impl Check {
    fn stop(&self) -> bool {
        match self {
            Check::Plain(f) => f(),
            Check::Closure(f) => f(),
        }
    }
}

thread_local! {
    static CHECK: RefCell<Option<Check>> = const { RefCell::new(None) };
}

/// Restores the previous check when dropped (also on unwinding).
struct Restore(Option<Check>);

impl Drop for Restore {
    fn drop(&mut self) {
        let previous = self.0.take();
        CHECK.with(|c| *c.borrow_mut() = previous);
    }
}

fn install<R>(check: Check, f: impl FnOnce() -> R) -> R {
    let previous = CHECK.with(|c| c.borrow_mut().replace(check));
    let _restore = Restore(previous);
    f()
}

/// Run `f` with `check` installed on this thread: long loops inside `f` call it through
/// [`poll`] and stop when it returns `true`.
pub fn with_check<R>(check: fn() -> bool, f: impl FnOnce() -> R) -> R {
    install(Check::Plain(check), f)
}

/// Run `f` with a check that reads `flag` (a worker thread's whole life: the flag is raised by
/// the thread that [`relay`]s its check).
pub fn with_flag<R>(flag: Arc<AtomicBool>, f: impl FnOnce() -> R) -> R {
    install(Check::Closure(Rc::new(move || flag.load(Ordering::Relaxed))), f)
}

/// Run `f` with this thread's check (if any) relayed to `flag`: inside `f` a poll asks `flag`
/// first, then the check, and raises `flag` when the check says stop (a check that consumes
/// what it reports, as Python's signal check does, thus still stops every thread sharing
/// `flag`). Without a check installed `f` simply runs: nothing could raise the flag.
pub fn relay<R>(flag: &Arc<AtomicBool>, f: impl FnOnce() -> R) -> R {
    let Some(outer) = CHECK.with(|c| c.borrow().clone()) else {
        return f();
    };
    let flag = Arc::clone(flag);
    let relayed = move || {
        if flag.load(Ordering::Relaxed) {
            return true;
        }
        let stop = outer.stop();
        if stop {
            flag.store(true, Ordering::Relaxed);
        }
        stop
    };
    install(Check::Closure(Rc::new(relayed)), f)
}

/// Ask the installed check (if any) whether to stop.
pub fn poll() -> Result<(), Interrupted> {
    // Clone the check out so that it may itself call `with_check` or `poll`.
    let check = CHECK.with(|c| c.borrow().clone());
    match check {
        Some(check) if check.stop() => Err(Interrupted),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    thread_local! {
        static CALLS: Cell<u32> = const { Cell::new(0) };
    }

    /// Says stop from its third call on (counting per thread).
    fn third_call_on() -> bool {
        CALLS.with(|c| {
            c.set(c.get() + 1);
            c.get() >= 3
        })
    }

    /// Says stop on its first call only (as Python's signal check consumes the signal).
    fn first_call_only() -> bool {
        CALLS.with(|c| {
            c.set(c.get() + 1);
            c.get() == 1
        })
    }

    #[test]
    fn checks_are_scoped_to_the_call_and_thread() {
        assert_eq!(poll(), Ok(()));
        CALLS.with(|c| c.set(0));
        let r = with_check(third_call_on, || {
            let inner = with_check(|| false, poll);
            assert_eq!(inner, Ok(()));
            (0..5).map(|_| poll()).collect::<Vec<_>>()
        });
        assert_eq!(
            r,
            [Ok(()), Ok(()), Err(Interrupted), Err(Interrupted), Err(Interrupted)]
        );
        assert_eq!(CALLS.with(Cell::get), 5);
        assert_eq!(poll(), Ok(()), "restored after the call");
        let other = with_check(|| true, || std::thread::spawn(poll).join().unwrap());
        assert_eq!(other, Ok(()), "another thread does not see this thread's check");
        let caught = std::panic::catch_unwind(|| with_check(|| true, || panic!("boom")));
        assert!(caught.is_err());
        assert_eq!(poll(), Ok(()), "restored after a panic");
    }

    #[test]
    fn a_relayed_stop_reaches_threads_sharing_the_flag() {
        let flag = Arc::new(AtomicBool::new(false));
        // Without a check on this thread, relay installs nothing.
        assert_eq!(relay(&flag, poll), Ok(()));
        assert!(!flag.load(Ordering::Relaxed));
        CALLS.with(|c| c.set(0));
        let worker_flag = Arc::clone(&flag);
        let (first, second, worker) = with_check(first_call_only, || {
            relay(&flag, || {
                let first = poll();
                let second = poll();
                let worker = std::thread::spawn(move || with_flag(worker_flag, poll)).join().unwrap();
                (first, second, worker)
            })
        });
        assert_eq!(first, Err(Interrupted));
        assert_eq!(
            second,
            Err(Interrupted),
            "the flag keeps the stop after the check consumed it"
        );
        assert_eq!(worker, Err(Interrupted), "a worker thread sees the relayed stop");
        assert_eq!(CALLS.with(Cell::get), 1, "the check is not asked once the flag is up");
        flag.store(false, Ordering::Relaxed);
        let idle = Arc::clone(&flag);
        assert_eq!(
            std::thread::spawn(move || with_flag(idle, poll)).join().unwrap(),
            Ok(())
        );
    }
}
