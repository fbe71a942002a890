//! Binary swap (Ma, Painter, Hansen, Krogh 1994), with folding for rank counts that are
//! not powers of two (Yu, Wang, Ma 2008 call the alternative 2-3 swap; IceT folds): the
//! first 2*(p - 2^m) positions pair up and the odd one sends its whole layer to the even
//! one, leaving 2^m active ranks; then, in m rounds, partners v and v xor 2^i swap halves
//! of their current span, each keeping and compositing one half. Every rank ends with
//! 1/2^m of the image, having sent S(1 - 1/2^m) bytes: the reduce-scatter lower bound.
//! Each round is a [`pairwise::swap`] and the fold a one-way [`pairwise::transfer`]:
//! dense spans go straight from the layer's memory in pipelined pieces into a reused
//! buffer, sparse ones as run lengths.

use super::pairwise::{self, Step};
use super::{
    split_span, ActiveRect, CompositeOptions, Layer, LayerRef, Order, Pixel, TAG_COMPOSITE,
};
use crate::comm::{Comm, CommError};
use std::ops::Range;

pub fn reduce<P: Pixel, C: Comm>(
    comm: &C,
    layer: Layer<P>,
    rect: &mut ActiveRect,
    opts: &CompositeOptions,
) -> Result<(Layer<P>, Range<usize>), CommError> {
    reduce_from(comm, layer, None, rect, opts)
}

/// [`reduce`] of a layer whose pixels are in `src` (the caller's memory, read in
/// place) when given, `layer` being working memory of the same size whose contents do
/// not matter: the first step (the fold, or the first swap) sends straight from `src`
/// and copies into `layer` only the span it keeps ([`pairwise::transfer_from`]); the
/// returned span of `layer` holds this rank's part of the composite.
pub fn reduce_from<P: Pixel, C: Comm>(
    comm: &C,
    mut layer: Layer<P>,
    mut src: Option<LayerRef<'_, P>>,
    rect: &mut ActiveRect,
    opts: &CompositeOptions,
) -> Result<(Layer<P>, Range<usize>), CommError> {
    let n = comm.size();
    let order = Order::new(n, opts.order.as_deref());
    let me = order.pos(comm.rank());
    let p = if n.is_power_of_two() {
        n
    } else {
        n.next_power_of_two() / 2
    };
    let extra = n - p;
    let fold_tag = TAG_COMPOSITE;
    // Folding: positions 2i+1 < 2*extra hand their layer to 2i.
    let v = if me < 2 * extra {
        let all = 0..layer.len();
        let fold = |sends, recvs, keep| Step {
            sends,
            recvs,
            keep,
            tag: fold_tag,
            op: opts.op,
            rle: opts.rle,
        };
        if me % 2 == 1 {
            let to = [(order.rank(me - 1), all)];
            pairwise::transfer_from(comm, &mut layer, src, rect, &fold(&to, &[], 0..0))?;
            return Ok((layer, 0..0));
        }
        let from = [(order.rank(me + 1), false)];
        pairwise::transfer_from(comm, &mut layer, src.take(), rect, &fold(&[], &from, all))?;
        me / 2
    } else {
        me - extra
    };
    let pos_of = |v: usize| if v < extra { 2 * v } else { v + extra };
    let mut span = 0..layer.len();
    let mut bit = 1;
    let mut round = 1;
    while bit < p {
        let pv = v ^ bit;
        let partner = order.rank(pos_of(pv));
        let halves = split_span(&span, 2);
        let (keep, give) = if v & bit == 0 {
            (halves[0].clone(), halves[1].clone())
        } else {
            (halves[1].clone(), halves[0].clone())
        };
        pairwise::swap_from(
            comm,
            partner,
            &mut layer,
            src.take(),
            rect,
            give,
            keep.clone(),
            TAG_COMPOSITE + round,
            opts.op,
            pv < v,
            opts.rle,
        )?;
        span = keep;
        bit <<= 1;
        round += 1;
    }
    if let Some(s) = src {
        // One rank: no step read the source.
        layer.color[span.clone()].copy_from_slice(&s.color[span.clone()]);
        layer.depth[span.clone()].copy_from_slice(&s.depth[span.clone()]);
    }
    Ok((layer, span))
}
