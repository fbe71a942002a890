//! The private communicator `irradia.composite` runs on: a duplicate of the caller's
//! mpi4py communicator (so that Irradia's messages never match the caller's), made by
//! the first composite over that communicator and cached on it as an MPI attribute,
//! the mechanism MPI provides for libraries to keep a private communicator with a
//! user's (MPI-4.0, section 7.7 "Caching"; the "inner communicator" of PETSc, IceT's
//! context). Later composites over the same communicator reuse the duplicate.
//!
//! Why: `MPI_Comm_dup` is collective and not cheap. OpenMPI 4 agrees on a new context
//! id with nonblocking allreduces (libnbc: `NBC_Progress`, `opal_progress`) in two or
//! more rounds, i.e. several round trips between every pair of ranks before a single
//! pixel moves; with more processes than free cores each round trip waits for the
//! partner to be scheduled. A duplicate per call made a 2-rank composite of 1280x720
//! pay those round trips every frame.
//!
//! Lifetime. The duplicate is freed when the caller's communicator is freed (the
//! attribute's delete callback runs inside the caller's `Comm.Free()`), or at the very
//! start of `MPI_Finalize` for communicators that live until then (`MPI_COMM_WORLD`):
//! a second attribute, on `MPI_COMM_SELF`, whose delete callback MPI runs first thing
//! in `MPI_Finalize` while every other part of MPI still works (MPI-4.0, section
//! 11.2.4). A `Comm.Dup()` of the caller's communicator does not inherit the cached
//! duplicate (the copy callback declines).
//!
//! Like every collective, composites over one communicator must be called in the same
//! order on every rank and not from two threads at once; the cached duplicate adds no
//! rule to that.

use mpi::ffi;
use std::os::raw::{c_int, c_void};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

/// The keyval of the cached duplicate (`None` until the first composite) and the
/// duplicates not freed yet (addresses of their boxed handles, which the attributes
/// hold).
struct Cache {
    keyval: Option<c_int>,
    live: Vec<usize>,
}

static CACHE: Mutex<Cache> = Mutex::new(Cache {
    keyval: None,
    live: Vec::new(),
});

/// Duplicates made so far in this process ([`duplicates`]).
static MADE: AtomicUsize = AtomicUsize::new(0);

const MPI_SUCCESS: c_int = 0;

/// How many duplicates this process has made (for the tests: a second composite over
/// the same communicator makes none).
pub fn duplicates() -> usize {
    MADE.load(Ordering::Relaxed)
}

fn cache() -> std::sync::MutexGuard<'static, Cache> {
    CACHE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Copy callback: a duplicate of the caller's communicator does not inherit ours.
unsafe extern "C" fn decline_copy(
    _comm: ffi::MPI_Comm,
    _keyval: c_int,
    _extra: *mut c_void,
    _value_in: *mut c_void,
    _value_out: *mut c_void,
    flag: *mut c_int,
) -> c_int {
    *flag = 0;
    MPI_SUCCESS
}

/// Delete callback of the attribute on the caller's communicator (its `Free()`, or
/// OpenMPI's late clean-up of `MPI_COMM_WORLD`): frees the duplicate unless
/// [`at_finalize`] did, and its box.
unsafe extern "C" fn free_duplicate(
    _comm: ffi::MPI_Comm,
    _keyval: c_int,
    value: *mut c_void,
    _extra: *mut c_void,
) -> c_int {
    let boxed = Box::from_raw(value as *mut ffi::MPI_Comm);
    let still_live = {
        let mut c = cache();
        match c.live.iter().position(|&p| p == value as usize) {
            Some(i) => {
                c.live.swap_remove(i);
                true
            }
            None => false,
        }
    };
    if still_live {
        let mut dup = *boxed;
        ffi::MPI_Comm_free(&mut dup);
    }
    MPI_SUCCESS
}

/// Delete callback of the attribute on `MPI_COMM_SELF`, run first thing in
/// `MPI_Finalize`: frees every duplicate still live (their boxes stay with the
/// attributes, which [`free_duplicate`] frees if MPI ever deletes them).
unsafe extern "C" fn at_finalize(
    _comm: ffi::MPI_Comm,
    _keyval: c_int,
    _value: *mut c_void,
    _extra: *mut c_void,
) -> c_int {
    let live = std::mem::take(&mut cache().live);
    for p in live {
        let mut dup = *(p as *const ffi::MPI_Comm);
        ffi::MPI_Comm_free(&mut dup);
    }
    MPI_SUCCESS
}

/// The keyval, made (with the finalize hook on `MPI_COMM_SELF`) on first use.
unsafe fn keyval(c: &mut Cache) -> c_int {
    if let Some(k) = c.keyval {
        return k;
    }
    let mut k = 0;
    ffi::MPI_Comm_create_keyval(
        Some(decline_copy),
        Some(free_duplicate),
        &mut k,
        std::ptr::null_mut(),
    );
    let mut hook = 0;
    ffi::MPI_Comm_create_keyval(
        Some(decline_copy),
        Some(at_finalize),
        &mut hook,
        std::ptr::null_mut(),
    );
    ffi::MPI_Comm_set_attr(ffi::RSMPI_COMM_SELF, hook, std::ptr::null_mut());
    c.keyval = Some(k);
    k
}

/// The private duplicate of `comm`: the cached one, or (collectively, on the first
/// composite over `comm`) a new `MPI_Comm_dup` cached on `comm`. Returns the handle and
/// whether it was just made. The caller must not free it.
///
/// # Safety
/// `comm` must be a valid intra-communicator of an initialised MPI (not
/// `MPI_COMM_NULL`), and every rank of it must call this together, in the same order
/// as its other collectives.
pub unsafe fn private_comm(comm: ffi::MPI_Comm) -> (ffi::MPI_Comm, bool) {
    let k = keyval(&mut cache());
    let mut value: *mut c_void = std::ptr::null_mut();
    let mut flag: c_int = 0;
    ffi::MPI_Comm_get_attr(comm, k, (&mut value as *mut *mut c_void).cast(), &mut flag);
    if flag != 0 && !value.is_null() {
        return (*(value as *const ffi::MPI_Comm), false);
    }
    let mut dup = std::mem::MaybeUninit::<ffi::MPI_Comm>::uninit();
    ffi::MPI_Comm_dup(comm, dup.as_mut_ptr());
    let dup = dup.assume_init();
    MADE.fetch_add(1, Ordering::Relaxed);
    let boxed = Box::into_raw(Box::new(dup));
    cache().live.push(boxed as usize);
    ffi::MPI_Comm_set_attr(comm, k, boxed.cast());
    (dup, true)
}
