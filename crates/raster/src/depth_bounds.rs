//! Coarse depth bounds for rejecting hidden triangles before they are scanned: the
//! largest stored depth of every 8x8-pixel tile of a band (one level of a hierarchical
//! z-buffer, Greene, Kass and Miller, "Hierarchical Z-Buffer Visibility", SIGGRAPH
//! 1993; the per-tile depth range test of tiled rasterizers, Abrash, "Rasterization on
//! Larrabee", 2009).
//!
//! With the depth test `Less`, a triangle whose smallest fragment depth is at least the
//! largest stored depth of every tile its bounding box touches cannot pass anywhere,
//! so it is skipped (`LessEqual`: strictly larger). The test is exact, never an
//! approximation: [`DepthBounds::triangle_min_depth`] takes the minimum of the
//! fragment depth *as the rasterizer computes it* (the f64 plane of `Setup`, rounded
//! to f32) over the four corners of the scanned pixel block. That computed depth is
//! monotone in x and in y separately (each of its floating-point operations — a
//! product with a fixed coefficient, a sum, the rounding to f32 — is monotone in its
//! argument), so no pixel of the block has a smaller computed depth than the
//! smallest corner. The tile bounds only ever overestimate the stored depth: a pixel
//! that passes `Less` or `LessEqual` only decreases, the bounds are recomputed from the
//! buffer every [`DepthBounds::REFRESH`] triangles, and a NaN stored depth (which no
//! fragment can pass) is ignored. Images are therefore identical with and without
//! the test; only the work for hidden triangles goes away. `Always` does not use it.

use crate::fragment::DepthFunc;
use crate::rasterizer::Setup;

/// Tile edge in pixels.
const TILE: usize = 8;

/// The largest stored depth of each 8x8 tile of one band of rows.
pub(crate) struct DepthBounds {
    width: usize,
    tiles_x: usize,
    band_y0: u32,
    max: Vec<f32>,
    /// Triangles drawn since the bounds were last computed.
    drawn: u32,
}

impl DepthBounds {
    /// Triangles between recomputations of the bounds (a band's bounds cost about as
    /// much to recompute as drawing a few dozen triangles).
    pub const REFRESH: u32 = 1024;

    /// The bounds of `depth`, whole rows of `width` pixels starting at row `band_y0`.
    pub fn new(depth: &[f32], width: usize, band_y0: u32) -> Self {
        let tiles_x = width.div_ceil(TILE);
        let rows = depth.len() / width.max(1);
        let mut b = Self {
            width,
            tiles_x,
            band_y0,
            max: vec![f32::NEG_INFINITY; tiles_x * rows.div_ceil(TILE)],
            drawn: 0,
        };
        b.recompute(depth);
        b
    }

