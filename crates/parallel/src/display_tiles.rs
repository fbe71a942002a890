//! The final gather to *several* display ranks: a tiled display, where each display
//! process drives one projector or panel and needs only its own rectangle of the
//! composited image (IceT's tiled-display compositing: Moreland, Wylie, Pavlakos 2001,
//! "Sort-last parallel rendering for viewing extremely large data sets on tile displays";
//! Moreland et al. 2011, "An Image Compositing Solution at Scale", §3).
//!
//! After a compositing strategy's reduce step every rank owns a contiguous span of the
//! image ([`crate::composite::reduce`]). Each rank cuts its span against every display
//! tile and sends each display rank the rows it holds of that tile, active pixels only
//! ([`rle`]); the display rank pastes them into a tile-sized layer. Tiles may overlap
//! (projectors whose images are edge-blended share pixels): each display receives its
//! whole rectangle. A single tile covering the image at rank `root` is the ordinary
//! [`gather`](crate::composite::gather::gather).
//!
//! Wire format of one message: for each row segment, its byte length as a `u32`
//! followed by an [`rle`] span message, whose span names the image pixels it covers.

use crate::comm::{Comm, CommError};
use crate::composite::active::ActiveRect;
use crate::composite::{self, rle, CompositeOptions, Layer, Pixel, Strategy};
use std::ops::Range;

/// Tag of the tile messages.
const TAG_TILES: u32 = 0x0ffe;

/// One display: the rank that drives it and the rectangle of the image it shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct DisplayTile {
    pub rank: usize,
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl DisplayTile {
    /// The image pixels (row-major indices in an image `image_width` wide) of row `row`
    /// of this tile (`0 <= row < height`).
    fn row_pixels(&self, image_width: u32, row: u32) -> Range<usize> {
        let start = (self.y + row) as usize * image_width as usize + self.x as usize;
        start..start + self.width as usize
    }
}

/// The displays of a tiled display over an image of `width` x `height` pixels.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DisplayLayout {
    pub width: u32,
    pub height: u32,
    pub tiles: Vec<DisplayTile>,
}

impl DisplayLayout {
    /// A grid of `columns` x `rows` tiles, driven by ranks `0, 1, ...` in row-major order
    /// from the top left, each tile widened by `overlap` pixels into its neighbours (as
    /// edge-blended projectors are), clipped to the image.
    pub fn grid(
        width: u32,
        height: u32,
        columns: u32,
        rows: u32,
        overlap: u32,
    ) -> Result<Self, String> {
        if columns == 0 || rows == 0 {
            return Err("a display grid needs at least one column and one row".into());
        }
        if columns > width || rows > height {
            return Err(format!(
                "a {columns}x{rows} display grid does not fit a {width}x{height} image"
            ));
        }
        let cut = |n: u32, k: u32, i: u32| (n as u64 * i as u64 / k as u64) as u32;
        let mut tiles = Vec::new();
        for r in 0..rows {
            for c in 0..columns {
                let x0 = cut(width, columns, c).saturating_sub(if c > 0 { overlap } else { 0 });
                let x1 = (cut(width, columns, c + 1) + if c + 1 < columns { overlap } else { 0 })
                    .min(width);
                let y0 = cut(height, rows, r).saturating_sub(if r > 0 { overlap } else { 0 });
                let y1 =
                    (cut(height, rows, r + 1) + if r + 1 < rows { overlap } else { 0 }).min(height);
                tiles.push(DisplayTile {
                    rank: (r * columns + c) as usize,
                    x: x0,
                    y: y0,
                    width: x1 - x0,
                    height: y1 - y0,
                });
            }
        }
        Ok(Self {
            width,
            height,
            tiles,
        })
    }

    /// Checks the layout against a job of `ranks` ranks and an image of `width` x
    /// `height`: every tile non-empty and inside the image, every display rank a rank of
    /// the job, at most one tile per rank.
    pub fn validate(&self, ranks: usize, width: u32, height: u32) -> Result<(), String> {
        if (self.width, self.height) != (width, height) {
            return Err(format!(
                "the display layout is for a {}x{} image, the frame is {width}x{height}",
                self.width, self.height
            ));
        }
        let mut seen = vec![false; ranks];
        for (i, t) in self.tiles.iter().enumerate() {
            if t.width == 0 || t.height == 0 {
                return Err(format!("display tile {i} is empty"));
            }
            if t.x as u64 + t.width as u64 > width as u64
                || t.y as u64 + t.height as u64 > height as u64
            {
                return Err(format!(
                    "display tile {i} ({}x{} at {},{}) lies outside the {width}x{height} image",
                    t.width, t.height, t.x, t.y
                ));
            }
            if t.rank >= ranks {
                return Err(format!(
                    "display tile {i} needs rank {}, but the job has {ranks} rank(s): run at least {} ranks or use fewer tiles",
                    t.rank,
                    t.rank + 1
                ));
            }
            if std::mem::replace(&mut seen[t.rank], true) {
                return Err(format!("rank {} drives two display tiles", t.rank));
            }
        }
        Ok(())
    }

    /// The tile driven by `rank`, if any.
    pub fn tile_of(&self, rank: usize) -> Option<&DisplayTile> {
        self.tiles.iter().find(|t| t.rank == rank)
    }

    /// `image` cut to `tile` (the serial oracle of [`gather_tiles`]).
    pub fn crop<P: Pixel>(image: &Layer<P>, tile: &DisplayTile) -> Layer<P> {
        let mut out = Layer::new(tile.width, tile.height);
        for row in 0..tile.height {
            let src = tile.row_pixels(image.width, row);
            let dst = row as usize * tile.width as usize;
            let n = tile.width as usize;
            out.color[dst..dst + n].copy_from_slice(&image.color[src.clone()]);
            out.depth[dst..dst + n].copy_from_slice(&image.depth[src]);
        }
        out
    }
}

