//! Tree compositing (the lecture's "composite in pairs, send color and depth buffers,
//! each time half the processors become idle"): in round i, position v with bit i set
//! sends its whole layer to v - 2^i and drops out; after ceil(log2 p) rounds position 0
//! holds the image. Works for any p (a missing partner just skips the round). Each
//! transfer is a one-way [`pairwise::transfer`] (dense in place or run lengths).

use super::pairwise::{self, Step};
use super::{ActiveRect, CompositeOptions, Layer, Order, Pixel, TAG_COMPOSITE};
use crate::comm::{Comm, CommError};
use std::ops::Range;

pub fn reduce<P: Pixel, C: Comm>(
    comm: &C,
    mut layer: Layer<P>,
    rect: &mut ActiveRect,
    opts: &CompositeOptions,
) -> Result<(Layer<P>, Range<usize>), CommError> {
    let n = comm.size();
    let order = Order::new(n, opts.order.as_deref());
    let me = order.pos(comm.rank());
    let full = 0..layer.len();
    let mut bit = 1;
    let mut round = 0;
    while bit < n {
        let step = |sends, recvs, keep| Step {
            sends,
            recvs,
            keep,
            tag: TAG_COMPOSITE + round,
            op: opts.op,
            rle: opts.rle,
        };
        if me.is_multiple_of(2 * bit) {
            if me + bit < n {
                let from = [(order.rank(me + bit), false)];
                let s = step(&[], &from, full.clone());
                pairwise::transfer(comm, &mut layer, rect, &s)?;
            }
        } else {
            let to = [(order.rank(me - bit), full.clone())];
            pairwise::transfer(comm, &mut layer, rect, &step(&to, &[], 0..0))?;
            return Ok((layer, 0..0));
        }
        bit <<= 1;
        round += 1;
    }
    Ok((layer, full))
}
