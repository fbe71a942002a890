//! Finding active pixels fast: the run-length encoder and the pairwise exchange's trimming
//! look for where a run of active (or inactive) pixels ends.
//!
//! * Depth compositing (a pixel is active when its depth is not +infinity, the bits of
//!   `FAR`): 32 depths are compared at once with AVX2 (`vpcmpeqd`), the four 8-lane
//!   results packed into one 32-bit mask with `vmovmskps`, and the end of the run is the
//!   mask's first set bit (`trailing_zeros`): no branch per pixel, and a uniform block
//!   costs one test. The portable fallback builds the same masks lane by lane.
//! * "Over" (active when the colour is not clear): blocks of [`BLOCK`] colours are folded
//!   and skipped when uniform, and the block where the run ends is walked pixel by pixel.
//! * [`ActiveRect`]: the screen rectangle that holds every active pixel of a layer, as a
//!   renderer knows it from its projected geometry bounds (IceT's `icetBoundingBox`,
//!   Moreland et al. 2011, "An Image Compositing Solution at Scale"). With it, rows and
//!   columns outside the rectangle are skipped without reading a single depth, so the
//!   cost of finding runs scales with the rectangle, not the screen.

use super::{Layer, LayerRef, Operator, Pixel, FAR};
use std::ops::Range;

/// Colours tested together ("over").
pub const BLOCK: usize = 16;

const FAR_BITS: u32 = FAR.to_bits();

/// A screen rectangle `x0..x1` by `y0..y1` (pixels, half-open) outside which every pixel
/// of a layer is inactive (background). A promise made by whoever rendered the layer:
/// pixels outside it are never looked at, so a rectangle that is too small loses them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ActiveRect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl ActiveRect {
    /// The whole screen (no knowledge).
    pub fn full(width: u32, height: u32) -> Self {
        Self {
            x0: 0,
            y0: 0,
            x1: width,
            y1: height,
        }
    }

    /// The empty rectangle.
    pub const EMPTY: Self = Self {
        x0: 0,
        y0: 0,
        x1: 0,
        y1: 0,
    };

    pub fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.y0 >= self.y1
    }

    /// The smallest rectangle holding both.
    pub fn union(&self, o: &Self) -> Self {
        if self.is_empty() {
            return *o;
        }
        if o.is_empty() {
            return *self;
        }
        Self {
            x0: self.x0.min(o.x0),
            y0: self.y0.min(o.y0),
            x1: self.x1.max(o.x1),
            y1: self.y1.max(o.y1),
        }
    }

    /// Whether it lies on a `width` x `height` screen.
    pub fn fits(&self, width: u32, height: u32) -> bool {
        self.x0 <= self.x1 && self.y0 <= self.y1 && self.x1 <= width && self.y1 <= height
    }

    /// The tightest rectangle of `layer`'s active pixels, found by scanning (for tests
    /// and for renderers that do not track their bounds).
    pub fn of_layer<P: Pixel>(layer: &Layer<P>, op: Operator) -> Self {
        let w = layer.width as usize;
        let mut r = Self::EMPTY;
        for y in 0..layer.height as usize {
            let row = y * w..(y + 1) * w;
            let t = trim(layer, op, &row);
            if !t.is_empty() {
                let line = Self {
                    x0: (t.start - row.start) as u32,
                    x1: (t.end - row.start) as u32,
                    y0: y as u32,
                    y1: y as u32 + 1,
                };
                r = r.union(&line);
            }
        }
        r
    }

    /// The part of `span` (pixel indices, row-major) between the rectangle's first and
    /// last pixel: the only place an active pixel can be.
    pub fn clip(&self, width: u32, span: &Range<usize>) -> Range<usize> {
        if self.is_empty() {
            return span.start..span.start;
        }
        let w = width as usize;
        let first = self.y0 as usize * w + self.x0 as usize;
        let last = (self.y1 as usize - 1) * w + self.x1 as usize;
        let a = span.start.max(first);
        let b = span.end.min(last);
        if a < b {
            a..b
        } else {
            span.start..span.start
        }
    }

    /// Whether the rectangle spans whole rows (then runs may cross row ends).
    fn full_width(&self, width: u32) -> bool {
        self.x0 == 0 && self.x1 == width
    }
}

