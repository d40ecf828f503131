//! Where a solve runs: on one of rayon's worker threads, the others kept awake for its sections
//! (docs/performance.md, "The solve on the pool's threads" and "A partner that does not sleep").
//!
//! A parallel section (`par_iter`, `rayon::join`) started from a thread **outside** the pool is
//! injected into the pool's queue, and the calling thread blocks on a lock until a worker has run
//! it: every section costs a hand-off to a (possibly sleeping) worker and a wake-up of the caller.
//! A solve at 128² runs ≈ 12–15 such sections per iteration of ≈ 0.5–1 ms, so from the main
//! thread the second thread hardly paid. Started **on** a worker, a section is pushed to that
//! worker's own deque and the other worker steals half of it; the caller works on the other half
//! and never sleeps.
//!
//! Between two sections (a dot product, a convergence test, the serial bookkeeping) the other
//! worker finds no work; after a few rounds rayon puts it to sleep, and the next section must wake
//! it with a futex call on the solving thread's path, then wait for the kernel (and, on a virtual
//! machine, the host) to run it again: the cost that varied from process to process. [`on_pool`]
//! therefore starts, next to a large solve, a **partner** job: whichever worker steals it polls
//! for the solve's sections (`rayon::yield_now`) until the solve is done, so it is awake at every
//! section (its processor time during the solve is spent waiting, not computing).
//!
//! [`on_pool`] runs a whole solve on a worker: one hand-off per solve instead of one per section.
//!
//! Two costs of the partner a caller should know: it spends a core's time polling for the whole
//! solve (on a machine whose other cores run the caller's own parallel work, turn it off with
//! [`set_partner`]`(false)`), and it runs *whatever* job the pool offers it — in a pool shared
//! with the caller's own tasks it may pick up an unrelated job and finish it before it sees that
//! the solve is done, which delays `on_pool`'s return by that job's length (never its result).

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Grids of at least this many cells get a partner in [`on_pool`] (the size from which the FFTs'
/// and the passes' sections run on threads: [`crate::fft2d::PARALLEL_CELLS`]).
pub const PARTNER_CELLS: usize = crate::fft2d::PARALLEL_CELLS;

/// Grids of more than this many cells get no partner: from 512² the sections are long enough
/// that a wake-up is a small part of them, and the partner's polling cost ≈ 4 % of the wall time
/// (docs/performance.md, "A partner that does not sleep").
pub const PARTNER_MAX_CELLS: usize = 256 * 256;

/// Whether [`on_pool`] starts partners (on by default).
static PARTNER_ON: AtomicBool = AtomicBool::new(true);

/// Turns [`on_pool`]'s partner on or off for the whole process (default on). Off, a solve of
/// [`PARTNER_CELLS`]`..=`[`PARTNER_MAX_CELLS`] cells runs as a larger one does (on a worker, its
/// sections' other halves taken by sleeping workers): the same results bit for bit, no core spent
/// polling, more wake-ups (docs/performance.md, "A partner that does not sleep").
pub fn set_partner(on: bool) {
    PARTNER_ON.store(on, Ordering::Relaxed);
}

/// Whether [`on_pool`] starts partners ([`set_partner`]).
pub fn partner_enabled() -> bool {
    PARTNER_ON.load(Ordering::Relaxed)
}

/// `f()` run on one of the global rayon pool's worker threads (the caller waits): directly when
/// the caller already is one, or when the pool has one thread (nothing runs in parallel then).
/// With [`PARTNER_CELLS`] `≤ cells ≤` [`PARTNER_MAX_CELLS`] (the size of the problem `f`
/// solves) a partner job keeps another worker polling for `f`'s parallel sections until `f`
/// returns (module doc; [`set_partner`] turns it off). The result is the same bit for bit as `f()` on the calling thread; only
/// where it runs differs.
pub fn on_pool<R: Send>(cells: usize, f: impl FnOnce() -> R + Send) -> R {
    on_pool_with(partner_enabled(), cells, f)
}

/// [`on_pool`] with a partner whatever the problem's size (unless [`set_partner`]`(false)`): for
/// a computation of many sections of a few tens of microseconds each, where a wake-up per section
/// would cost as much as the section (the MDR wear run's split FFTs, docs/performance.md, "Two
/// threads in the MDR wear run"). The same result bit for bit as `f()` on the calling thread.
pub fn on_pool_with_partner<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    on_pool_with(partner_enabled(), PARTNER_CELLS, f)
}

