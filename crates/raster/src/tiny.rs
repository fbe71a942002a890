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
use crate::rasterizer::{Candidate, Setup, EXACT_CULL_CENTRES, HALF, ONE};
use crate::screen::{varying, ScreenVertex};

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
///
/// The box has at most [`MAX_CENTRES`] centres, so it is walked here centre by centre
/// with the edge functions of [`Setup::scan`] (the same values, stepped the same way;
/// a box this narrow never takes `scan`'s skip of a row's uncovered start), and the
/// f64 depth plane and its division are computed at the first covered centre: about a
/// third of these triangles (the gyroid's sub-pixel ones) cover none and need neither.
#[inline(always)]
pub(crate) fn fragments(v: [&ScreenVertex; 3], k: &Candidate, mut f: impl FnMut(Fragment)) {
    let (x0, x1, y0, y1) = k.bounds;
    debug_assert!(k.centres() <= MAX_CENTRES);
    let mut s = Setup::edges(v, k.p, k.area);
    let step_x = [s.a[0] * ONE, s.a[1] * ONE, s.a[2] * ONE];
    let step_y = [s.b[0] * ONE, s.b[1] * ONE, s.b[2] * ONE];
    let (px, py) = (x0 * ONE + HALF, y0 * ONE + HALF);
    let mut row: [i64; 3] = std::array::from_fn(|j| s.a[j] * px + s.b[j] * py + s.c[j]);
    let mut planed = false;
    for y in y0..=y1 {
        let mut e = row;
        for x in x0..=x1 {
            if (e[0] | e[1] | e[2]) >= 0 {
                if !planed {
                    s.plane();
                    planed = true;
                }
                // As `fragment::draw` with `InterpolatedColor` and `ColorTarget for [[u8; 4]]`.
                let z = s.depth_in_row(s.depth_row(y as u32), x as u32);
                let w = perspective_weights(&s.v, s.lambda(&e));
                let rgba = to_rgba8(varyings::<4>(&s.v, w, varying::COLOR));
                f(Fragment {
                    x: x as u32,
                    y: y as u32,
                    z,
                    rgba,
                });
            }
            for j in 0..3 {
                e[j] += step_x[j];
            }
        }
        for j in 0..3 {
            row[j] += step_y[j];
        }
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
