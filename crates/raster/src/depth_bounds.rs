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
//! to f32) over the corners of the scanned pixel block. That computed depth is
//! monotone in x and in y separately (each of its floating-point operations — a
//! product with a fixed coefficient, a sum, the rounding to f32 — is monotone in its
//! argument), so no pixel of the block has a smaller computed depth than the
//! smallest corner, which is the corner the plane's slopes point away from. The tile bounds only ever overestimate the stored depth: a pixel
//! that passes `Less` or `LessEqual` only decreases, and the bounds are read from the
//! buffer when a band starts and again after every [`DepthBounds::REFRESH`] drawn
//! triangles; a NaN stored depth (which no fragment can
//! pass) is ignored. Images are therefore identical with and without
//! the test; only the work for hidden triangles goes away. `Always` does not use it.

use crate::fragment::DepthFunc;
use crate::rasterizer::Setup;

/// Tile edge in pixels.
pub(crate) const TILE: usize = 8;

/// The largest stored depth of each 8x8 tile of one band of rows.
pub(crate) struct DepthBounds {
    width: usize,
    tiles_x: usize,
    band_y0: u32,
    max: Vec<f32>,
    /// Triangles drawn since the bounds were last computed.
    drawn: u32,
    /// Blocks of eight pixels that the triangles asked about before the bounds were
    /// computed would scan.
    asked: i64,
    /// Whether the warm-up and the probation apply (off only in tests, to test every
    /// triangle).
    adaptive: bool,
    /// Whether `max` holds the bounds.
    ready: bool,
    /// Tests answered from the bounds, and how many of them found the triangle hidden.
    tested: u32,
    rejected: u32,
    /// Whether the CPU has AVX (for [`DepthBounds::tile_avx`]).
    avx: bool,
}

impl DepthBounds {
    /// Triangles drawn between recomputations of the bounds (which make them tight
    /// again: the stored depths they bound only decrease).
    pub const REFRESH: u32 = 1024;

    /// Tests are answered "not hidden" without looking until the triangles asked about
    /// would scan this many blocks of eight pixels in all: computing a band's bounds
    /// (640 tiles of 8x8 for a band of 32 rows of 1280) costs about as much as
    /// scanning that many blocks, so a band drawing little (or tiny triangles, as in
    /// the gyroid workload) does not pay for reading its whole depth.
    pub const WARM_UP_BLOCKS: i64 = 2048;

    /// After this many tests, a band that found fewer than a quarter of its triangles
    /// hidden (few layers of depth, as in the gyroid workload) stops testing.
    pub const PROBATION: u32 = 64;

    /// Bounds for the band `depth` (whole rows of `width` pixels starting at screen row
    /// `band_y0`); computed once enough work has asked ([`Self::WARM_UP_BLOCKS`]).
    pub fn new(depth: &[f32], width: usize, band_y0: u32) -> Self {
        let tiles_x = width.div_ceil(TILE);
        let rows = depth.len() / width.max(1);
        let avx = Self::avx_for(width);
        Self {
            width,
            tiles_x,
            band_y0,
            max: vec![f32::NEG_INFINITY; tiles_x * rows.div_ceil(TILE)],
            drawn: 0,
            asked: 0,
            adaptive: true,
            ready: false,
            tested: 0,
            rejected: 0,
            avx,
        }
    }

    /// Bounds that test every triangle asked about, from the first (for tests).
    #[cfg(test)]
    pub fn always_on(mut self) -> Self {
        self.adaptive = false;
        self
    }

    fn recompute(&mut self, depth: &[f32]) {
        for ty in 0..self.max.len() / self.tiles_x {
            for tx in 0..self.tiles_x {
                self.max[ty * self.tiles_x + tx] = self.tile(depth, tx, ty);
            }
        }
        self.drawn = 0;
    }

    /// Whether tiles of rows `width` pixels wide are computed eight pixels at a time
    /// ([`Self::tile_max`]): the CPU has AVX and the width is a multiple of the tile.
    pub(crate) fn avx_for(width: usize) -> bool {
        #[cfg(target_arch = "x86_64")]
        return std::is_x86_feature_detected!("avx") && width.is_multiple_of(TILE);
        #[cfg(not(target_arch = "x86_64"))]
        false
    }

