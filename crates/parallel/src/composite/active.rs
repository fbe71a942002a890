//! Finding active pixels fast: the run-length encoder and the pairwise swap's trimming
//! look for where a run of active (or inactive) pixels ends. Testing one pixel at a time
//! costs a branch per pixel; here whole blocks are tested at once and skipped when
//! uniform, and only the block where the run ends is walked pixel by pixel. For depth
//! compositing a pixel is active when its depth is not +infinity (the bits of `FAR`):
//! a block of [`DEPTH_BLOCK`] depths is tested by counting the infinite ones, a
//! reduction that compiles to vector compares and adds (with AVX2 where the CPU has
//! it). For "over" a pixel is active when its colour is not clear; blocks of
//! [`BLOCK`] colours are folded the same way.

use super::{Layer, Operator, Pixel, FAR};
use std::ops::Range;

/// Colours tested together ("over").
pub const BLOCK: usize = 16;
/// Depths tested together (depth compositing).
pub const DEPTH_BLOCK: usize = 64;

const FAR_BITS: u32 = FAR.to_bits();

/// How many of `d` are at infinity (background).
#[inline(always)]
fn far_count(d: &[f32]) -> u32 {
    d.iter()
        .fold(0u32, |n, &x| n + (x.to_bits() == FAR_BITS) as u32)
}

#[inline(always)]
fn depth_run_end_impl(d: &[f32], from: usize, end: usize, active: bool) -> usize {
    let uniform = if active { 0 } else { DEPTH_BLOCK as u32 };
    let mut i = from;
    while i + DEPTH_BLOCK <= end && far_count(&d[i..i + DEPTH_BLOCK]) == uniform {
        i += DEPTH_BLOCK;
    }
    while i < end && (d[i].to_bits() != FAR_BITS) == active {
        i += 1;
    }
    i
}

#[inline(always)]
fn depth_trim_back_impl(d: &[f32], a: usize, end: usize) -> usize {
    let mut b = end;
    while b >= a + DEPTH_BLOCK && far_count(&d[b - DEPTH_BLOCK..b]) == DEPTH_BLOCK as u32 {
        b -= DEPTH_BLOCK;
    }
    while b > a && d[b - 1].to_bits() == FAR_BITS {
        b -= 1;
    }
    b
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn depth_run_end_avx2(d: &[f32], from: usize, end: usize, active: bool) -> usize {
    depth_run_end_impl(d, from, end, active)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn depth_trim_back_avx2(d: &[f32], a: usize, end: usize) -> usize {
    depth_trim_back_impl(d, a, end)
}

fn depth_run_end(d: &[f32], from: usize, end: usize, active: bool) -> usize {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above).
        return unsafe { depth_run_end_avx2(d, from, end, active) };
    }
    depth_run_end_impl(d, from, end, active)
}

fn depth_trim_back(d: &[f32], a: usize, end: usize) -> usize {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above).
        return unsafe { depth_trim_back_avx2(d, a, end) };
    }
    depth_trim_back_impl(d, a, end)
}

/// Whether colours `i..i + BLOCK` are all active (true) or all clear (false).
#[inline]
fn colors_uniform<P: Pixel>(c: &[P], i: usize, active: bool) -> bool {
    c[i..i + BLOCK]
        .iter()
        .fold(true, |all, c| all & (c.is_clear() != active))
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
    match op {
        Operator::Depth => depth_run_end(&layer.depth, from, end, active),
        Operator::Over => {
            let c = &layer.color;
            let mut i = from;
            while i + BLOCK <= end && colors_uniform(c, i, active) {
                i += BLOCK;
            }
            while i < end && c[i].is_clear() != active {
                i += 1;
            }
            i
        }
    }
}

/// The smallest range holding every active pixel of `span` (empty when none is).
pub fn trim<P: Pixel>(layer: &Layer<P>, op: Operator, span: &Range<usize>) -> Range<usize> {
    let a = run_end(layer, op, span.start, span.end, false);
    if a == span.end {
        return a..a;
    }
    let b = match op {
        Operator::Depth => depth_trim_back(&layer.depth, a, span.end),
        Operator::Over => {
            let c = &layer.color;
            let mut b = span.end;
            while b >= a + BLOCK && colors_uniform(c, b - BLOCK, false) {
                b -= BLOCK;
            }
            while c[b - 1].is_clear() {
                b -= 1;
            }
            b
        }
    };
    a..b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_and_trims_match_a_pixel_by_pixel_scan() {
        let mut l = Layer::<[u8; 4]>::new(97, 5);
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
            len = len % 150 + 1;
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
