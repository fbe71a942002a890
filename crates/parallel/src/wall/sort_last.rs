//! The wall rendered sort-last: instead of every display rank rendering all objects
//! through its own off-axis frustum (sort-first by display), every rank renders its
//! block of the objects over the whole wall, and the layers are depth-composited
//! straight onto the displays' tiles ([`crate::display_tiles`]) — the way IceT drives a
//! tiled display from a cluster whose data does not fit one node (Moreland, Wylie,
//! Pavlakos 2001). Each display then blends and corrects its tile as before.
//!
//! The wall image is one frustum; display `i`'s tile is its rectangle of it (overlap
//! included, bezel gaps skipped), so the tile shows what the display's own off-axis
//! frustum shows, up to the rasterizer's rounding of the two projections.

use super::{WallConfig, WallSource};
use crate::comm::{Comm, CommError};
use crate::composite::active::ActiveRect;
use crate::composite::{CompositeOptions, Layer, Strategy, FAR};
use crate::display_tiles::{composite_to_tiles_bounded, DisplayLayout, DisplayTile};
use crate::sort_common::block;
use crate::workload::Workload;
use glam::Vec3;
use irradia_raster::{ColorBuffer, ColorFormat, Framebuffer};

/// How the displays' images are made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WallRendering {
    /// Every display renders every object through its own frustum.
    PerDisplay,
    /// Objects split over the ranks, composited onto the displays with this strategy.
    SortLast(Strategy),
}

/// The displays as tiles of the wall image: display `i` is driven by rank `i`.
pub fn layout(c: &WallConfig) -> DisplayLayout {
    let (width, height) = c.wall_size();
    DisplayLayout {
        width,
        height,
        tiles: (0..c.displays())
            .map(|i| {
                let (x, y) = c.origin(i);
                DisplayTile {
                    rank: i,
                    x,
                    y,
                    width: c.width,
                    height: c.height,
                }
            })
            .collect(),
    }
}

/// This rank's block of `w`'s triangles rendered over the whole wall (linear RGBA32F and
/// depth, background clear at depth [`FAR`]), and the screen rectangle it lies in
/// ([`crate::sort_last::active_rect`]).
pub fn wall_layer<C: Comm>(
    comm: &C,
    c: &WallConfig,
    w: &Workload,
) -> (Layer<[f32; 4]>, ActiveRect) {
    let (ww, wh) = c.wall_size();
    let p = w.pipeline(ww, wh);
    let tris = w.triangles();
    let mine = &tris[block(tris.len(), comm.rank(), comm.size())];
    let rect = crate::sort_last::active_rect(&p, mine);
    let mut fb = Framebuffer::new(ww, wh, ColorFormat::Rgba32F).expect("checked wall size");
    p.render_triangles(mine, &mut fb)
        .expect("framebuffer matches the pipeline");
    let ColorBuffer::Rgba32F(color) = fb.color else {
        unreachable!("asked for RGBA32F")
    };
    let layer = Layer {
        width: ww,
        height: wh,
        color,
        depth: fb
            .depth
            .iter()
            .map(|&d| if d >= 1.0 { FAR } else { d })
            .collect(),
    };
    (layer, rect)
}

/// The linear colour this rank's display should show, composited sort-last with
/// `strategy` (every rank renders its share of the objects). A uniform source has no
/// objects: each display takes its colour directly.
pub fn render_tile<C: Comm>(
    comm: &C,
    c: &WallConfig,
    src: &WallSource,
    strategy: Strategy,
) -> Result<Vec<Vec3>, CommError> {
    let w = match src {
        WallSource::Uniform(_) => return Ok(super::render_display(c, src, comm.rank())),
        WallSource::Workload(w) => w,
    };
    let (layer, rect) = wall_layer(comm, c, w);
    let opts = CompositeOptions::default();
    let tile = composite_to_tiles_bounded(comm, strategy, layer, rect, &layout(c), &opts)?
        .ok_or_else(|| CommError::Aborted(format!("rank {} drives no display", comm.rank())))?;
    Ok(tile
        .color
        .iter()
        .map(|q| Vec3::new(q[0], q[1], q[2]).clamp(Vec3::ZERO, Vec3::ONE))
        .collect())
}