    /// The largest stored depth of tile (`tx`, `ty`) of the band `depth`, ignoring NaN
    /// (a pixel no fragment can pass); negative infinity when all are NaN.
    fn tile(&self, depth: &[f32], tx: usize, ty: usize) -> f32 {
        Self::tile_max(depth, self.width, self.avx, tx, ty)
    }

    /// [`Self::tile`] of the band `depth` of rows `width` pixels wide, with AVX when
    /// `avx` ([`Self::avx_for`]).
    pub(crate) fn tile_max(depth: &[f32], width: usize, avx: bool, tx: usize, ty: usize) -> f32 {
        let rows = depth.len() / width;
        let (r0, r1) = (ty * TILE, ((ty + 1) * TILE).min(rows));
        let (c0, c1) = (tx * TILE, ((tx + 1) * TILE).min(width));
        #[cfg(target_arch = "x86_64")]
        if avx {
            // SAFETY: `avx` says the CPU has AVX; the tile is a whole 8-pixel span of
            // rows r0..r1 (the width is a multiple of 8).
            return unsafe { Self::tile_avx(depth, width, r0, r1, c0) };
        }
        let _ = avx;
        let mut m = f32::NEG_INFINITY;
        for y in r0..r1 {
            // `f32::max` ignores NaN.
            m = depth[y * width + c0..y * width + c1]
                .iter()
                .fold(m, |a, &z| a.max(z));
        }
        m
    }