/// Bit k set when `d[i + k]` is background, for k in 0..32 (`i + 32 <= d.len()`).
#[inline(always)]
fn far_mask32_portable(d: &[f32], i: usize) -> u32 {
    let mut m = 0u32;
    for (k, x) in d[i..i + 32].iter().enumerate() {
        m |= ((x.to_bits() == FAR_BITS) as u32) << k;
    }
    m
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn far_mask32_avx2(d: &[f32], i: usize) -> u32 {
    use std::arch::x86_64::*;
    debug_assert!(i + 32 <= d.len());
    let far = _mm256_set1_epi32(FAR_BITS as i32);
    let p = d.as_ptr().add(i) as *const __m256i;
    let m = |k: usize| {
        let v = _mm256_loadu_si256(p.add(k));
        _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(v, far))) as u32
    };
    m(0) | m(1) << 8 | m(2) << 16 | m(3) << 24
}

/// The first index in `from..end` whose activity is not `active`, 32 depths per step.
#[inline(always)]
fn depth_run_end_with(
    d: &[f32],
    from: usize,
    end: usize,
    active: bool,
    mask: impl Fn(&[f32], usize) -> u32,
) -> usize {
    let mut i = from;
    while i + 32 <= end {
        let far = mask(d, i);
        // bits where the run stops: a background pixel ends an active run, and an
        // active pixel ends a background run
        let stop = if active { far } else { !far };
        if stop != 0 {
            return i + stop.trailing_zeros() as usize;
        }
        i += 32;
    }
    while i < end && (d[i].to_bits() != FAR_BITS) == active {
        i += 1;
    }
    i
}

/// One past the last active depth in `a..end` (or `a`), 32 depths per step from the back.
#[inline(always)]
fn depth_trim_back_with(
    d: &[f32],
    a: usize,
    end: usize,
    mask: impl Fn(&[f32], usize) -> u32,
) -> usize {
    let mut b = end;
    while b >= a + 32 {
        let active = !mask(d, b - 32);
        if active != 0 {
            return b - active.leading_zeros() as usize;
        }
        b -= 32;
    }
    while b > a && d[b - 1].to_bits() == FAR_BITS {
        b -= 1;
    }
    b
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn depth_run_end_avx2(d: &[f32], from: usize, end: usize, active: bool) -> usize {
    depth_run_end_with(d, from, end, active, |d, i| unsafe {
        far_mask32_avx2(d, i)
    })
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn depth_trim_back_avx2(d: &[f32], a: usize, end: usize) -> usize {
    depth_trim_back_with(d, a, end, |d, i| unsafe { far_mask32_avx2(d, i) })
}

fn depth_run_end(d: &[f32], from: usize, end: usize, active: bool) -> usize {
    assert!(end <= d.len());
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above); every 32-depth load
        // lies inside `from..end`, which lies inside `d` (asserted).
        return unsafe { depth_run_end_avx2(d, from, end, active) };
    }
    depth_run_end_with(d, from, end, active, far_mask32_portable)
}

