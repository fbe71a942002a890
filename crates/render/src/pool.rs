//! The one place a render's worker threads are chosen: a pool of one thread per core
//! (made once, shared by every render that asks for no count), or a pool of its own
//! with the asked-for count. Images never depend on it.

use crate::RenderError;
use std::sync::OnceLock;

/// Each worker's stack: 16 MiB, reserved address space that costs memory only where it
/// is touched. An optimised build's path kernel needs a small part of rayon's default
/// 2 MiB; an unoptimised one (a `cargo build` without `--release`, the Python
/// package's test build) keeps the locals of everything inlined into the kernel in one
/// frame, and such a frame has outgrown 2 MiB before (`path::wide::kernel`).
pub const WORKER_STACK: usize = 16 << 20;

/// A pool of `threads` workers (0: one per core, or `RAYON_NUM_THREADS`).
fn pool(threads: usize) -> Result<rayon::ThreadPool, String> {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .stack_size(WORKER_STACK)
        .build()
        .map_err(|e| e.to_string())
}

/// Runs `job` on `threads` worker threads (`None`: the shared pool, one thread per
/// core).
pub fn with_threads<T: Send>(
    threads: Option<usize>,
    job: impl FnOnce() -> T + Send,
) -> Result<T, RenderError> {
    match threads {
        Some(n) => Ok(pool(n.max(1)).map_err(RenderError::Threads)?.install(job)),
        None => {
            static SHARED: OnceLock<Result<rayon::ThreadPool, String>> = OnceLock::new();
            match SHARED.get_or_init(|| pool(0)) {
                Ok(shared) => Ok(shared.install(job)),
                Err(e) => Err(RenderError::Threads(e.clone())),
            }
        }
    }
}
