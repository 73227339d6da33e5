//! A tiny persistent fork-join pool for [`VecEnv`](super::vec_env::VecEnv).
//!
//! One batch step of 1024 CartPoles takes ~10 µs, less than spawning a thread, so the workers
//! are started once and wait for jobs by spinning briefly, then parking. [`Pool::run`] splits
//! `0..n` into blocks that the calling thread and the workers claim from a shared counter, so a
//! worker that is descheduled (a busy machine) never stalls the step: the caller simply does the
//! remaining blocks itself. A worker may only join a job while it is open; the caller closes it
//! when no block is left and waits just for workers that are inside the job. A panic in a job is
//! re-raised on the calling thread.
//!
//! Cancellation ([`carl_env::cancel`]): each worker polls the pool's stop flag; a job's calling
//! thread relays its own check (the binding's Ctrl-C check) to that flag, also while it waits for
//! the workers, so a long batch step (rna_design's folds) stops on every thread.

use std::cell::UnsafeCell;
use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::thread::{JoinHandle, Thread};

use carl_env::cancel;

type Job = dyn Fn(Range<usize>) + Sync;

/// How long the caller spins (`pause`) waiting for workers before it yields: ~400 µs here.
const SPIN: u32 = 1 << 14;
/// While the caller yields waiting for workers, it asks its cancellation check every this many
/// yields.
const POLL_WAIT: u32 = 64;
/// How long an idle worker polls for a job before it parks: ~450 µs here (a poll is ~0.4 ns).
const POLLS: u32 = 1 << 20;
/// [`POLLS`] in nanoseconds, roughly (to turn a time into polls).
const POLLS_NS: u128 = 450_000;
/// A worker whose share of its last job took longer than this (heavy environments: a physics
/// world per environment) polls for the next job an eighth of that share's time, at most
/// [`HEAVY_POLL_NS`], before it parks, not [`POLLS`]: parking costs such jobs little (the
/// calling thread steps blocks while the worker wakes), while polling through every gap burns
/// the core's time, which on a busy machine (more runnable threads than cores) the scheduler
/// takes back from the worker in the next job, where the caller then waits for its block
/// (Pusher ×16 on two threads at load ~20: 5.7–8.5 k steps/s polling `POLLS`, 10.7–20.9 k so).
const HEAVY_SHARE_NS: u128 = 200_000;
/// The longest poll after a heavy share, ns.
const HEAVY_POLL_NS: u128 = 100_000;

/// `state`: generation in the high 32 bits, `CLOSED` flag, active-worker count in the low bits.
const CLOSED: u64 = 1 << 31;
const ACTIVE_MASK: u64 = CLOSED - 1;
const GEN_ONE: u64 = 1 << 32;

/// An atomic on a cache line of its own.
#[repr(align(128))]
struct Line<T>(T);

impl<T> std::ops::Deref for Line<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

struct Shared {
    /// Its own cache line: idle workers poll it in a tight loop.
    state: Line<AtomicU64>,
    /// Next unclaimed item of the current job (its own cache line, apart from the polled
    /// `state`: claiming must not contend with the workers' polling).
    next: Line<AtomicUsize>,
    /// `(job, n, block)` of the current job; written only while no worker is inside a job.
    job: UnsafeCell<(*const Job, usize, usize)>,
    shutdown: AtomicBool,
    panicked: AtomicBool,
    /// Raised when the calling thread's check says stop (lowered when a job opens); the
    /// workers' loops poll it.
    stop: Arc<AtomicBool>,
    /// Per worker: parked (or about to park) and must be unparked.
    sleeping: Vec<AtomicBool>,
}

// SAFETY: `job` is written by the owner only while the job is closed and no worker is active; a
// worker reads it only after joining the open job (an Acquire CAS on `state` that follows the
// owner's Release store of the new generation).
unsafe impl Sync for Shared {}
unsafe impl Send for Shared {}

