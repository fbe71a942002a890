//! The final gather: every rank sends the piece of the image it owns (as run lengths) to
//! the display rank, which pastes the pieces into a background layer. Runs are found
//! inside the rank's active rectangle only (what the reduce step left it with).

use super::{rle, ActiveRect, CompositeOptions, Layer, Pixel};
use crate::comm::{Comm, CommError};
use std::ops::Range;

const TAG_PIECES: u32 = 0x0fff;

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
    let root = opts.root;
    if comm.rank() != root {
        let msg = rle::encode_bounded(layer, span, opts.op, opts.rle, rect);
        comm.send(root, TAG_PIECES, &msg)?;
        return Ok(None);
    }
    // The root's own span, read inside the rectangle only (outside it is background).
    let mut out = Layer::new(layer.width, layer.height);
    let w = layer.width as usize;
    let inside = rect.clip(layer.width, &span);
    if !inside.is_empty() {
        for y in inside.start / w..=(inside.end - 1) / w {
            let row = y * w + rect.x0 as usize..y * w + rect.x1 as usize;
            let part = row.start.max(inside.start)..row.end.min(inside.end);
            if !part.is_empty() {
                out.color[part.clone()].copy_from_slice(&layer.color[part.clone()]);
                out.depth[part.clone()].copy_from_slice(&layer.depth[part]);
            }
        }
    }
    for r in (0..comm.size()).filter(|&r| r != root) {
        let buf = comm.recv(r, TAG_PIECES)?;
        rle::apply(&mut out, &buf, rle::Apply::Replace)
            .map_err(|message| CommError::Malformed { rank: r, message })?;
    }
    Ok(Some(out))
}
