//! The fused paths' depth snapshot, refreshed by each band as it finishes a group: the
//! largest stored depth of every 8x8 tile of the screen ([`crate::depth_bounds`]'s
//! tiles, one level of a hierarchical z-buffer, Greene, Kass and Miller 1993), which
//! the geometry stage reads to drop the next groups' hidden triangles before lighting
//! them ([`crate::geometry_stage::GeometryStage::with_occlusion`]).
//!
//! A band writes its own tiles ([`DepthSnapshot::refresh_band`]) right after drawing
//! its triangles of a group, while its depth rows are still in the cache, instead of a
//! pass of its own over the whole depth buffer between the groups (which read it back
//! from memory, and was one more point where the threads waited for each other). The
//! bands share the snapshot, each writing only its own rows of tiles, so every tile is
//! an atomic value (relaxed loads and stores: plain moves on x86). The bounds are exact
//! overestimates of the depths stored when a later group's triangle is drawn (with
//! `Less` and `LessEqual` stored depths only decrease), so the test drops only
//! triangles that the rasterizer would not draw.

use crate::depth_bounds::{DepthBounds, TILE};
use crate::fragment::DepthFunc;
use crate::rasterizer::Setup;
use std::sync::atomic::{AtomicU32, Ordering::Relaxed};

/// Tile maxima of a whole depth buffer, shared between the bands that refresh them and
/// the geometry stage that tests against them.
pub(crate) struct DepthSnapshot {
    width: usize,
    tiles_x: usize,
    /// The bits of each tile's largest stored depth (never NaN: a tile of NaN only is
    /// negative infinity), row by row of tiles.
    max: Vec<AtomicU32>,
    /// Whether the CPU has AVX and the width is a multiple of the tile
    /// ([`DepthBounds::tile_max`]).
    avx: bool,
}

impl DepthSnapshot {
    /// A snapshot of a `width` x `height` depth buffer; every tile must be refreshed
    /// before it is read ([`Self::refresh_band`]).
    pub fn new(width: u32, height: u32) -> Self {
        let (width, height) = (width as usize, height as usize);
        let tiles_x = width.div_ceil(TILE);
        Self {
            width,
            tiles_x,
            max: (0..tiles_x * height.div_ceil(TILE))
                .map(|_| AtomicU32::new(f32::NEG_INFINITY.to_bits()))
                .collect(),
            avx: DepthBounds::avx_for(width),
        }
    }

    /// Recomputes the tiles of the band `depth` (whole rows starting at screen row
    /// `y0`, a multiple of the tile height) from its stored depths.
    pub fn refresh_band(&self, y0: u32, depth: &[f32]) {
        let rows = depth.len() / self.width.max(1);
        let ty0 = y0 as usize / TILE;
        for ty in 0..rows.div_ceil(TILE) {
            let row = &self.max[(ty0 + ty) * self.tiles_x..(ty0 + ty + 1) * self.tiles_x];
            for (tx, m) in row.iter().enumerate() {
                let z = DepthBounds::tile_max(depth, self.width, self.avx, tx, ty);
                m.store(z.to_bits(), Relaxed);
            }
        }
    }

    /// Whether no pixel of the block `x0..=x1` x `y0..=y1` of `s` can pass `func`
    /// against a depth buffer whose stored depths are at most those the tiles were
    /// computed from ([`DepthBounds::hides`] on these tiles). `s` needs its depth plane.
    #[inline]
    pub fn hides(&self, s: &Setup, func: DepthFunc, x0: i64, x1: i64, y0: i64, y1: i64) -> bool {
        if !(s.zc.is_finite() && s.zx.is_finite() && s.zy.is_finite()) {
            return false;
        }
        let z = || DepthBounds::triangle_min_depth(s, x0, x1, y0, y1);
        match func {
            DepthFunc::Less => z() >= self.max_over(x0, x1, y0, y1),
            DepthFunc::LessEqual => z() > self.max_over(x0, x1, y0, y1),
            DepthFunc::Always => false,
        }
    }

    /// The largest bound over the tiles that pixels `x0..=x1` x `y0..=y1` touch.
    #[inline]
    fn max_over(&self, x0: i64, x1: i64, y0: i64, y1: i64) -> f32 {
        let (tx0, tx1) = (x0 as usize / TILE, x1 as usize / TILE);
        let (ty0, ty1) = (y0 as usize / TILE, y1 as usize / TILE);
        let mut m = f32::NEG_INFINITY;
        for ty in ty0..=ty1 {
            for t in &self.max[ty * self.tiles_x + tx0..=ty * self.tiles_x + tx1] {
                let t = f32::from_bits(t.load(Relaxed));
                m = if t > m { t } else { m };
            }
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Refreshed band by band, the snapshot's tiles are the maxima of the whole
    /// buffer's tiles (fails when a band writes its tiles one row of tiles off).
    #[test]
    fn bands_refresh_their_own_tiles() {
        let (w, h) = (24usize, 40usize);
        let depth: Vec<f32> = (0..w * h)
            .map(|i| ((i * 7919) % 101) as f32 / 101.0)
            .collect();
        let snap = DepthSnapshot::new(w as u32, h as u32);
        for (band, rows) in depth.chunks(w * 16).enumerate() {
            snap.refresh_band(band as u32 * 16, rows);
        }
        for ty in 0..h / TILE {
            for tx in 0..w / TILE {
                let mut m = f32::NEG_INFINITY;
                for y in ty * TILE..(ty + 1) * TILE {
                    for x in tx * TILE..(tx + 1) * TILE {
                        m = m.max(depth[y * w + x]);
                    }
                }
                let (x, y) = ((tx * TILE) as i64, (ty * TILE) as i64);
                assert_eq!(snap.max_over(x, x + 7, y, y + 7), m, "tile ({tx}, {ty})");
            }
        }
    }
}
