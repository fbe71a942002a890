//! Active-pixel run-length encoding (Ahrens and Painter 1998; IceT's sparse images): a
//! span of a layer travels as alternating runs of inactive and active pixels, and only
//! active pixels carry colour and depth, so background costs eight bytes per run.
//!
//! Wire format, all in 4-byte words so that it can be read in place:
//! `start, end, mode` then, for `mode = DENSE`, `end - start` colours and as many depths;
//! for `mode = RLE`, runs of `inactive, active, colour[active], depth[active]` until the
//! span is covered. The receiver blends straight from the buffer, skipping inactive runs.

use super::active::{self, ActiveRect};
use super::{Layer, LayerRef, Operator, Pixel};
use std::borrow::Cow;
use std::ops::Range;

const DENSE: u32 = 0;
const RLE: u32 = 1;

fn push_words(out: &mut Vec<u8>, w: &[u32]) {
    out.extend_from_slice(bytemuck::cast_slice(w));
}

/// Encodes `span` of `layer` (run lengths when `rle`, else dense).
pub fn encode<P: Pixel>(layer: &Layer<P>, span: Range<usize>, op: Operator, rle: bool) -> Vec<u8> {
    let all = ActiveRect::full(layer.width, layer.height);
    encode_bounded(layer, span, op, rle, &all)
}

/// [`encode`] of a layer whose active pixels all lie inside `rect`: run lengths are
/// found without reading anything outside it.
pub fn encode_bounded<P: Pixel>(
    layer: &Layer<P>,
    span: Range<usize>,
    op: Operator,
    rle: bool,
    rect: &ActiveRect,
) -> Vec<u8> {
    let px = std::mem::size_of::<P>() + 4;
    let mut out = Vec::with_capacity(12 + if rle { 64 } else { span.len() * px });
    encode_bounded_into(&mut out, layer, span, op, rle, rect);
    out
}

/// [`encode_bounded`] appended to `out` (no allocation when `out` has room).
pub fn encode_bounded_into<P: Pixel>(
    out: &mut Vec<u8>,
    layer: &Layer<P>,
    span: Range<usize>,
    op: Operator,
    rle: bool,
    rect: &ActiveRect,
) {
    if !rle {
        out.reserve(12 + span.len() * (std::mem::size_of::<P>() + 4));
        push_words(out, &[span.start as u32, span.end as u32, DENSE]);
        out.extend_from_slice(bytemuck::cast_slice(&layer.color[span.clone()]));
        out.extend_from_slice(bytemuck::cast_slice(&layer.depth[span]));
        return;
    }
    encode_runs_into(out, layer, span, op, rect);
}

/// Appends the run-length message of `span` of `layer` to `out` (no allocation when
/// `out` has room: the pairwise exchange reuses one buffer for every round and frame).
/// Only pixels inside `rect` are read ([`ActiveRect`]: everything outside it is
/// background); pass [`ActiveRect::full`] when nothing is known. A span with no active
/// pixel is one run of background.
pub fn encode_runs_into<'a, P: Pixel>(
    out: &mut Vec<u8>,
    layer: impl Into<LayerRef<'a, P>>,
    span: Range<usize>,
    op: Operator,
    rect: &ActiveRect,
) {
    let layer = layer.into();
    push_words(out, &[span.start as u32, span.end as u32, RLE]);
    let mut i = span.start;
    while i < span.end {
        let run = active::next_run(layer, op, i, span.end, rect);
        let (a0, a1) = (run.start, run.end);
        // one reservation per run: the three copies below then never reallocate
        out.reserve(8 + (a1 - a0) * (std::mem::size_of::<P>() + 4));
        push_words(out, &[(a0 - i) as u32, (a1 - a0) as u32]);
        out.extend_from_slice(bytemuck::cast_slice(&layer.color[a0..a1]));
        out.extend_from_slice(bytemuck::cast_slice(&layer.depth[a0..a1]));
        i = a1;
    }
}

/// A received buffer as 4-byte words (copied only if the allocation is misaligned).
fn words(buf: &[u8]) -> Result<Cow<'_, [u32]>, String> {
    if !buf.len().is_multiple_of(4) || buf.len() < 12 {
        return Err(format!(
            "image message of {} bytes is not whole words",
            buf.len()
        ));
    }
    Ok(match bytemuck::try_cast_slice::<u8, u32>(buf) {
        Ok(w) => Cow::Borrowed(w),
        Err(_) => Cow::Owned(bytemuck::pod_collect_to_vec(buf)),
    })
}