pub(crate) struct Pool {
    shared: Arc<Shared>,
    threads: Vec<Thread>,
    handles: Vec<JoinHandle<()>>,
}

impl std::fmt::Debug for Pool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pool").field("threads", &self.threads()).finish()
    }
}

fn noop(_: Range<usize>) {}

/// Claim blocks until none is left; whether any was claimed.
fn drain(sh: &Shared, job: &(dyn Fn(Range<usize>) + Sync + '_), n: usize, block: usize) -> bool {
    let mut any = false;
    loop {
        let start = sh.next.fetch_add(block, Ordering::Relaxed);
        if start >= n {
            return any;
        }
        any = true;
        job(start..(start + block).min(n));
    }
}

impl Pool {
    /// A pool running jobs on `threads` threads in total (the caller plus `threads - 1` workers).
    pub(crate) fn new(threads: usize) -> Pool {
        let workers = threads.max(1) - 1;
        let noop: &'static Job = &noop;
        let shared = Arc::new(Shared {
            state: Line(AtomicU64::new(CLOSED)),
            next: Line(AtomicUsize::new(0)),
            job: UnsafeCell::new((noop as *const Job, 0, 1)),
            shutdown: AtomicBool::new(false),
            panicked: AtomicBool::new(false),
            stop: Arc::new(AtomicBool::new(false)),
            sleeping: (0..workers).map(|_| AtomicBool::new(false)).collect(),
        });
        let handles: Vec<JoinHandle<()>> = (0..workers)
            .map(|w| {
                let shared = Arc::clone(&shared);
                std::thread::Builder::new()
                    .name(format!("vecenv-{}", w + 1))
                    .spawn(move || cancel::with_flag(Arc::clone(&shared.stop), || worker(&shared, w)))
                    .expect("failed to spawn a VecEnv worker thread")
            })
            .collect();
        let threads = handles.iter().map(|h| h.thread().clone()).collect();
        Pool {
            shared,
            threads,
            handles,
        }
    }

    /// Number of threads (including the caller).
    pub(crate) fn threads(&self) -> usize {
        self.handles.len() + 1
    }

    /// Call `job` on disjoint ranges covering `0..n` (blocks of `block` items) from all threads;
    /// return when every range is done. The calling thread first runs `caller` while the
    /// workers already claim blocks: `caller` may do other work there (the Python binding makes
    /// the step's output objects, with the GIL) before it takes its own [`CallerShare`] of the
    /// blocks (for example with the GIL released); blocks it leaves are claimed after it returns.
    pub(crate) fn run(
        &mut self,
        n: usize,
        block: usize,
        job: &(dyn Fn(Range<usize>) + Sync),
        caller: impl FnOnce(&mut CallerShare<'_>),
    ) {
        let block = block.max(1);
        let sh = &*self.shared;
        if self.handles.is_empty() || n <= block {
            // One block on the calling thread; no job is opened, so no worker joins.
            sh.next.store(0, Ordering::Relaxed);
            let mut share = CallerShare {
                sh,
                shared: false,
                job,
                n,
                block: n.max(1),
            };
            caller(&mut share);
            share.claim_all();
            return;
        }
        // SAFETY: the lifetime is erased only while the job is open: `CloseGuard` closes it and
        // waits (even while unwinding) until no worker is inside it.
        let ptr: *const Job = unsafe { std::mem::transmute::<&(dyn Fn(Range<usize>) + Sync), &'static Job>(job) };
        // SAFETY: the previous job is closed with no active worker, and `&mut self` excludes
        // concurrent `run`s.
        unsafe { *sh.job.get() = (ptr, n, block) };
        sh.next.store(0, Ordering::Relaxed);
        sh.stop.store(false, Ordering::Relaxed);
        let generation = (sh.state.load(Ordering::Relaxed) & !(GEN_ONE - 1)).wrapping_add(GEN_ONE);
        // SeqCst pairs with the workers' "announce sleeping, re-check state" (no lost wake-up).
        sh.state.store(generation, Ordering::SeqCst);
        for (flag, t) in sh.sleeping.iter().zip(&self.threads) {
            if flag.swap(false, Ordering::SeqCst) {
                t.unpark();
            }
        }
        cancel::relay(&sh.stop, || {
            let guard = CloseGuard(sh);
            let mut share = CallerShare {
                sh,
                shared: true,
                job,
                n,
                block,
            };
            caller(&mut share);
            share.claim_all();
            drop(guard);
        });
        if sh.panicked.swap(false, Ordering::AcqRel) {
            panic!("a VecEnv worker thread panicked");
        }
    }
}

/// The calling thread's share of a job of the worker pool (`Pool::run`, behind
/// [`super::vec_env::VecEnv::step_with`]). It is `Send`, so the claiming may happen inside a
/// closure that runs with the GIL released.
pub struct CallerShare<'a> {
    sh: &'a Shared,
    /// Whether worker threads take part in this job (false: one block on the calling thread).
    shared: bool,
    job: &'a (dyn Fn(Range<usize>) + Sync + 'a),
    n: usize,
    block: usize,
}

impl CallerShare<'_> {
    /// Claim and run blocks until none is left (the workers may still finish theirs).
    pub fn claim_all(&mut self) {
        drain(self.sh, self.job, self.n, self.block);
    }

    /// Whether blocks are left that worker threads may claim meanwhile (false without workers):
    /// work the calling thread does before [`CallerShare::claim_all`] while this holds overlaps
    /// the workers' stepping, and the blocks it would have stepped go to them.
    pub fn blocks_left(&self) -> bool {
        self.shared && self.sh.next.load(Ordering::Relaxed) < self.n
    }

    /// Whether a worker thread is still inside the job (after [`CallerShare::claim_all`]: still
    /// stepping its last block, so the calling thread would only wait).
    pub fn workers_busy(&self) -> bool {
        self.sh.state.load(Ordering::Acquire) & ACTIVE_MASK != 0
    }
}

