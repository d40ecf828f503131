//! Where a solve runs: on one of rayon's worker threads (docs/performance.md, "The solve on the
//! pool's threads").
//!
//! A parallel section (`par_iter`, `rayon::join`) started from a thread **outside** the pool is
//! injected into the pool's queue, and the calling thread blocks on a lock until a worker has run
//! it: every section costs a hand-off to a (possibly sleeping) worker and a wake-up of the caller.
//! A solve at 128² runs ≈ 12–15 such sections per iteration of ≈ 0.5–1 ms, so from the main
//! thread the second thread hardly paid. Started **on** a worker, a section is pushed to that
//! worker's own deque and the other worker (spinning between sections, or woken once) steals
//! half of it; the caller works on the other half and never sleeps.
//!
//! [`on_pool`] runs a whole solve on a worker: one hand-off per solve instead of one per section.

/// `f()` run on one of the global rayon pool's worker threads (the caller waits): directly when
/// the caller already is one, or when the pool has one thread (nothing runs in parallel then).
/// The result is the same bit for bit as `f()` on the calling thread; only where it runs differs.
pub fn on_pool<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() || rayon::current_num_threads() <= 1 {
        f()
    } else {
        rayon::scope(|_| f())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
            let inside = pool.install(|| on_pool(|| rayon::current_thread_index().is_some()));
            assert!(inside);
        }
        // From outside any pool (the test thread) with the global pool of ≥ 2 threads: a worker.
        let (worker, value) = on_pool(|| (rayon::current_thread_index(), 6 * 7));
        assert_eq!(value, 42);
        if rayon::current_num_threads() > 1 {
            assert!(worker.is_some());
        }
    }
}
