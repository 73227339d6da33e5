//! A tiny persistent fork-join pool for [`VecEnv`](super::vec_env::VecEnv).
//!
//! One batch step of 1024 CartPoles takes ~10 µs, which is less than spawning a thread, so the
//! workers are started once and wait for jobs by spinning briefly, then parking. [`Pool::run`]
//! runs `job(0)` on the calling thread and `job(1..threads)` on the workers and returns when all
//! are done (also when a job panics: the panic is re-raised on the calling thread afterwards).

use std::cell::UnsafeCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::thread::{JoinHandle, Thread};

type Job = dyn Fn(usize) + Sync;

/// How long an idle worker spins before it parks (spin-loop iterations).
const SPIN_BEFORE_PARK: u32 = 1 << 16;

struct Shared {
    /// Bumped (Release) after `job` is written; workers read `job` after seeing a new value.
    generation: AtomicU64,
    /// Workers still running the current job.
    pending: AtomicUsize,
    job: UnsafeCell<*const Job>,
    shutdown: AtomicBool,
    panicked: AtomicBool,
    /// Per worker: parked (or about to park) and must be unparked.
    sleeping: Vec<AtomicBool>,
}

// SAFETY: `job` is written only by the owner thread while no worker reads it (all workers have
// finished the previous job: `pending == 0`), and published via the Release bump of `generation`.
unsafe impl Sync for Shared {}
unsafe impl Send for Shared {}

pub(crate) struct Pool {
    shared: Arc<Shared>,
    threads: Vec<Thread>,
    handles: Vec<JoinHandle<()>>,
}

impl std::fmt::Debug for Pool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Pool").field("threads", &(self.handles.len() + 1)).finish()
    }
}

fn noop(_: usize) {}

impl Pool {
    /// A pool running jobs on `threads` threads in total (the caller plus `threads - 1` workers).
    pub(crate) fn new(threads: usize) -> Pool {
        let workers = threads.max(1) - 1;
        let noop: &'static Job = &noop;
        let shared = Arc::new(Shared {
            generation: AtomicU64::new(0),
            pending: AtomicUsize::new(0),
            job: UnsafeCell::new(noop as *const Job),
            shutdown: AtomicBool::new(false),
            panicked: AtomicBool::new(false),
            sleeping: (0..workers).map(|_| AtomicBool::new(false)).collect(),
        });
        let handles: Vec<JoinHandle<()>> = (0..workers)
            .map(|w| {
                let shared = Arc::clone(&shared);
                std::thread::Builder::new()
                    .name(format!("vecenv-{}", w + 1))
                    .spawn(move || worker(&shared, w))
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

    /// Run `job(t)` for every `t in 0..threads()`, `job(0)` on this thread; return when all finished.
    pub(crate) fn run(&mut self, job: &(dyn Fn(usize) + Sync)) {
        if self.handles.is_empty() {
            job(0);
            return;
        }
        let sh = &*self.shared;
        // SAFETY: the lifetime is erased only for the duration of this call: `WaitGuard` blocks
        // (even while unwinding) until every worker has finished with the job.
        let ptr: *const Job = unsafe { std::mem::transmute::<&(dyn Fn(usize) + Sync), &'static Job>(job) };
        // SAFETY: no worker is running a job (pending == 0 since the previous run returned), and
        // `&mut self` excludes concurrent `run`s.
        unsafe { *sh.job.get() = ptr };
        sh.pending.store(self.handles.len(), Ordering::Relaxed);
        // SeqCst pairs with the workers' "announce sleeping, re-check generation" (no lost wake-up).
        sh.generation.fetch_add(1, Ordering::SeqCst);
        for (flag, t) in sh.sleeping.iter().zip(&self.threads) {
            if flag.swap(false, Ordering::SeqCst) {
                t.unpark();
            }
        }
        let guard = WaitGuard(sh);
        job(0);
        drop(guard);
        if sh.panicked.swap(false, Ordering::AcqRel) {
            panic!("a VecEnv worker thread panicked");
        }
    }
}

struct WaitGuard<'a>(&'a Shared);

impl Drop for WaitGuard<'_> {
    fn drop(&mut self) {
        let mut spins = 0u32;
        while self.0.pending.load(Ordering::Acquire) != 0 {
            if spins < SPIN_BEFORE_PARK {
                spins += 1;
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }
}

fn worker(sh: &Shared, w: usize) {
    let mut seen = 0u64;
    loop {
        let mut spins = 0u32;
        let generation = loop {
            let g = sh.generation.load(Ordering::Acquire);
            if g != seen {
                break g;
            }
            if spins < SPIN_BEFORE_PARK {
                spins += 1;
                std::hint::spin_loop();
            } else {
                // Announce, re-check (the owner may have bumped before seeing the flag), park.
                sh.sleeping[w].store(true, Ordering::SeqCst);
                if sh.generation.load(Ordering::SeqCst) == seen {
                    std::thread::park();
                }
                sh.sleeping[w].store(false, Ordering::SeqCst);
            }
        };
        seen = generation;
        if sh.shutdown.load(Ordering::Acquire) {
            return;
        }
        // SAFETY: published by the Release bump observed above; valid until `pending` hits 0.
        let job = unsafe { &**sh.job.get() };
        if std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| job(w + 1))).is_err() {
            sh.panicked.store(true, Ordering::Release);
        }
        sh.pending.fetch_sub(1, Ordering::AcqRel);
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        self.shared.shutdown.store(true, Ordering::Release);
        self.shared.generation.fetch_add(1, Ordering::Release);
        for t in &self.threads {
            t.unpark();
        }
        for h in self.handles.drain(..) {
            let _ = h.join();
        }
    }
}
