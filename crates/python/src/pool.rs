//! Memory for the image arrays `irradia.composite` returns, kept mapped from one call
//! to the next.
//!
//! A fresh 1280x720 RGBA8 image and its depth are 7.4 MB, and memory fresh from the
//! system is mapped one 4 KiB page at a time on its first write (about 1,800 page
//! faults, each clearing its page; ~1,250 with the 2 MiB page advice, which covers only
//! the aligned middle of a buffer). Measured in `bench/python/composite_numpy.py` at 2
//! ranks, the root's faults made a 3.5 ms composite 6.7 ms whenever the caller's own
//! numpy work between two calls had released the heap's top to the system (glibc
//! trims it once more than twice its mmap threshold is free).
//!
//! So the arrays' memory comes from this small pool: each array's base object is a
//! [`PooledBuffer`], which owns its buffer and, when Python frees the last array
//! viewing it, hands the buffer back here instead of to the allocator; the next call
//! asking for the same size takes it, already mapped. A buffer is reused only after
//! every array on it is gone (Python's reference count says so), so an array a caller
//! keeps is never written again. The pool keeps at most [`KEEP_BYTES`] (the oldest
//! buffers are freed first), so a process that composited once holds one image's
//! memory afterwards, no more.

use numpy::ndarray::{ArrayView, Dimension};
use pyo3::prelude::*;
use std::mem::MaybeUninit;
use std::ptr::NonNull;
use std::sync::Mutex;

/// The most memory the pool keeps for later calls (four 1920x1080 RGBA8 + depth
/// images, or a 4K float image).
pub const KEEP_BYTES: usize = 64 << 20;

/// A buffer of 8-byte words (aligned for every element type an array holds here).
type Words = Box<[MaybeUninit<u64>]>;

/// The buffers freed by Python, newest last.
static FREE: Mutex<Vec<Words>> = Mutex::new(Vec::new());

/// How many buffers the pool has allocated from the system, and how many times it
/// handed out a kept one (see [`_pool_stats`]).
static STATS: Mutex<(usize, usize)> = Mutex::new((0, 0));

/// The owner of one buffer: the base object of the numpy arrays made on it.
#[pyclass(frozen, module = "irradia._irradia")]
pub struct PooledBuffer {
    ptr: NonNull<MaybeUninit<u64>>,
    words: usize,
}

// SAFETY: the buffer is plain memory owned by this object alone (the arrays on it hold
// a reference to the object, not the memory); moving it between threads is harmless.
unsafe impl Send for PooledBuffer {}
// SAFETY: the object itself is never mutated after construction (frozen); the
// memory is written only through the numpy arrays, under Python's rules.
unsafe impl Sync for PooledBuffer {}

impl Drop for PooledBuffer {
    fn drop(&mut self) {
        // SAFETY: `ptr` and `words` came from `Box::into_raw` of a `Words` in `take`,
        // and this is the one place that rebuilds it.
        let words = unsafe {
            Box::from_raw(std::ptr::slice_from_raw_parts_mut(
                self.ptr.as_ptr(),
                self.words,
            ))
        };
        give_back(words);
    }
}

/// Returns a buffer to the pool, freeing the oldest ones beyond [`KEEP_BYTES`].
fn give_back(words: Words) {
    let mut free = FREE.lock().unwrap_or_else(|e| e.into_inner());
    free.push(words);
    let mut kept: usize = free.iter().map(|w| w.len() * 8).sum();
    while kept > KEEP_BYTES {
        kept -= free.remove(0).len() * 8;
    }
}

/// A buffer of `bytes` bytes (rounded up to whole words): the newest kept one of that
/// size, or a fresh one advised onto 2 MiB pages. Its contents are unspecified.
fn take(bytes: usize) -> Words {
    let words = bytes.div_ceil(8);
    let mut free = FREE.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(i) = free.iter().rposition(|w| w.len() == words) {
        STATS.lock().unwrap_or_else(|e| e.into_inner()).1 += 1;
        return free.remove(i);
    }
    drop(free);
    STATS.lock().unwrap_or_else(|e| e.into_inner()).0 += 1;
    let mut fresh: Words = Box::new_uninit_slice(words);
    irradia_core::pages::prefer_huge_pages_raw(fresh.as_mut_ptr(), words);
    fresh
}

/// A C-contiguous, writable numpy array of shape `dims` on pooled memory, left
/// uninitialised (as `numpy.empty`): the caller writes every element before Python
/// sees it.
///
/// # Safety
/// Every element must be written before the array is read (any bits are valid for
/// the plain number types used here, but the values would be a previous image's).
pub unsafe fn empty_array<'py, T: numpy::Element, D: Dimension>(
    py: Python<'py>,
    dims: D,
) -> PyResult<Bound<'py, numpy::PyArray<T, D>>> {
    debug_assert!(std::mem::align_of::<T>() <= 8);
    let len = dims.size();
    let words = take(len * std::mem::size_of::<T>());
    let n = words.len();
    let ptr =
        NonNull::new(Box::into_raw(words).cast::<MaybeUninit<u64>>()).expect("a box is never null");
    let owner = Bound::new(py, PooledBuffer { ptr, words: n })?;
    // SAFETY: `ptr` holds at least `len` elements of `T` (aligned: 8-byte words), it
    // stays valid while `owner` lives, and `owner` becomes the array's base object, so
    // it lives as long as the array; the view is never read before it is written
    // (this function's contract).
    let view = unsafe { ArrayView::from_shape_ptr(dims, ptr.as_ptr().cast::<T>().cast_const()) };
    // SAFETY: as above; the array is writable through numpy (the memory is owned by
    // `owner` and no Rust reference to it exists).
    Ok(unsafe { numpy::PyArray::borrow_from_array(&view, owner.into_any()) })
}

/// `(allocated, reused)`: how many buffers the pool has taken from the system and
/// how many times it handed out one kept from an earlier call (for tests).
#[pyfunction]
pub fn _pool_stats() -> (usize, usize) {
    *STATS.lock().unwrap_or_else(|e| e.into_inner())
}