fn depth_trim_back(d: &[f32], a: usize, end: usize) -> usize {
    assert!(end <= d.len());
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: as in `depth_run_end`.
        return unsafe { depth_trim_back_avx2(d, a, end) };
    }
    depth_trim_back_with(d, a, end, far_mask32_portable)
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
pub fn run_end<'a, P: Pixel>(
    layer: impl Into<LayerRef<'a, P>>,
    op: Operator,
    from: usize,
    end: usize,
    active: bool,
) -> usize {
    let layer = layer.into();
    match op {
        Operator::Depth => depth_run_end(layer.depth, from, end, active),
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
pub fn trim<'a, P: Pixel>(
    layer: impl Into<LayerRef<'a, P>>,
    op: Operator,
    span: &Range<usize>,
) -> Range<usize> {
    let layer = layer.into();
    let a = run_end(layer, op, span.start, span.end, false);
    if a == span.end {
        return a..a;
    }
    a..trim_back(layer, op, a, span.end)
}

/// One past the last active pixel of `a..end`, given that pixel `a` is active.
fn trim_back<P: Pixel>(layer: LayerRef<'_, P>, op: Operator, a: usize, end: usize) -> usize {
    match op {
        Operator::Depth => depth_trim_back(layer.depth, a, end),
        Operator::Over => {
            let c = &layer.color;
            let mut b = end;
            while b >= a + BLOCK && colors_uniform(c, b - BLOCK, false) {
                b -= BLOCK;
            }
            while b > a && c[b - 1].is_clear() {
                b -= 1;
            }
            b
        }
    }
}

/// [`trim`] knowing that every active pixel lies in `rect`: rows and columns outside it
/// are not read (the front is found with [`first_active`]; the back scans back from the
/// rectangle's last pixel). Constant time for a dense layer.
pub fn trim_in<'a, P: Pixel>(
    layer: impl Into<LayerRef<'a, P>>,
    op: Operator,
    span: &Range<usize>,
    rect: &ActiveRect,
) -> Range<usize> {
    let layer = layer.into();
    let clip = rect.clip(layer.width, span);
    let a = first_active(layer, op, clip.start, clip.end, rect);
    if a == clip.end {
        return span.end..span.end;
    }
    a..trim_back(layer, op, a, clip.end)
}

/// The next run of active pixels at or after `from` and before `end`, reading only
/// pixels inside `rect` (outside it everything is background); `end..end` when there is
/// none. A run never crosses the rectangle's right edge unless the rectangle spans whole
/// rows.
pub fn next_run<'a, P: Pixel>(
    layer: impl Into<LayerRef<'a, P>>,
    op: Operator,
    from: usize,
    end: usize,
    rect: &ActiveRect,
) -> Range<usize> {
    let layer = layer.into();
    let a = first_active(layer, op, from, end, rect);
    if a == end {
        return end..end;
    }
    let w = layer.width as usize;
    let run_limit = if rect.full_width(layer.width) {
        rect.y1 as usize * w
    } else {
        (a / w) * w + rect.x1 as usize
    };
    a..run_end(layer, op, a, end.min(run_limit), true)
}

