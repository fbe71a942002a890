//! Per-thread span buffers, so that intersecting a CSG tree allocates nothing per ray:
//! each node borrows three buffers from a thread-local pool for the duration of one
//! call and returns them (nested nodes borrow their own), keeping their capacity.

use crate::shape::Span;
use std::cell::RefCell;

thread_local! {
    static POOL: RefCell<Vec<Buffers>> = const { RefCell::new(Vec::new()) };
}

/// Three empty buffers: `(result, operand, temporary)`.
#[derive(Default)]
pub struct Buffers {
    pub acc: Vec<Span>,
    pub operand: Vec<Span>,
    pub tmp: Vec<Span>,
}

/// Runs `f` with three cleared buffers from this thread's pool.
#[inline]
pub fn with_buffers<R>(f: impl FnOnce(&mut Buffers) -> R) -> R {
    let mut bufs = POOL.with(|p| p.borrow_mut().pop().unwrap_or_default());
    bufs.acc.clear();
    bufs.operand.clear();
    bufs.tmp.clear();
    let r = f(&mut bufs);
    POOL.with(|p| p.borrow_mut().push(bufs));
    r
}