/// The span a message covers.
pub fn span_of(buf: &[u8]) -> Result<Range<usize>, String> {
    let w = words(buf)?;
    Ok(w[0] as usize..w[1] as usize)
}

/// What to do with each incoming active pixel.
#[derive(Clone, Copy, Debug)]
pub enum Apply {
    /// Overwrite (gathering final pieces).
    Replace,
    /// Overwrite, and write background over the inactive runs too (gathering into
    /// planes that hold nothing yet: every pixel of the span is written).
    Paste,
    /// Composite; `incoming_front` says whether the sender is in front of this rank.
    Blend { op: Operator, incoming_front: bool },
}

/// Applies an encoded span to `layer`. Returns the span. Errors describe a malformed
/// message (the caller names the sender).
pub fn apply<P: Pixel>(
    layer: &mut Layer<P>,
    buf: &[u8],
    how: Apply,
) -> Result<Range<usize>, String> {
    apply_to(&mut layer.color, &mut layer.depth, 0, buf, how)
}

/// [`apply`] on a window of a layer: `colors` and `depths` hold pixels
/// `base..base + colors.len()`, and the message's span must lie inside that window.
pub fn apply_to<P: Pixel>(
    colors: &mut [P],
    depths: &mut [f32],
    base: usize,
    buf: &[u8],
    how: Apply,
) -> Result<Range<usize>, String> {
    let w = words(buf)?;
    let (start, end, mode) = (w[0] as usize, w[1] as usize, w[2]);
    if start > end || start < base || end - base > colors.len() {
        return Err(format!(
            "span {start}..{end} outside pixels {base}..{}",
            base + colors.len()
        ));
    }
    let cw = std::mem::size_of::<P>() / 4;
    let body = &w[3..];
    let run = |colors: &mut [P],
               depths: &mut [f32],
               at: usize,
               words: &[u32],
               count: usize|
     -> Result<usize, String> {
        let need = count * (cw + 1);
        if words.len() < need {
            return Err("message ends inside a run".into());
        }
        let incoming: &[P] = bytemuck::cast_slice(&words[..count * cw]);
        let incoming_depths: &[f32] = bytemuck::cast_slice(&words[count * cw..need]);
        let at = at - base;
        apply_run(
            &mut colors[at..at + count],
            &mut depths[at..at + count],
            incoming,
            incoming_depths,
            how,
        );
        Ok(need)
    };
    match mode {
        DENSE => {
            run(colors, depths, start, body, end - start)?;
        }
        RLE => {
            let mut i = start;
            let mut k = 0;
            while i < end {
                if k + 2 > body.len() {
                    return Err("message ends inside a run header".into());
                }
                let (skip, active) = (body[k] as usize, body[k + 1] as usize);
                k += 2;
                if skip > end - i || active > end - i - skip {
                    return Err("runs overflow the span".into());
                }
                if let Apply::Paste = how {
                    colors[i - base..i - base + skip].fill(P::CLEAR);
                    depths[i - base..i - base + skip].fill(super::FAR);
                }
                i += skip;
                k += run(colors, depths, i, &body[k..], active)?;
                i += active;
            }
        }
        m => return Err(format!("unknown image encoding {m}")),
    }
    Ok(start..end)
}

#[inline]
fn apply_run<P: Pixel>(lc: &mut [P], ld: &mut [f32], colors: &[P], depths: &[f32], how: Apply) {
    match how {
        Apply::Replace | Apply::Paste => {
            lc.copy_from_slice(colors);
            ld.copy_from_slice(depths);
        }
        Apply::Blend {
            op: Operator::Depth,
            incoming_front,
        } => super::depth::blend(lc, ld, colors, depths, incoming_front),
        Apply::Blend {
            op: Operator::Over,
            incoming_front,
        } => super::over::blend(lc, ld, colors, depths, incoming_front),
    }
}

/// Decodes a message into a fresh background layer of the given size (for tests).
pub fn decode<P: Pixel>(width: u32, height: u32, buf: &[u8]) -> Result<Layer<P>, String> {
    let mut l = Layer::new(width, height);
    apply(&mut l, buf, Apply::Replace)?;
    Ok(l)
}
