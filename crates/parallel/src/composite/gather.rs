//! The final gather: every rank sends the piece of the image it owns (as run lengths) to
//! the display rank, which pastes the pieces into a background layer.

use super::{rle, CompositeOptions, Layer, Pixel};
use crate::comm::{Comm, CommError};
use std::ops::Range;

const TAG_PIECES: u32 = 0x0fff;

pub fn gather<P: Pixel, C: Comm>(
    comm: &C,
    layer: &Layer<P>,
    span: Range<usize>,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    let root = opts.root;
    if comm.rank() != root {
        let msg = rle::encode(layer, span, opts.op, opts.rle);
        comm.send(root, TAG_PIECES, &msg)?;
        return Ok(None);
    }
    let mut out = Layer::new(layer.width, layer.height);
    out.color[span.clone()].copy_from_slice(&layer.color[span.clone()]);
    out.depth[span.clone()].copy_from_slice(&layer.depth[span]);
    for r in (0..comm.size()).filter(|&r| r != root) {
        let buf = comm.recv(r, TAG_PIECES)?;
        rle::apply(&mut out, &buf, rle::Apply::Replace)
            .map_err(|message| CommError::Malformed { rank: r, message })?;
    }
    Ok(Some(out))
}
