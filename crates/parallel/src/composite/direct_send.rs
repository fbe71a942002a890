//! Direct send (Hsu 1993; Neumann 1993): the image is cut into p parts and every rank
//! sends each other rank the part it owns, in one round of p(p-1) messages. It is radix-k
//! with a single factor p, and shares its round with [`super::radix_k`].

use super::TAG_COMPOSITE;
use super::{radix_k::group_round, ActiveRect, CompositeOptions, Layer, Order, Pixel};
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
    let members: Vec<usize> = (0..n).collect();
    let span = 0..layer.len();
    let span = group_round(
        comm,
        &order,
        &mut layer,
        rect,
        span,
        &members,
        me,
        TAG_COMPOSITE,
        opts,
    )?;
    Ok((layer, span))
}
