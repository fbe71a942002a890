//! Tiny triangles as ready-made fragments.
//!
//! Most triangles of a finely tessellated mesh seen from afar (the gyroid workload:
//! 0.7 pixels per input triangle) have a bounding box of at most a few pixel centres
//! and cover one or two of them. For such a triangle the rasterizer's per-triangle
//! set-up (edge functions, depth plane, broadcasting the constants) and the trip of the
//! whole screen triangle (152 bytes) through memory to every band cost far more than
//! its pixels. The geometry stage therefore shades them itself, while the vertices are
//! in registers: it scans the few centres of the box with the same [`Setup`], computes
//! the depth and the Gouraud colour of each covered one exactly as the rasterizer
//! would, and bins a 16-byte [`Fragment`] per covered pixel instead of the triangle.
//! The band then only does the depth test and the write, in submission order (the bin
//! lists interleave triangles and fragments, [`FRAGMENT_BIT`]), so images are bit for
//! bit those of drawing the triangles.
//!
//! This is the "fragment" end of the sorting taxonomy (Molnar, Cox, Ellsworth and
//! Fuchs, "A Sorting Classification of Parallel Rendering", 1994) applied to the
//! triangles whose set-up costs more than their pixels, as hardware rasterizers do
//! with small-triangle fast paths. Only the interpolated-colour RGBA8 path (Gouraud or
//! unlit without material textures) uses it: other shaders need the triangle at the
//! pixel.

use crate::fragment::DepthFunc;
use crate::framebuffer::to_rgba8;
use crate::interpolate::{perspective_weights, varyings};
use crate::rasterizer::{Candidate, Setup, EXACT_CULL_CENTRES};
use crate::screen::{varying, Rect, ScreenVertex};

/// Bounding boxes of at most this many pixel centres are turned into fragments (those
/// the geometry stage's cull tests centre by centre anyway).
pub(crate) const MAX_CENTRES: i64 = EXACT_CULL_CENTRES;

/// Set in a bin entry that indexes the batch's fragments instead of its triangles.
pub(crate) const FRAGMENT_BIT: u32 = 1 << 31;

/// A shaded pixel of a tiny triangle: where, its depth and its colour.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C)]
pub(crate) struct Fragment {
    pub x: u32,
    pub y: u32,
    pub z: f32,
    pub rgba: [u8; 4],
}

/// Calls `f` with the fragment of every pixel centre of the candidate's box that the
/// triangle `v` (snapped as in `k`) covers, in scan order: the pixels, depths and
/// colours that drawing it with interpolated colour into an RGBA8 buffer computes.
#[inline(always)]
pub(crate) fn fragments(v: [&ScreenVertex; 3], k: &Candidate, mut f: impl FnMut(Fragment)) {
    let (x0, x1, y0, y1) = k.bounds;
    // The edges first: about a third of these triangles cover no centre (the gyroid's
    // sub-pixel ones), and need neither the f64 depth plane nor its division.
    let s = Setup::edges(v, k.p, k.area);
    let clip = Rect::new(x0 as u32, y0 as u32, x1 as u32 + 1, y1 as u32 + 1);
    debug_assert!(k.centres() <= MAX_CENTRES);
    let mut hits = [(0u32, 0u32, [0i64; 3]); MAX_CENTRES as usize];
    let mut n = 0;
    s.scan(&clip, |x, y, e| {
        hits[n] = (x, y, *e);
        n += 1;
    });
    if n == 0 {
        return;
    }
    let s = s.with_plane();
    // As `fragment::draw` with `InterpolatedColor` and `ColorTarget for [[u8; 4]]`.
    for (x, y, e) in &hits[..n] {
        let z = s.depth_in_row(s.depth_row(*y), *x);
        let w = perspective_weights(&s.v, s.lambda(e));
        let rgba = to_rgba8(varyings::<4>(&s.v, w, varying::COLOR));
        f(Fragment {
            x: *x,
            y: *y,
            z,
            rgba,
        });
    }
}

/// Depth-tests and writes one fragment into a band of whole rows of `width` pixels
/// starting at row `band_y0`.
#[inline(always)]
pub(crate) fn draw_fragment(
    f: &Fragment,
    width: usize,
    band_y0: u32,
    depth: &mut [f32],
    color: &mut [[u8; 4]],
    func: DepthFunc,
) {
    let i = (f.y - band_y0) as usize * width + f.x as usize;
    if func.pass(f.z, depth[i]) {
        depth[i] = f.z;
        color[i] = f.rgba;
    }
}