/// The first active pixel in `from..end` (or `end`), reading only pixels inside `rect`.
pub fn first_active<'a, P: Pixel>(
    layer: impl Into<LayerRef<'a, P>>,
    op: Operator,
    from: usize,
    end: usize,
    rect: &ActiveRect,
) -> usize {
    let layer = layer.into();
    if rect.is_empty() {
        return end;
    }
    let w = layer.width as usize;
    let (x0, x1, y0, y1) = (
        rect.x0 as usize,
        rect.x1 as usize,
        rect.y0 as usize,
        rect.y1 as usize,
    );
    if rect.full_width(layer.width) {
        let lim = end.min(y1 * w);
        let from = from.max(y0 * w);
        if from >= lim {
            return end;
        }
        let a = run_end(layer, op, from, lim, false);
        return if a == lim { end } else { a };
    }
    let mut i = from;
    while i < end {
        let (y, x) = (i / w, i % w);
        if y >= y1 {
            break;
        }
        if y < y0 {
            i = y0 * w + x0;
        } else if x < x0 {
            i = y * w + x0;
        } else if x >= x1 {
            i = (y + 1) * w + x0;
        } else {
            let row_end = (y * w + x1).min(end);
            let a = run_end(layer, op, i, row_end, false);
            if a < row_end {
                return a;
            }
            i = (y + 1) * w + x0;
        }
    }
    end
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs of every length from 1 to 150, alternating, in a 97 x 5 layer.
    fn striped() -> Layer<[u8; 4]> {
        let mut l = Layer::<[u8; 4]>::new(97, 5);
        let n = l.len();
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
        l
    }

    #[test]
    fn runs_and_trims_match_a_pixel_by_pixel_scan() {
        let l = striped();
        let n = l.len();
        for op in [Operator::Depth, Operator::Over] {
            for from in 0..n {
                for active in [false, true] {
                    let slow = (from..n).find(|&k| op.active(&l, k) != active).unwrap_or(n);
                    assert_eq!(run_end(&l, op, from, n, active), slow);
                    // ends inside the span, at every distance from `from`
                    for end in [from, from + 1, from + 31, from + 32, from + 33, n - 1] {
                        let end = end.clamp(from, n);
                        let slow = (from..end).find(|&k| op.active(&l, k) != active);
                        assert_eq!(run_end(&l, op, from, end, active), slow.unwrap_or(end));
                    }
                }
            }
            for s in [0..n, 3..n - 2, 5..6, 40..40, 0..5, 33..97, 64..400] {
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

    /// A layer whose active pixels all lie in `rect`, with runs touching its edges.
    fn inside(w: u32, h: u32, rect: ActiveRect, seed: u64) -> Layer<[u8; 4]> {
        let mut l = Layer::<[u8; 4]>::new(w, h);
        let mut s = seed;
        for y in rect.y0..rect.y1 {
            for x in rect.x0..rect.x1 {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let edge = x == rect.x0 || x + 1 == rect.x1;
                if edge || (s >> 60) < 9 {
                    let i = (y * w + x) as usize;
                    l.depth[i] = (s >> 40) as f32;
                    l.color[i] = [x as u8, y as u8, 1, 255];
                }
            }
        }
        l
    }

    #[test]
    fn runs_inside_a_rectangle_are_the_runs_of_a_full_scan() {
        let (w, h) = (70u32, 9u32);
        let rects = [
            ActiveRect::full(w, h),
            ActiveRect {
                x0: 0,
                y0: 2,
                x1: w,
                y1: 7,
            },
            ActiveRect {
                x0: 3,
                y0: 1,
                x1: 41,
                y1: 8,
            },
            ActiveRect {
                x0: 33,
                y0: 0,
                x1: 70,
                y1: 9,
            },
            ActiveRect {
                x0: 5,
                y0: 4,
                x1: 6,
                y1: 5,
            },
            ActiveRect::EMPTY,
        ];
        for (k, rect) in rects.iter().enumerate() {
            let l = inside(w, h, *rect, k as u64);
            assert_eq!(ActiveRect::of_layer(&l, Operator::Depth), *rect);
            let full = ActiveRect::full(w, h);
            for op in [Operator::Depth, Operator::Over] {
                for span in [0..l.len(), 1..300, 69..71, 140..141, 350..630, 0..0] {
                    assert_eq!(
                        trim_in(&l, op, &span, rect),
                        trim(&l, op, &span),
                        "{rect:?} {span:?}"
                    );
                    // every active pixel is covered by exactly the runs next_run finds
                    let mut got = vec![false; l.len()];
                    let mut i = span.start;
                    loop {
                        let r = next_run(&l, op, i, span.end, rect);
                        if r.is_empty() {
                            break;
                        }
                        assert!(r.start >= i && r.end <= span.end);
                        got[r.clone()].iter_mut().for_each(|g| *g = true);
                        i = r.end;
                    }
                    for (p, &g) in got.iter().enumerate() {
                        assert_eq!(g, span.contains(&p) && op.active(&l, p), "{rect:?} {p}");
                    }
                    let r = next_run(&l, op, span.start, span.end, &full);
                    let first = span.clone().find(|&p| op.active(&l, p));
                    assert_eq!(r.start, first.unwrap_or(span.end));
                }
            }
        }
    }
}