    /// [`Self::tile`] for a full 8-pixel-wide tile, eight pixels at a time: the same
    /// value, since `max` is exact and `_mm256_max_ps(z, m)` keeps `m` when `z` is NaN.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    unsafe fn tile_avx(depth: &[f32], width: usize, r0: usize, r1: usize, c0: usize) -> f32 {
        use std::arch::x86_64::*;
        let mut m = _mm256_set1_ps(f32::NEG_INFINITY);
        for y in r0..r1 {
            let at = y * width + c0;
            m = _mm256_max_ps(_mm256_loadu_ps(depth[at..at + TILE].as_ptr()), m);
        }
        let m = _mm_max_ps(_mm256_castps256_ps128(m), _mm256_extractf128_ps::<1>(m));
        let m = _mm_max_ps(m, _mm_movehl_ps(m, m));
        let m = _mm_max_ss(m, _mm_shuffle_ps::<1>(m, m));
        _mm_cvtss_f32(m)
    }

    /// Whether the band has stopped testing: after [`Self::PROBATION`] tests that
    /// found fewer than a quarter of the triangles hidden (for good: the counts stop
    /// there). Its bounds are then no longer recomputed either.
    #[inline(always)]
    fn retired(&self) -> bool {
        self.adaptive && self.tested >= Self::PROBATION && self.rejected * 4 < self.tested
    }

    /// Counts a drawn triangle; every [`Self::REFRESH`] the bounds are recomputed
    /// (while the band still tests).
    #[inline]
    pub fn count_drawn(&mut self, depth: &[f32]) {
        self.drawn += 1;
        if self.ready && self.drawn >= Self::REFRESH && !self.retired() {
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
                // Bounds are never NaN (a tile of NaN only is negative infinity), so a
                // plain comparison (one `maxss`) does what `f32::max` does.
                m = if t > m { t } else { m };
            }
        }
        m
    }

    /// The smallest depth the rasterizer computes for any pixel of the block
    /// `x0..=x1` x `y0..=y1` of triangle `s` (see the module notes): its depth at the
    /// corner where the plane is lowest (left or right by the sign of `zx`, top or
    /// bottom by that of `zy`). The computed depth is monotone in x and in y
    /// separately, rising with the coefficient's sign, so this is the value the least
    /// of the four corners' depths would be, for one evaluation of the plane instead
    /// of four.
    #[inline(always)]
    pub fn triangle_min_depth(s: &Setup, x0: i64, x1: i64, y0: i64, y1: i64) -> f32 {
        let y = if s.zy > 0.0 { y0 } else { y1 };
        let x = if s.zx > 0.0 { x0 } else { x1 };
        s.depth_in_row(s.depth_row(y as u32), x as u32)
    }

    /// Whether no pixel of the block `x0..=x1` x `y0..=y1` of `s` (`blocks` blocks of
    /// eight pixels to scan) can pass `func` against the band `depth` (the triangle
    /// can be skipped). Planes with a
    /// non-finite coefficient (where the monotonicity argument breaks down at
    /// infinities) are never skipped.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    #[allow(clippy::too_many_arguments)]
    pub fn hidden(
        &mut self,
        depth: &[f32],
        s: &Setup,
        func: DepthFunc,
        x0: i64,
        x1: i64,
        y0: i64,
        y1: i64,
        blocks: i64,
    ) -> bool {
        if !self.ready {
            self.asked += blocks;
            if (self.adaptive && self.asked < Self::WARM_UP_BLOCKS) || func == DepthFunc::Always {
                return false;
            }
            self.recompute(depth);
            self.ready = true;
        }
        if self.retired() {
            return false;
        }
        if !(s.zc.is_finite() && s.zx.is_finite() && s.zy.is_finite()) {
            return false;
        }
        let z = || Self::triangle_min_depth(s, x0, x1, y0, y1);
        let hidden = match func {
            DepthFunc::Less => z() >= self.max_over(x0, x1, y0, y1),
            DepthFunc::LessEqual => z() > self.max_over(x0, x1, y0, y1),
            DepthFunc::Always => false,
        };
        self.tested += 1;
        self.rejected += hidden as u32;
        hidden
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::screen::{ScreenTriangle, ScreenVertex};

    /// The depth at the one corner `triangle_min_depth` picks is the least computed
    /// depth of every pixel of the block, for random planes and blocks (fails when the
    /// corner is picked the other way in x or in y).
    #[test]
    fn min_depth_is_the_least_of_every_pixel_of_the_block() {
        let mut seed = 0x2545_F491_4F6C_DD1Du64;
        let mut r = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let mut checked = 0;
        for _ in 0..3000 {
            let v = [0; 3].map(|_| ScreenVertex {
                x: r() * 60.0,
                y: r() * 40.0,
                z: r(),
                inv_w: 1.0,
                ..Default::default()
            });
            let t = ScreenTriangle {
                v,
                ..Default::default()
            };
            let Some(s) = Setup::new(&t) else { continue };
            let (x0, y0) = ((r() * 50.0) as i64, (r() * 30.0) as i64);
            let (x1, y1) = (x0 + (r() * 10.0) as i64, y0 + (r() * 10.0) as i64);
            let mut least = f32::INFINITY;
            for y in y0..=y1 {
                let row = s.depth_row(y as u32);
                for x in x0..=x1 {
                    least = least.min(s.depth_in_row(row, x as u32));
                }
            }
            assert_eq!(
                DepthBounds::triangle_min_depth(&s, x0, x1, y0, y1),
                least,
                "block ({x0}..={x1}, {y0}..={y1})"
            );
            checked += 1;
        }
        assert!(checked > 2000, "{checked} triangles");
    }

    #[test]
    fn bounds_are_the_tile_maxima_and_ignore_nan() {
        // 20 wide: the scalar path; 24 wide: the AVX path where available.
        for w in [20usize, 24] {
            let rows = 11usize;
            let mut depth: Vec<f32> = (0..w * rows).map(|i| (i % 37) as f32 / 37.0).collect();
            depth[3] = f32::NAN;
            depth[w * 9 + 17] = f32::NAN;
            let mut b = DepthBounds::new(&depth, w, 64);
            b.recompute(&depth);
            b.ready = true;
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
                    let (x, y) = (tx as i64 * 8, 64 + ty as i64 * 8);
                    assert_eq!(b.max_over(x, x, y, y), m, "width {w}, tile ({tx}, {ty})");
                }
            }
            // Rows 64.. of the screen are rows 0.. of the band.
            let all = b.max.iter().fold(f32::NEG_INFINITY, |a, &m| a.max(m));
            assert_eq!(b.max_over(0, w as i64 - 1, 64, 74), all);
            assert_eq!(b.max_over(9, 9, 73, 73), b.max[tiles_x + 1]);
            // Recomputed after REFRESH drawn triangles.
            depth.iter_mut().for_each(|z| *z *= 0.5);
            for _ in 0..DepthBounds::REFRESH {
                b.count_drawn(&depth);
            }
            assert_eq!(b.max_over(0, w as i64 - 1, 64, 74), all * 0.5);
        }
    }
}
