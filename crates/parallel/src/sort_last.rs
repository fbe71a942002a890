//! Sort-last rendering (lecture: "couple rasterizers and geometric units; assign objects
//! to geometric units; composite results at end"; Molnar et al. 1994): each rank renders
//! its own block of the triangles over the whole screen, then the layers are composited
//! with colour and depth. Blocks follow the serial draw order, so the composite equals
//! the serial render bit for bit.

use crate::comm::{Comm, CommError};
use crate::composite::active::ActiveRect;
use crate::composite::{self, CompositeOptions, Layer, Strategy};
use crate::sort_common::{block, framebuffer, to_layer};
use glam::Vec3;
use irradia_raster::{Pipeline, Triangle};

/// Renders and composites; the image arrives at `opts.root`. Each rank tells the
/// compositor where its pixels can be ([`active_rect`]), so background outside that
/// rectangle is never scanned.
pub fn render<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
    strategy: Strategy,
    opts: &CompositeOptions,
) -> Result<Option<Layer<[u8; 4]>>, CommError> {
    let (layer, rect) = render_layer(comm, p, tris);
    composite::composite_bounded(comm, strategy, layer, rect, opts)
}

/// A screen rectangle holding every pixel `tris` can cover: the projection of their
/// world bounding box, widened by a pixel (the bounding boxes IceT asks of each rank,
/// Moreland et al. 2011). The whole screen when the box reaches behind the eye; empty
/// for no triangles.
pub fn active_rect(p: &Pipeline, tris: &[Triangle]) -> ActiveRect {
    let (w, h) = (p.width, p.height);
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for v in tris.iter().flat_map(|t| &t.v) {
        lo = lo.min(v.position);
        hi = hi.max(v.position);
    }
    if tris.is_empty() {
        return ActiveRect::EMPTY;
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return ActiveRect::full(w, h);
    }
    let m = p.view.view_proj();
    let (mut x0, mut y0, mut x1, mut y1) = (
        f32::INFINITY,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NEG_INFINITY,
    );
    for k in 0..8 {
        let c = Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        );
        let q = m * c.extend(1.0);
        if q.w.is_nan() || q.w <= 1e-6 {
            return ActiveRect::full(w, h);
        }
        // The geometry stage's viewport: NDC x, y in [-1, 1] to pixels, y down.
        let x = (q.x / q.w * 0.5 + 0.5) * w as f32;
        let y = (0.5 - q.y / q.w * 0.5) * h as f32;
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let clamp = |v: f32, n: u32| v.clamp(0.0, n as f32) as u32;
    let r = ActiveRect {
        x0: clamp(x0.floor() - 1.0, w),
        y0: clamp(y0.floor() - 1.0, h),
        x1: clamp(x1.ceil() + 1.0, w),
        y1: clamp(y1.ceil() + 1.0, h),
    };
    if r.is_empty() {
        ActiveRect::EMPTY
    } else {
        r
    }
}

/// The render step alone (stage "render"): this rank's block of the triangles drawn
/// over the whole screen, as a layer to composite, and the [`active_rect`] it lies in
/// (for [`composite::composite_bounded`], or onto a tiled display with
/// [`crate::display_tiles::composite_to_tiles_bounded`]).
pub fn render_layer<C: Comm>(
    comm: &C,
    p: &Pipeline,
    tris: &[Triangle],
) -> (Layer<[u8; 4]>, ActiveRect) {
    comm.log().begin_stage("render");
    let mine = &tris[block(tris.len(), comm.rank(), comm.size())];
    let mut fb = framebuffer(p);
    p.render_triangles(mine, &mut fb)
        .expect("framebuffer matches the pipeline");
    (to_layer(&fb), active_rect(p, mine))
}
