//! The final gather: every rank sends the piece of the image it owns (as run lengths) to
//! the display rank, which pastes the pieces into the image. Runs are found inside the
//! rank's active rectangle only (what the reduce step left it with). The message
//! buffers, out and in, are reused by every gather on the thread (no allocation, no page
//! faults after the first frame); [`gather_into`] writes straight into the caller's
//! planes (the Python binding's numpy arrays), each pixel once.

use super::{pairwise, rle, ActiveRect, CompositeOptions, Layer, Pixel, FAR};
use crate::comm::{Comm, CommError};
use std::cell::RefCell;
use std::ops::Range;

const TAG_PIECES: u32 = 0x0fff;
/// The colour and depth planes of a dense piece follow its header with this tag.
const TAG_PLANES: u32 = TAG_PIECES + 0x4000;
/// Header mode (after the run-length encoder's 0 and 1): words `start, end, 2, a, b`,
/// pixels `a..b` of the span `start..end` follow as a colour and a depth message, sent
/// from the layer's memory and received straight into the image; the rest of the span
/// is background.
const PLANES: u32 = 2;

/// Bytes of the header a rank sends before its dense span's colour and depth planes
/// (span start and end, the planes tag, the sent range): the gather of a dense span is
/// three messages, this header and the two planes (the network model of `scale.rs`
/// counts them so).
pub const DENSE_HEADER_BYTES: usize = 5 * 4;

thread_local! {
    /// The message a rank sends (or the one the root receives), reused.
    static BUFS: RefCell<Vec<Vec<u8>>> = const { RefCell::new(Vec::new()) };
}

pub fn gather<P: Pixel, C: Comm>(
    comm: &C,
    layer: &Layer<P>,
    span: Range<usize>,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    let all = ActiveRect::full(layer.width, layer.height);
    gather_bounded(comm, layer, span, &all, opts)
}

/// [`gather`] of a layer whose active pixels all lie inside `rect`.
pub fn gather_bounded<P: Pixel, C: Comm>(
    comm: &C,
    layer: &Layer<P>,
    span: Range<usize>,
    rect: &ActiveRect,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    if comm.rank() != opts.root {
        gather_into(comm, layer, span, rect, opts, None)?;
        return Ok(None);
    }
    let mut out = Layer::new(layer.width, layer.height);
    gather_into(
        comm,
        layer,
        span,
        rect,
        opts,
        Some((&mut out.color, &mut out.depth)),
    )?;
    Ok(Some(out))
}