/// Sends every display rank the part of `span` (this rank's share of the composited
/// `layer`, whose active pixels all lie in `rect`) that falls in its tile, and on a
/// display rank assembles its tile. Returns the tile image on display ranks, `None` on
/// the others.
pub fn gather_tiles<P: Pixel, C: Comm>(
    comm: &C,
    layer: &Layer<P>,
    span: Range<usize>,
    rect: &ActiveRect,
    layout: &DisplayLayout,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    let me = comm.rank();
    let mut local: Option<Vec<u8>> = None;
    let mut outgoing = Vec::new();
    for tile in &layout.tiles {
        let msg = encode_tile_part(layer, &span, rect, tile, opts);
        if tile.rank == me {
            local = Some(msg);
        } else {
            outgoing.push((tile.rank, msg));
        }
    }
    let tile = layout.tile_of(me);
    // Display ranks send to each other as well as receive: one exchange, which never
    // deadlocks (blocking sends both ways would, once messages pass MPI's eager limit).
    let sources: Vec<usize> = match tile {
        Some(_) => (0..comm.size()).filter(|&r| r != me).collect(),
        None => Vec::new(),
    };
    let sends: Vec<(usize, &[u8])> = outgoing.iter().map(|(r, m)| (*r, m.as_slice())).collect();
    let received = comm.exchange(&sends, &sources, TAG_TILES)?;
    let Some(tile) = tile else {
        return Ok(None);
    };
    let mut out = Layer::new(tile.width, tile.height);
    let local = local.unwrap_or_default();
    for (r, buf) in std::iter::once((me, &local)).chain(sources.iter().copied().zip(&received)) {
        paste(&mut out, tile, layout.width, buf)
            .map_err(|message| CommError::Malformed { rank: r, message })?;
    }
    Ok(Some(out))
}

/// The rows of `tile` inside `span`, each as a length-prefixed [`rle`] message.
fn encode_tile_part<P: Pixel>(
    layer: &Layer<P>,
    span: &Range<usize>,
    rect: &ActiveRect,
    tile: &DisplayTile,
    opts: &CompositeOptions,
) -> Vec<u8> {
    let mut out = Vec::new();
    if span.is_empty() {
        return out;
    }
    let w = layer.width as usize;
    // Only the tile rows that the span reaches.
    let first = (span.start / w).max(tile.y as usize);
    let last = ((span.end - 1) / w).min((tile.y + tile.height - 1) as usize);
    if first > last {
        return out;
    }
    for y in first..=last {
        let row = tile.row_pixels(layer.width, (y - tile.y as usize) as u32);
        let part = row.start.max(span.start)..row.end.min(span.end);
        if part.is_empty() {
            continue;
        }
        let msg = rle::encode_bounded(layer, part, opts.op, opts.rle, rect);
        out.extend_from_slice(&(msg.len() as u32).to_le_bytes());
        out.extend_from_slice(&msg);
    }
    out
}

/// Pastes the row segments of one message into the tile layer.
fn paste<P: Pixel>(
    out: &mut Layer<P>,
    tile: &DisplayTile,
    image_width: u32,
    mut buf: &[u8],
) -> Result<(), String> {
    let iw = image_width as usize;
    while !buf.is_empty() {
        if buf.len() < 4 {
            return Err("tile message ends inside a length".into());
        }
        let n = u32::from_le_bytes([buf[0], buf[1], buf[2], buf[3]]) as usize;
        let Some(msg) = buf.get(4..4 + n) else {
            return Err("tile message ends inside a row segment".into());
        };
        let span = rle::span_of(msg)?;
        let y = span.start / iw;
        if y < tile.y as usize || y >= (tile.y + tile.height) as usize {
            return Err(format!("row {y} is not in this display's tile"));
        }
        let row = (y - tile.y as usize) as u32;
        let pixels = tile.row_pixels(image_width, row);
        let at = row as usize * tile.width as usize;
        let n_row = tile.width as usize;
        rle::apply_to(
            &mut out.color[at..at + n_row],
            &mut out.depth[at..at + n_row],
            pixels.start,
            msg,
            rle::Apply::Replace,
        )?;
        buf = &buf[4 + n..];
    }
    Ok(())
}

/// Composites with `strategy` and delivers each display rank its tile (stages
/// "composite" and "gather" in the comm's log), ending with a frame barrier.
pub fn composite_to_tiles<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    layout: &DisplayLayout,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    let all = ActiveRect::full(layer.width, layer.height);
    composite_to_tiles_bounded(comm, strategy, layer, all, layout, opts)
}

/// [`composite_to_tiles`] of a layer whose active pixels all lie inside `rect` (see
/// [`composite::composite_bounded`]).
pub fn composite_to_tiles_bounded<P: Pixel, C: Comm>(
    comm: &C,
    strategy: Strategy,
    layer: Layer<P>,
    rect: ActiveRect,
    layout: &DisplayLayout,
    opts: &CompositeOptions,
) -> Result<Option<Layer<P>>, CommError> {
    comm.log().begin_stage("composite");
    let mut rect = rect;
    let (layer, span) = composite::reduce_tracked(comm, strategy, layer, &mut rect, opts)?;
    comm.log().begin_stage("gather");
    let out = gather_tiles(comm, &layer, span, &rect, layout, opts)?;
    comm.barrier()?;
    comm.log().end_stage();
    Ok(out)
}
