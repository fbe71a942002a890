//! The one place a render's worker threads are chosen: rayon's global pool (one thread
//! per core), or a pool of its own with the asked-for count. Images never depend on it.
//!
//! Pools of a given count are kept for the next call with the same count (the last
//! [`KEPT`] counts asked for), so that repeated calls (`Scene.cast_rays` on small
//! batches from Python, one render after another) do not start and stop their threads
//! each time: building a pool of 2 threads costs about 0.1 ms, as much as casting
//! a thousand rays.

use crate::RenderError;
use rayon::ThreadPool;
use std::sync::{Arc, Mutex};

/// How many pools (thread counts) are kept.
const KEPT: usize = 4;

/// Pools by thread count, the most recently used last.
type Pools = Mutex<Vec<(usize, Arc<ThreadPool>)>>;

static POOLS: Pools = Mutex::new(Vec::new());

/// Runs `job` on `threads` worker threads (`None`: the global pool).
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    job: impl FnOnce() -> T + Send,
) -> Result<T, RenderError> {
    match threads {
        Some(n) => Ok(pool(&POOLS, n.max(1))?.install(job)),
        None => Ok(job()),
    }
}

/// The pool of `n` threads in `pools`, built (and the least recently used one dropped
/// beyond [`KEPT`]) when there is none. A pool dropped while a job still runs on it
/// lives until that job ends (the job's caller holds it).
fn pool(pools: &Pools, n: usize) -> Result<Arc<ThreadPool>, RenderError> {
    let mut pools = pools.lock().unwrap_or_else(|e| e.into_inner());
    let p = match pools.iter().position(|(k, _)| *k == n) {
        Some(i) => pools.remove(i).1,
        None => Arc::new(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| RenderError::Threads(e.to_string()))?,
        ),
    };
    if pools.len() >= KEPT {
        pools.remove(0);
    }
    pools.push((n, Arc::clone(&p)));
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pools_are_kept_per_count() {
        let pools: Pools = Mutex::new(Vec::new());
        let two = pool(&pools, 2).unwrap();
        assert_eq!(two.current_num_threads(), 2);
        assert!(Arc::ptr_eq(&two, &pool(&pools, 2).unwrap()));
        let three = pool(&pools, 3).unwrap();
        assert_eq!(three.current_num_threads(), 3);
        assert!(Arc::ptr_eq(&two, &pool(&pools, 2).unwrap()));
        // Beyond KEPT counts the least recently used goes: 3 here, not 2.
        for n in 4..4 + KEPT - 1 {
            pool(&pools, n).unwrap();
        }
        assert!(Arc::ptr_eq(&two, &pool(&pools, 2).unwrap()));
        assert!(!Arc::ptr_eq(&three, &pool(&pools, 3).unwrap()));
        assert_eq!(pools.lock().unwrap().len(), KEPT);
    }

    #[test]
    fn jobs_run_on_the_asked_count() {
        for n in [1, 2, 3, 2] {
            assert_eq!(
                with_threads(Some(n), rayon::current_num_threads).unwrap(),
                n
            );
        }
        assert_eq!(
            with_threads(Some(0), rayon::current_num_threads).unwrap(),
            1
        );
    }
}
