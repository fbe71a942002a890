//! Radix-k compositing (Peterka, Goodell, Ross, Shen, Thakur 2009, "A configurable
//! algorithm for parallel image-compositing applications"): the p ranks are factored as
//! p = k1 * k2 * ...; in round i, groups of k_i ranks (those differing only in the i-th
//! mixed-radix digit of their position) split their current span into k_i parts and
//! direct-send them, each member keeping one part. k = 2 everywhere is binary swap; one
//! factor p is direct send. Any p works: a prime factor larger than k stays a round of
//! its own.

use super::pairwise::{self, Step};
use super::{split_span, ActiveRect, CompositeOptions, Layer, Order, Pixel, TAG_COMPOSITE};
use crate::comm::{Comm, CommError};
use std::ops::Range;

/// Factors `n` into round sizes of at most `k` where the primes allow (largest primes
/// first, each merged into the first factor it fits).
pub fn factors(n: usize, k: usize) -> Vec<usize> {
    let mut primes = Vec::new();
    let mut m = n;
    let mut d = 2;
    while m > 1 {
        while m.is_multiple_of(d) {
            primes.push(d);
            m /= d;
        }
        d += 1;
        if d * d > m && m > 1 {
            primes.push(m);
            break;
        }
    }
    primes.sort_unstable_by(|a, b| b.cmp(a));
    let mut out: Vec<usize> = Vec::new();
    for p in primes {
        match out.iter_mut().find(|f| **f * p <= k) {
            Some(f) => *f *= p,
            None => out.push(p),
        }
    }
    out
}

pub fn reduce<P: Pixel, C: Comm>(
    comm: &C,
    mut layer: Layer<P>,
    rect: &mut ActiveRect,
    opts: &CompositeOptions,
    k: usize,
) -> Result<(Layer<P>, Range<usize>), CommError> {
    let n = comm.size();
    let order = Order::new(n, opts.order.as_deref());
    let me = order.pos(comm.rank());
    let mut span = 0..layer.len();
    let mut stride = 1;
    for (round, &f) in factors(n, k.max(2)).iter().enumerate() {
        let digit = (me / stride) % f;
        let base = me - digit * stride;
        let members: Vec<usize> = (0..f).map(|d| base + d * stride).collect();
        span = group_round(
            comm,
            &order,
            &mut layer,
            rect,
            span,
            &members,
            digit,
            TAG_COMPOSITE + round as u32,
            opts,
        )?;
        stride *= f;
    }
    Ok((layer, span))
}

/// One direct-send round among `members` (positions, front first; this rank is
/// `members[me]`): the span is cut into one part per member, each part is sent to its
/// owner, and the owner composites what it receives (one [`pairwise::transfer`]: dense
/// parts in place, sparse ones as run lengths, every part posted at once). Sources are
/// composited in front of the accumulated image nearest first (`me - 1` down to 0),
/// then behind it nearest first (`me + 1` up): with the tie rule of [`super::depth`]
/// that is the serial z-buffer's result bit for bit, and for "over" the visibility
/// order. Returns the part kept; `rect` is widened by the sources' rectangles.
#[allow(clippy::too_many_arguments)]
pub fn group_round<P: Pixel, C: Comm>(
    comm: &C,
    order: &Order,
    layer: &mut Layer<P>,
    rect: &mut ActiveRect,
    span: Range<usize>,
    members: &[usize],
    me: usize,
    tag: u32,
    opts: &CompositeOptions,
) -> Result<Range<usize>, CommError> {
    let f = members.len();
    let parts = split_span(&span, f);
    let sends: Vec<(usize, Range<usize>)> = (0..f)
        .filter(|&d| d != me)
        .map(|d| (order.rank(members[d]), parts[d].clone()))
        .collect();
    let fronts = (0..me).rev().map(|d| (order.rank(members[d]), true));
    let backs = (me + 1..f).map(|d| (order.rank(members[d]), false));
    let recvs: Vec<(usize, bool)> = fronts.chain(backs).collect();
    let step = Step {
        sends: &sends,
        recvs: &recvs,
        keep: parts[me].clone(),
        tag,
        op: opts.op,
        rle: opts.rle,
    };
    pairwise::transfer(comm, layer, rect, &step)?;
    Ok(parts[me].clone())
}

#[cfg(test)]
mod tests {
    use super::factors;

    #[test]
    fn factors_multiply_back_and_respect_k() {
        for n in 1..=64 {
            for k in 2..=8 {
                let f = factors(n, k);
                assert_eq!(f.iter().product::<usize>(), n.max(1), "n={n} k={k}");
            }
        }
        assert_eq!(factors(16, 4), vec![4, 4]);
        assert_eq!(factors(7, 4), vec![7]);
        assert_eq!(factors(1, 4), Vec::<usize>::new());
    }
}
