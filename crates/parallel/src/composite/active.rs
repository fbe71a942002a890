//! Finding active pixels fast: the run-length encoder and the pairwise swap's trimming
//! look for where a run of active (or inactive) pixels ends. Testing one pixel at a time
//! costs a branch per pixel; here whole blocks of [`BLOCK`] pixels are tested with a
//! branch-free fold (which vectorises) and skipped when uniform, and only the block where
//! the run ends is walked pixel by pixel. For depth compositing a pixel is active when
//! its depth is not +infinity (the bits of `FAR`); for "over", when its colour is not
//! clear.

use super::{Layer, Operator, Pixel, FAR};
use std::ops::Range;

/// Pixels tested together.
pub const BLOCK: usize = 16;

#[inline]
fn depth_active(d: f32) -> bool {
    d.to_bits() != FAR.to_bits()
}

/// Whether pixels `i..i + BLOCK` are all `active` (true) or all inactive (false).
#[inline]
fn block_uniform<P: Pixel>(layer: &Layer<P>, op: Operator, i: usize, active: bool) -> bool {
    match op {
        Operator::Depth => layer.depth[i..i + BLOCK]
            .iter()
            .fold(true, |all, &d| all & (depth_active(d) == active)),
        Operator::Over => layer.color[i..i + BLOCK]
            .iter()
            .fold(true, |all, c| all & (c.is_clear() != active)),
    }
}

#[inline]
fn is_active<P: Pixel>(layer: &Layer<P>, op: Operator, i: usize) -> bool {
    match op {
        Operator::Depth => depth_active(layer.depth[i]),
        Operator::Over => !layer.color[i].is_clear(),
    }
}

/// The first index in `from..end` whose activity is not `active` (or `end`): the end of
/// the run of `active` pixels starting at `from`.
pub fn run_end<P: Pixel>(
    layer: &Layer<P>,
    op: Operator,
    from: usize,
    end: usize,
    active: bool,
) -> usize {
    let mut i = from;
    while i + BLOCK <= end && block_uniform(layer, op, i, active) {
        i += BLOCK;
    }
    while i < end && is_active(layer, op, i) == active {
        i += 1;
    }
    i
}

/// The smallest range holding every active pixel of `span` (empty when none is).
pub fn trim<P: Pixel>(layer: &Layer<P>, op: Operator, span: &Range<usize>) -> Range<usize> {
    let a = run_end(layer, op, span.start, span.end, false);
    if a == span.end {
        return a..a;
    }
    let mut b = span.end;
    while b >= a + BLOCK && block_uniform(layer, op, b - BLOCK, false) {
        b -= BLOCK;
    }
    while !is_active(layer, op, b - 1) {
        b -= 1;
    }
    a..b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_and_trims_match_a_pixel_by_pixel_scan() {
        let mut l = Layer::<[u8; 4]>::new(97, 3);
        let n = l.len();
        // runs of every length from 1 to 40, alternating
        let (mut i, mut len, mut on) = (5, 1, true);
        while i < n - 7 {
            for j in i..(i + len).min(n - 7) {
                if on {
                    l.depth[j] = j as f32;
                    l.color[j] = [1, 2, 3, 255];
                }
            }
            i += len;
            len = len % 40 + 1;
            on = !on;
        }
        for op in [Operator::Depth, Operator::Over] {
            for from in 0..n {
                for active in [false, true] {
                    let slow = (from..n).find(|&k| op.active(&l, k) != active).unwrap_or(n);
                    assert_eq!(run_end(&l, op, from, n, active), slow);
                }
            }
            for s in [0..n, 3..n - 2, 5..6, 40..40, 0..5] {
                let first = s.clone().find(|&k| op.active(&l, k));
                let last = s.clone().rev().find(|&k| op.active(&l, k));
                let want = match (first, last) {
                    (Some(a), Some(b)) => a..b + 1,
                    _ => s.end..s.end,
                };
                assert_eq!(trim(&l, op, &s), want, "{op:?} {s:?}");
            }
        }
    }
}
