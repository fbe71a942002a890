//! Software prefetching for the bands of the binned rasterizer.
//!
//! A band draws every few-dozenth triangle of a batch (those binned into it), a stride
//! the hardware prefetcher does not follow, and each triangle touches a few rows of the
//! band's depth and colour buffers at an unpredictable place: with the triangles of a
//! group of batches spread over the screen, most of those rows have left the cache
//! since the band last drew there (the random-triangle workload spent half of its
//! span-drawing time waiting on the first depth load and the first colour load of a
//! block). So the band works two stages ahead (software pipelining of the loads, as in
//! Mowry, Lam and Gupta, "Design and Evaluation of a Compiler Algorithm for
//! Prefetching", ASPLOS 1992): [`FAR`] entries ahead it asks for the triangle's record,
//! [`NEAR`] entries ahead — the record has arrived by then — for the depth and colour
//! lines of the pixels its bounding box covers. The geometry stage asks for the vertex
//! records of an indexed mesh [`VERTEX_AHEAD`] triangles ahead. Prefetches are hints:
//! they change no result.

use crate::screen::ScreenTriangle;
use crate::tiny::Fragment;

/// Bin entries ahead of the one being drawn whose pixels are prefetched.
pub(crate) const NEAR: usize = 8;
/// Bin entries ahead whose triangle record (or fragment) is prefetched.
pub(crate) const FAR: usize = 16;
/// Rows of a triangle's box prefetched at most (larger triangles stream their rows
/// long enough for the hardware prefetcher).
const MAX_ROWS: usize = 12;

#[inline(always)]
fn line<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        // SAFETY: prefetching is only a hint and never faults.
        unsafe { _mm_prefetch(p as *const i8, _MM_HINT_T0) };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Asks for the cache lines of `t`.
#[inline(always)]
pub(crate) fn triangle(t: &ScreenTriangle) {
    let p = t as *const ScreenTriangle as *const u8;
    line(p);
    line(p.wrapping_add(64));
    line(p.wrapping_add(128));
}

/// Triangles ahead in an indexed mesh whose three vertex records are prefetched
/// ([`record`]): the geometry stage reads the records of the mesh's shared vertices
/// (tens of megabytes for a large mesh, written by the vertex pass before) in index
/// order, which wanders too far for the hardware prefetcher.
pub(crate) const VERTEX_AHEAD: usize = 12;

/// Asks for the cache lines of the record `r` (its first and its last byte).
#[inline(always)]
pub(crate) fn record<T>(r: &T) {
    let p = r as *const T as *const u8;
    line(p);
    line(p.wrapping_add(std::mem::size_of::<T>() - 1));
}

/// Asks for the cache line of `f`.
#[inline(always)]
pub(crate) fn fragment(f: &Fragment) {
    line(f);
}

/// A band's depth and colour buffers: whole rows of `width` pixels from row `y0`.
pub(crate) struct BandPixels<T> {
    pub depth: *const f32,
    pub color: *const T,
    pub width: usize,
    pub y0: usize,
    pub rows: usize,
}

impl<T> BandPixels<T> {
    /// Asks for the depth and colour lines of pixel `i` of the band (inside it).
    #[inline(always)]
    fn pixel(&self, i: usize) {
        line(self.depth.wrapping_add(i));
        line(self.color.wrapping_add(i));
    }

    /// Asks for the lines of the pixel of fragment `f` (in the band).
    #[inline(always)]
    pub fn fragment_pixels(&self, f: &Fragment) {
        let r = (f.y as usize).wrapping_sub(self.y0);
        if r < self.rows {
            self.pixel(r * self.width + f.x as usize);
        }
    }

    /// Asks for the lines at both ends of each row of `t`'s bounding box in the band
    /// (the boxes of the triangles that this is for span one or two lines a row).
    #[inline(always)]
    pub fn triangle_pixels(&self, t: &ScreenTriangle) {
        let [a, b, c] = &t.v;
        let (x0, x1) = (a.x.min(b.x).min(c.x), a.x.max(b.x).max(c.x));
        let (y0, y1) = (a.y.min(b.y).min(c.y), a.y.max(b.y).max(c.y));
        // `as usize` saturates (negative and NaN to 0): only the clamping matters here.
        let last_x = self.width - 1;
        let (cx0, cx1) = ((x0 as usize).min(last_x), (x1 as usize).min(last_x));
        let r0 = (y0 as usize).max(self.y0) - self.y0;
        let r1 = ((y1 as usize).max(self.y0) - self.y0).min(self.rows - 1);
        for r in (r0..=r1).take(MAX_ROWS) {
            let row = r * self.width;
            self.pixel(row + cx0);
            self.pixel(row + cx1);
        }
    }
}