/// [`gather_bounded`] into the caller's colour and depth planes, which the root passes
/// (`out`, `layer.len()` pixels each; every pixel is written: the pieces, and background
/// wherever no rank drew, so the planes need not be initialised to anything) and the
/// other ranks leave `None`. Returns whether this rank wrote `out` (is the root).
pub fn gather_into<P: Pixel, C: Comm>(
    comm: &C,
    layer: &Layer<P>,
    span: Range<usize>,
    rect: &ActiveRect,
    opts: &CompositeOptions,
    out: Option<(&mut [P], &mut [f32])>,
) -> Result<bool, CommError> {
    let root = opts.root;
    BUFS.with(|bufs| {
        let mut bufs = bufs.borrow_mut();
        if comm.rank() != root {
            // Dense (or not run-length encoded) spans go as planes, sparse ones as runs
            // (the pairwise exchange's choice: trimmed to the active pixels, sampled).
            let plan = pairwise::choose(layer, &span, opts.op, opts.rle, rect);
            if plan.mode == pairwise::DENSE {
                let (a, b) = (plan.span.start, plan.span.end);
                let header = [
                    span.start as u32,
                    span.end as u32,
                    PLANES,
                    a as u32,
                    b as u32,
                ];
                const { assert!(std::mem::size_of::<[u32; 5]>() == DENSE_HEADER_BYTES) };
                comm.send(root, TAG_PIECES, bytemuck::cast_slice(&header))?;
                if a < b {
                    let planes = vec![
                        bytemuck::cast_slice::<P, u8>(&layer.color[a..b]),
                        bytemuck::cast_slice::<f32, u8>(&layer.depth[a..b]),
                    ];
                    comm.exchange_pieces_many(
                        TAG_PLANES,
                        &[(root, planes)],
                        &mut [],
                        &mut |_, _, _| Ok(()),
                    )?;
                }
                return Ok(false);
            }
            bufs.resize_with(1, Vec::new);
            let msg = &mut bufs[0];
            msg.clear();
            rle::encode_bounded_into(msg, layer, span, opts.op, opts.rle, rect);
            comm.send(root, TAG_PIECES, msg)?;
            return Ok(false);
        }
        let (oc, od) = out.expect("the root gathers into the image's planes");
        assert!(
            oc.len() == layer.len() && od.len() == layer.len(),
            "gather: planes of {} and {} pixels for a layer of {}",
            oc.len(),
            od.len(),
            layer.len()
        );
        let background = |oc: &mut [P], od: &mut [f32], r: Range<usize>| {
            oc[r.clone()].fill(P::CLEAR);
            od[r].fill(FAR);
        };
        // The root's own span, read inside the rectangle only (outside it is background).
        let w = layer.width as usize;
        let inside = rect.clip(layer.width, &span);
        let mut at = span.start;
        if !inside.is_empty() {
            for y in inside.start / w..=(inside.end - 1) / w {
                let row = y * w + rect.x0 as usize..y * w + rect.x1 as usize;
                let part = row.start.max(inside.start)..row.end.min(inside.end);
                if !part.is_empty() {
                    background(oc, od, at..part.start);
                    oc[part.clone()].copy_from_slice(&layer.color[part.clone()]);
                    od[part.clone()].copy_from_slice(&layer.depth[part.clone()]);
                    at = part.end;
                }
            }
        }
        background(oc, od, at..span.end);
        let mut covered = Vec::with_capacity(comm.size());
        covered.push(span);
        for r in (0..comm.size()).filter(|&r| r != root) {
            comm.exchange_into(&[], &[r], TAG_PIECES, &mut bufs)?;
            let malformed = |message: String| CommError::Malformed { rank: r, message };
            let msg = &bufs[0];
            let words: Option<Vec<u32>> =
                (msg.len() == 20).then(|| bytemuck::pod_collect_to_vec(msg));
            match words.as_deref() {
                Some(&[start, end, PLANES, a, b]) => {
                    let (start, end, a, b) = (start as usize, end as usize, a as usize, b as usize);
                    if !(start <= a && a <= b && b <= end && end <= layer.len()) {
                        return Err(malformed(format!(
                            "pixels {a}..{b} of span {start}..{end} in an image of {}",
                            layer.len()
                        )));
                    }
                    background(oc, od, start..a);
                    background(oc, od, b..end);
                    if a < b {
                        let into = vec![
                            bytemuck::cast_slice_mut::<P, u8>(&mut oc[a..b]),
                            bytemuck::cast_slice_mut::<f32, u8>(&mut od[a..b]),
                        ];
                        comm.exchange_pieces_many(
                            TAG_PLANES,
                            &[],
                            &mut [(r, into)],
                            &mut |_, _, _| Ok(()),
                        )?;
                    }
                    covered.push(start..end);
                }
                _ => {
                    let got =
                        rle::apply_to(oc, od, 0, msg, rle::Apply::Paste).map_err(malformed)?;
                    covered.push(got);
                }
            }
        }
        // Pixels no rank owns (none after a complete reduce) are background.
        covered.sort_by_key(|s| s.start);
        let mut at = 0;
        for s in covered {
            if s.start > at {
                background(oc, od, at..s.start);
            }
            at = at.max(s.end);
        }
        if at < layer.len() {
            background(oc, od, at..layer.len());
        }
        Ok(true)
    })
}
