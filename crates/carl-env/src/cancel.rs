//! Cancelling long native work: a check the caller installs around a call, polled by the loops
//! that can run long (rna_design's local improvement, up to 4^d folds).
//!
//! The caller (the Python binding, with PyO3's `Python::check_signals`) wraps a call:
//!
//! ```
//! use carl_env::cancel;
//! // In the binding: `with_check(move || Python::with_gil(|py| py.check_signals().is_err()), ...)`.
//! let stopped = cancel::with_check(|| true, || {
//!     // env.step(&action) here; a long loop inside it calls `cancel::poll()`:
//!     cancel::poll().is_err()
//! });
//! assert!(stopped);
//! assert!(cancel::poll().is_ok(), "no check outside the call");
//! ```
//!
//! * [`with_check`]`(check, f)` runs `f` with `check` installed **on the calling thread** and
//!   restores the previous check afterwards (nesting works; a panic in `f` restores it too).
//! * [`poll`] calls the installed check, if any; `Err(Interrupted)` when it returns `true`.
//!   Without a check installed (the CLI, tests) it is one thread-local read and never cancels.
//! * A loop that polls turns `Err(Interrupted)` into [`crate::EnvError::Interrupted`]; the
//!   environment is then in an unfinished episode and needs a reset before it steps again.
//!
//! Loops poll every [`POLL_EVERY`] iterations of work that costs microseconds to milliseconds
//! each, so a cancellation is seen within well under a second. Work run on other threads (a
//! vector environment's worker pool) does not see the calling thread's check.

use std::cell::RefCell;
use std::rc::Rc;

/// How many units of work (e.g. folds) a loop does between two polls.
pub const POLL_EVERY: u64 = 16;

/// The installed check said stop.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Interrupted;

type Check = Rc<dyn Fn() -> bool>;

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

/// Run `f` with `check` installed on this thread: long loops inside `f` call it through
/// [`poll`] and stop when it returns `true`.
pub fn with_check<R>(check: impl Fn() -> bool + 'static, f: impl FnOnce() -> R) -> R {
    let previous = CHECK.with(|c| c.borrow_mut().replace(Rc::new(check)));
    let _restore = Restore(previous);
    f()
}

/// Ask the installed check (if any) whether to stop.
pub fn poll() -> Result<(), Interrupted> {
    // Clone the check out so that it may itself call `with_check` or `poll`.
    let check = CHECK.with(|c| c.borrow().clone());
    match check {
        Some(check) if check() => Err(Interrupted),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    #[test]
    fn checks_are_scoped_to_the_call_and_thread() {
        assert_eq!(poll(), Ok(()));
        let calls = Rc::new(Cell::new(0));
        let seen = calls.clone();
        let r = with_check(
            move || {
                seen.set(seen.get() + 1);
                seen.get() >= 3
            },
            || {
                let inner = with_check(|| false, poll);
                assert_eq!(inner, Ok(()));
                (0..5).map(|_| poll()).collect::<Vec<_>>()
            },
        );
        assert_eq!(
            r,
            [Ok(()), Ok(()), Err(Interrupted), Err(Interrupted), Err(Interrupted)]
        );
        assert_eq!(calls.get(), 5);
        assert_eq!(poll(), Ok(()), "restored after the call");
        let other = with_check(|| true, || std::thread::spawn(poll).join().unwrap());
        assert_eq!(other, Ok(()), "another thread does not see this thread's check");
        let caught = std::panic::catch_unwind(|| with_check(|| true, || panic!("boom")));
        assert!(caught.is_err());
        assert_eq!(poll(), Ok(()), "restored after a panic");
    }
}
