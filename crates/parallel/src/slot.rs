//! Where a rank's pool leaves the chunk it computed, waking the rank's main thread at
//! once. The main thread of an MPI rank talks (MPI calls stay on it) while the rank's
//! pool renders or links; it used to sleep a fixed poll interval between looks, which
//! left the pool idle up to that interval after every chunk (at 1 ms, half the time of
//! a 1-sample pass of 32x32 tiles). Waiting on a condition variable with the poll as its
//! timeout keeps the look at other ranks' messages and ends the wait the moment the
//! chunk is there.

use std::sync::{Condvar, Mutex};
use std::time::Duration;

/// A value handed from a pool task to the thread that waits for it.
pub struct Slot<T> {
    value: Mutex<Option<T>>,
    ready: Condvar,
}

impl<T> Slot<T> {
    pub fn new() -> Self {
        Slot {
            value: Mutex::new(None),
            ready: Condvar::new(),
        }
    }

    pub fn put(&self, v: T) {
        *self.value.lock().unwrap_or_else(|e| e.into_inner()) = Some(v);
        self.ready.notify_all();
    }

    pub fn take(&self) -> Option<T> {
        self.value.lock().unwrap_or_else(|e| e.into_inner()).take()
    }

    /// Waits until a value is there or `timeout` has passed.
    pub fn wait(&self, timeout: Duration) {
        let g = self.value.lock().unwrap_or_else(|e| e.into_inner());
        if g.is_none() {
            let _ = self.ready.wait_timeout(g, timeout);
        }
    }
}

impl<T> Default for Slot<T> {
    fn default() -> Self {
        Self::new()
    }
}
