//! The thread pool the C3D format crate and the c3dfix library run their parallel work in, owned per
//! process so that a forked process works.
//!
//! rayon's global pool is made once per process and never rebuilt. `fork()` copies the memory
//! of a process but only the thread that called it: in the child the global pool's workers do
//! not exist, and the first parallel iterator waits for them forever. Python's
//! `multiprocessing` forks by default on Linux (before Python 3.14), so a parent that read one
//! file and then maps over files with a `Pool` would hang every worker.
//!
//! So parallel work never touches the global pool: [`install`] runs it in a pool created for
//! the current process id and built anew when the id changes (a forked child). The parent's
//! pool is left in the child's memory untouched, as fork left it. A caller already running on
//! a rayon worker (the command's `batch`, which sizes its own pool by `--jobs`) keeps its pool.

use std::sync::atomic::{AtomicPtr, Ordering};

/// A pool and the process it was built in.
struct Owned {
    pid: u32,
    /// `None` when the pool could not be built (no threads to be had): work then runs on the
    /// caller's thread in rayon's global pool, as it would without this module.
    pool: Option<rayon::ThreadPool>,
}

/// The current process's pool. Each value is leaked on purpose: a pool that belonged to the
/// parent must never be dropped in a child (dropping it signals threads that are not there),
/// and one leaked pool per fork is the cost.
static POOL: AtomicPtr<Owned> = AtomicPtr::new(std::ptr::null_mut());

/// The pool of this process, built on first use and again after a fork. Lock-free, so that a
/// fork taken while another thread was here cannot leave a lock held in the child.
fn current() -> &'static Owned {
    let pid = std::process::id();
    loop {
        let seen = POOL.load(Ordering::Acquire);
        // SAFETY: every non-null pointer in POOL comes from `Box::leak` below and is never
        // freed, so it is valid for 'static.
        if let Some(o) = unsafe { seen.as_ref() } {
            if o.pid == pid {
                return o;
            }
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .thread_name(|i| format!("c3dfix-{i}"))
            .build()
            .ok();
        let fresh: &'static mut Owned = Box::leak(Box::new(Owned { pid, pool }));
        if POOL
            .compare_exchange(seen, fresh, Ordering::AcqRel, Ordering::Acquire)
            .is_ok()
        {
            return fresh;
        }
        // Another thread published a pool first: use that one. Ours was never shared, and its
        // threads exist in this process, so dropping it is sound.
        // SAFETY: `fresh` came from Box::leak above and was not published.
        drop(unsafe { Box::from_raw(fresh as *mut Owned) });
    }
}

/// Run `f` in this process's pool (see the module's note): every parallel iterator inside it
/// uses that pool. On a rayon worker thread already, `f` runs where it is.
pub fn install<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    if rayon::current_thread_index().is_some() {
        return f();
    }
    match &current().pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rayon::prelude::*;

    #[test]
    fn work_runs_in_the_process_pool_and_nests() {
        let names: Vec<String> = install(|| {
            (0..64)
                .into_par_iter()
                .map(|_| std::thread::current().name().unwrap_or("").to_string())
                .collect()
        });
        assert!(names.iter().all(|n| n.starts_with("c3dfix-")), "{names:?}");
        // Nested: already on a worker, so no second install.
        let sum: u64 = install(|| (0..100u64).into_par_iter().map(|i| install(|| i)).sum());
        assert_eq!(sum, 4950);
    }
}