/// [`on_pool`] with the partner switch given (`partner_on`: whether a partner may start) instead of
/// read from [`set_partner`]'s process-wide setting.
fn on_pool_with<R: Send>(partner_on: bool, cells: usize, f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() || rayon::current_num_threads() <= 1 {
        f()
    } else if !partner_on || !(PARTNER_CELLS..=PARTNER_MAX_CELLS).contains(&cells) {
        rayon::scope(|_| f())
    } else {
        let done = AtomicBool::new(false);
        let owner = AtomicUsize::new(usize::MAX);
        let (r, ()) = rayon::join(
            || {
                owner.store(
                    rayon::current_thread_index().unwrap_or(usize::MAX),
                    Ordering::Release,
                );
                // Set when `f` returns or unwinds: a panicking `f` must not leave a stolen
                // partner polling forever (rayon's join waits for it before it re-raises).
                let _done = SetOnDrop(&done);
                f()
            },
            || partner(&done, &owner),
        );
        r
    }
}

/// Sets its flag when dropped, on return or unwinding alike.
struct SetOnDrop<'a>(&'a AtomicBool);

impl Drop for SetOnDrop<'_> {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Release);
    }
}

/// The partner of [`on_pool`]: runs the pool's pending jobs (the solve's section halves) as they
/// appear, and spins between them, until `done`. On the solve's own thread (it popped its partner
/// while waiting in a join) it returns at once: it must not block the frames below it.
fn partner(done: &AtomicBool, owner: &AtomicUsize) {
    if rayon::current_thread_index() == Some(owner.load(Ordering::Acquire)) {
        return;
    }
    let mut idle = 0u32;
    while !done.load(Ordering::Acquire) {
        match rayon::yield_now() {
            Some(rayon::Yield::Executed) => idle = 0,
            Some(rayon::Yield::Idle) => {
                idle = idle.wrapping_add(1);
                if idle % 64 == 0 {
                    // Lets another runnable task of a loaded machine have this core now and then.
                    std::thread::yield_now();
                } else {
                    std::hint::spin_loop();
                }
            }
            None => return,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A closure that panics with a partner running: the panic reaches the caller (the partner
    /// stops polling) instead of the process hanging.
    #[test]
    fn a_panic_with_a_partner_reaches_the_caller() {
        let result = std::panic::catch_unwind(|| {
            on_pool(PARTNER_CELLS, || {
                rayon::join(
                    || std::thread::sleep(std::time::Duration::from_millis(5)),
                    || (),
                );
                panic!("the solve failed");
            })
        });
        assert!(result.is_err());
    }

    /// The closure runs on a worker of the pool it is called from (or inline on one thread), and
    /// its result comes back.
    #[test]
    fn runs_on_a_worker_and_returns() {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            // From inside the pool: inline.
            for cells in [16, PARTNER_CELLS] {
                let inside =
                    pool.install(|| on_pool(cells, || rayon::current_thread_index().is_some()));
                assert!(inside);
            }
        }
        // From outside any pool (the test thread) with the global pool of ≥ 2 threads: a worker.
        // With a partner, the closure's own parallel sections run and the partner ends.
        for cells in [16, PARTNER_CELLS, 4 * PARTNER_MAX_CELLS] {
            let (worker, value) = on_pool(cells, || (rayon::current_thread_index(), 6 * 7));
            assert_eq!(value, 42);
            if rayon::current_num_threads() > 1 {
                assert!(worker.is_some());
            }
            let sum: u64 = on_pool(cells, || {
                use rayon::prelude::*;
                (0..100_000u64).into_par_iter().map(|k| k % 7).sum()
            });
            assert_eq!(sum, (0..100_000u64).map(|k| k % 7).sum());
        }
    }

    /// With the partner off a partner-sized solve still runs on a worker and returns its
    /// result (called through `on_pool_with`, so the process-wide switch stays on for the other
    /// tests of this binary, which exercise the partner); the switch reads back what was set.
    #[test]
    fn without_a_partner_a_solve_still_runs_on_a_worker() {
        use rayon::prelude::*;
        let sum = |partner_on| {
            on_pool_with(partner_on, PARTNER_CELLS, || {
                let s: u64 = (0..200_000u64).into_par_iter().map(|k| k * k % 1009).sum();
                (s, rayon::current_thread_index())
            })
        };
        let (with, _) = sum(true);
        let (without, worker) = sum(false);
        assert_eq!(with, (0..200_000u64).map(|k| k * k % 1009).sum::<u64>());
        assert_eq!(with, without);
        if rayon::current_num_threads() > 1 {
            assert!(worker.is_some());
        }
        set_partner(true);
        assert!(partner_enabled());
    }
}