    fn recompute(&mut self, depth: &[f32]) {
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx") && self.width % TILE == 0 {
            // SAFETY: AVX was detected just above.
            unsafe { self.recompute_avx(depth) };
            self.drawn = 0;
            return;
        }
        self.max.fill(f32::NEG_INFINITY);
        for (y, row) in depth.chunks_exact(self.width).enumerate() {
            let tiles = &mut self.max[(y / TILE) * self.tiles_x..][..self.tiles_x];
            for (m, span) in tiles.iter_mut().zip(row.chunks(TILE)) {
                // `f32::max` ignores NaN (a pixel no fragment can pass).
                *m = span.iter().fold(*m, |a, &z| a.max(z));
            }
        }
        self.drawn = 0;
    }

    /// [`Self::recompute`] eight pixels at a time (rows a multiple of 8 pixels wide):
    /// the same maxima, since `max` is exact and `_mm256_max_ps(z, m)` keeps `m` when
    /// `z` is NaN, as `f32::max` does.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn recompute_avx(&mut self, depth: &[f32]) {
        use std::arch::x86_64::*;
        let rows = depth.len() / self.width;
        for ty in 0..rows.div_ceil(TILE) {
            let (r0, r1) = (ty * TILE, ((ty + 1) * TILE).min(rows));
            for tx in 0..self.tiles_x {
                let mut m = _mm256_set1_ps(f32::NEG_INFINITY);
                for y in r0..r1 {
                    let at = y * self.width + tx * TILE;
                    m = _mm256_max_ps(_mm256_loadu_ps(depth[at..at + TILE].as_ptr()), m);
                }
                let mut lanes = [0f32; 8];
                _mm256_storeu_ps(lanes.as_mut_ptr(), m);
                self.max[ty * self.tiles_x + tx] =
                    lanes.iter().fold(f32::NEG_INFINITY, |a, &z| a.max(z));
            }
        }
    }

    /// Counts a drawn triangle and recomputes the bounds every [`Self::REFRESH`].
    #[inline]
    pub fn count_drawn(&mut self, depth: &[f32]) {
        self.drawn += 1;
        if self.drawn >= Self::REFRESH {
            self.recompute(depth);
        }
    }

    /// The largest stored depth over the tiles that pixels `x0..=x1` x `y0..=y1`
    /// (screen rows, inside the band) touch.
    #[inline]
    pub fn max_over(&self, x0: i64, x1: i64, y0: i64, y1: i64) -> f32 {
        let (tx0, tx1) = (x0 as usize / TILE, x1 as usize / TILE);
        let ty0 = (y0 as usize - self.band_y0 as usize) / TILE;
        let ty1 = (y1 as usize - self.band_y0 as usize) / TILE;
        let mut m = f32::NEG_INFINITY;
        for ty in ty0..=ty1 {
            for &t in &self.max[ty * self.tiles_x + tx0..=ty * self.tiles_x + tx1] {
                m = m.max(t);
            }
        }
        m
    }

    /// The smallest depth the rasterizer computes for any pixel of the block
    /// `x0..=x1` x `y0..=y1` of triangle `s` (see the module notes).
    #[inline]
    pub fn triangle_min_depth(s: &Setup, x0: i64, x1: i64, y0: i64, y1: i64) -> f32 {
        let (r0, r1) = (s.depth_row(y0 as u32), s.depth_row(y1 as u32));
        let (x0, x1) = (x0 as u32, x1 as u32);
        s.depth_in_row(r0, x0)
            .min(s.depth_in_row(r0, x1))
            .min(s.depth_in_row(r1, x0))
            .min(s.depth_in_row(r1, x1))
    }

    /// Whether no pixel of the block can pass `func` (the triangle can be skipped).
    /// Planes with a non-finite coefficient (where the monotonicity argument breaks
    /// down at infinities) are never skipped.
    #[inline]
    pub fn hidden(&self, s: &Setup, func: DepthFunc, x0: i64, x1: i64, y0: i64, y1: i64) -> bool {
        if !(s.zc.is_finite() && s.zx.is_finite() && s.zy.is_finite()) {
            return false;
        }
        match func {
            DepthFunc::Less => {
                Self::triangle_min_depth(s, x0, x1, y0, y1) >= self.max_over(x0, x1, y0, y1)
            }
            DepthFunc::LessEqual => {
                Self::triangle_min_depth(s, x0, x1, y0, y1) > self.max_over(x0, x1, y0, y1)
            }
            DepthFunc::Always => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_are_the_tile_maxima_and_ignore_nan() {
        // 20 wide: the scalar path; 24 wide: the AVX path where available.
        for w in [20usize, 24] {
            let rows = 11usize;
            let mut depth: Vec<f32> = (0..w * rows).map(|i| (i % 37) as f32 / 37.0).collect();
            depth[3] = f32::NAN;
            depth[w * 9 + 17] = f32::NAN;
            let b = DepthBounds::new(&depth, w, 64);
            let tiles_x = w.div_ceil(8);
            for ty in 0..2 {
                for tx in 0..tiles_x {
                    let mut m = f32::NEG_INFINITY;
                    for y in ty * 8..((ty + 1) * 8).min(rows) {
                        for x in tx * 8..((tx + 1) * 8).min(w) {
                            if !depth[y * w + x].is_nan() {
                                m = m.max(depth[y * w + x]);
                            }
                        }
                    }
                    assert_eq!(b.max[ty * tiles_x + tx], m, "width {w}, tile ({tx}, {ty})");
                }
            }
            // Rows 64.. of the screen are rows 0.. of the band.
            let all = b.max.iter().fold(f32::NEG_INFINITY, |a, &m| a.max(m));
            assert_eq!(b.max_over(0, w as i64 - 1, 64, 74), all);
            assert_eq!(b.max_over(9, 9, 73, 73), b.max[tiles_x + 1]);
        }
    }
}