struct CloseGuard<'a>(&'a Shared);

impl Drop for CloseGuard<'_> {
    fn drop(&mut self) {
        let sh = self.0;
        sh.state.fetch_or(CLOSED, Ordering::AcqRel);
        let mut spins = 0u32;
        while sh.state.load(Ordering::Acquire) & ACTIVE_MASK != 0 {
            if spins < SPIN {
                spins += 1;
                std::hint::spin_loop();
            } else {
                // A long wait (workers in long steps): relay a stop to them now and then.
                spins = spins.wrapping_add(1);
                if spins % POLL_WAIT == 0 && !std::thread::panicking() {
                    let _ = cancel::poll();
                }
                std::thread::yield_now();
            }
        }
    }
}

fn worker(sh: &Shared, w: usize) {
    let mut seen_gen = 0u64;
    // Polls before parking: `POLLS`, or less after a heavy share (see `HEAVY_SHARE_NS`).
    let mut polls = POLLS;
    loop {
        let mut spins = 0u32;
        // Wait for a new, open generation and join it (active += 1).
        let joined = loop {
            if sh.shutdown.load(Ordering::Acquire) {
                return;
            }
            let s = sh.state.load(Ordering::Acquire);
            let generation = s & !(GEN_ONE - 1);
            if generation != seen_gen {
                if s & CLOSED != 0 {
                    // Finished without us.
                    seen_gen = generation;
                    continue;
                }
                if sh
                    .state
                    .compare_exchange_weak(s, s + 1, Ordering::AcqRel, Ordering::Relaxed)
                    .is_ok()
                {
                    seen_gen = generation;
                    break true;
                }
                continue;
            }
            if spins < polls {
                spins += 1;
                // No `spin_loop()` (x86 `pause`) here: under KVM a long run of `pause` makes the
                // vCPU exit to the hypervisor (pause-loop exiting), and a worker that spins
                // through the caller's Python work at every batch step then slowed `make_vec`'s
                // LunarLander steps by ~20 % after the first ~0.3 s (bimodal rounds, docs/performance.md).
                std::hint::black_box(());
            } else {
                sh.sleeping[w].store(true, Ordering::SeqCst);
                if sh.state.load(Ordering::SeqCst) & !(GEN_ONE - 1) == seen_gen && !sh.shutdown.load(Ordering::SeqCst) {
                    std::thread::park();
                }
                sh.sleeping[w].store(false, Ordering::SeqCst);
                spins = 0;
            }
        };
        if joined {
            // SAFETY: we are active in the open job, so the owner keeps it alive and unchanged.
            let (job, n, block) = unsafe { *sh.job.get() };
            let job = unsafe { &*job };
            let t0 = std::time::Instant::now();
            match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| drain(sh, job, n, block))) {
                Ok(true) => {
                    let ns = t0.elapsed().as_nanos();
                    polls = if ns < HEAVY_SHARE_NS {
                        POLLS
                    } else {
                        ((ns / 8).min(HEAVY_POLL_NS) * u128::from(POLLS) / POLLS_NS) as u32
                    };
                }
                Ok(false) => {}
                Err(_) => sh.panicked.store(true, Ordering::Release),
            }
            sh.state.fetch_sub(1, Ordering::AcqRel);
        }
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        self.shared.shutdown.store(true, Ordering::SeqCst);
        for t in &self.threads {
            t.unpark();
        }
        for h in self.handles.drain(..) {
            let _ = h.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;
    use std::time::{Duration, Instant};

    /// Each block loops until a poll says stop (or 10 s pass) and records which it was.
    fn long_job(stopped: &Mutex<Vec<(bool, bool)>>) -> impl Fn(Range<usize>) + Sync + '_ {
        move |r: Range<usize>| {
            let t0 = Instant::now();
            let mut seen = false;
            while t0.elapsed() < Duration::from_secs(10) {
                if cancel::poll().is_err() {
                    seen = true;
                    break;
                }
                std::thread::sleep(Duration::from_micros(50));
            }
            let worker = std::thread::current().name().is_some_and(|n| n.starts_with("vecenv-"));
            stopped.lock().unwrap().extend(r.map(|_| (seen, worker)));
        }
    }

    #[test]
    fn the_callers_check_stops_the_workers_blocks_too() {
        let mut pool = Pool::new(2);
        let stopped = Mutex::new(Vec::new());
        let job = long_job(&stopped);
        thread_local! {
            static CALLS: std::cell::Cell<u32> = const { std::cell::Cell::new(0) };
        }
        // A check that says stop once, on its 20th call (Python's signal check consumes the signal).
        fn check() -> bool {
            CALLS.with(|c| {
                c.set(c.get() + 1);
                c.get() == 20
            })
        }
        let t0 = Instant::now();
        // The caller waits before claiming, so the worker takes a block.
        let pause = |_: &mut CallerShare<'_>| std::thread::sleep(Duration::from_millis(50));
        cancel::with_check(check, || pool.run(2, 1, &job, pause));
        assert!(
            t0.elapsed() < Duration::from_secs(5),
            "the run waited for the long blocks"
        );
        let mut seen = stopped.lock().unwrap().clone();
        seen.sort();
        assert_eq!(
            seen,
            [(true, false), (true, true)],
            "both blocks, the worker's too, saw the stop"
        );
        // The next job starts with the flag lowered: without a check nothing stops.
        let quick_seen = Mutex::new(Vec::new());
        let quick = |r: Range<usize>| quick_seen.lock().unwrap().extend(r.map(|_| cancel::poll().is_err()));
        pool.run(4, 1, &quick, |_| {});
        assert_eq!(*quick_seen.lock().unwrap(), [false; 4]);
    }
}
