//! The one place a render's worker threads are chosen: rayon's global pool (one thread
//! per core), or a pool of its own with the asked-for count. Images never depend on it.

use crate::RenderError;

/// Runs `job` on `threads` worker threads (`None`: the global pool).
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    job: impl FnOnce() -> T + Send,
) -> Result<T, RenderError> {
    match threads {
        Some(n) => Ok(rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| RenderError::Threads(e.to_string()))?
            .install(job)),
        None => Ok(job()),
    }
}
