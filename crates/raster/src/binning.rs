//! Parallel rasterization by binning triangles into screen tiles.
//!
//! The screen is cut into bands of [`BAND_ROWS`] full-width rows (tiles that own whole
//! rows, so each is a contiguous piece of the framebuffer that one thread can borrow
//! mutably). Triangles are binned in parallel, batch by batch, into the bands their
//! bounding box touches; then every band draws its triangles in submission order. A
//! pixel is only ever touched by the one band that owns it, in the order the
//! triangles were given, so the image is the same for any number of threads — this is
//! sort-middle inside one machine, as in the lecture's "Sorting Paradigm".

use crate::depth_bounds::DepthBounds;
use crate::depth_snapshot::DepthSnapshot;
use crate::fragment::{
    draw, draw_blended, BlendTarget, ColorTarget, DepthFunc, InterpolatedColor, MaterialColor,
    PhongShader, PixelShader, Unproject,
};
use crate::framebuffer::{ColorBuffer, Framebuffer};
use crate::lighting::{EyeLights, Shading};
use crate::prefetch;
use crate::rasterizer::row_range;
use crate::screen::{Rect, ScreenTriangle};
use crate::texture::Texture;
use crate::tiny::{draw_fragment, Fragment, FRAGMENT_BIT};
use rayon::prelude::*;

/// Rows per band (tile height).
pub const BAND_ROWS: u32 = 32;
/// Triangles binned by one task.
pub(crate) const BATCH: usize = 8192;

/// The fragment stage's settings.
pub(crate) struct FragmentState<'a> {
    pub shading: Shading,
    pub lights: &'a EyeLights,
    pub depth_func: DepthFunc,
    /// For Phong: pixel and depth back to eye space.
    pub unproject: Unproject,
    /// The pipeline's texture table (materials name entries).
    pub textures: &'a [Texture],
    /// Draw the triangles as transparent: blended over the colour buffer, depth
    /// tested but not written ([`crate::transparency`]). Ignored by ID buffers.
    pub blend: bool,
    /// What transparent fragments are blended over where nothing was drawn.
    pub background: Option<[f32; 4]>,
}

/// Draws the triangles of `batches` (in order: batch by batch, each in order) into
/// `fb`, touching only pixels inside `region`.
pub(crate) fn rasterize_batches(
    batches: &[&[ScreenTriangle]],
    fb: &mut Framebuffer,
    region: Rect,
    state: &FragmentState,
) {
    let region = region.intersect(&Rect::full(fb.width(), fb.height()));
    if region.is_empty() {
        return;
    }
    let pieces: Vec<&[ScreenTriangle]> = batches.iter().flat_map(|b| b.chunks(BATCH)).collect();
    let bands = band_count(fb.height());
    let bins: Vec<Vec<Vec<u32>>> = pieces.par_iter().map(|p| bin(p, &region, bands)).collect();
    let bins: Vec<&[Vec<u32>]> = bins.iter().map(|b| b.as_slice()).collect();
    let frags: Vec<&[Fragment]> = vec![&[]; pieces.len()];
    rasterize_binned(&pieces, &frags, &bins, fb, region, state, None);
}

/// The number of bands of a screen `height` rows high.
pub(crate) fn band_count(height: u32) -> usize {
    height.div_ceil(BAND_ROWS) as usize
}

/// Appends triangle `i` to the bins of the bands that rows `y0..=y1` touch.
#[inline(always)]
pub(crate) fn push_to_bands(bins: &mut [Vec<u32>], i: u32, y0: i64, y1: i64) {
    let (first, last) = (
        y0 as usize / BAND_ROWS as usize,
        y1 as usize / BAND_ROWS as usize,
    );
    for bin in &mut bins[first..=last] {
        bin.push(i);
    }
}

/// Draws already binned triangles: `bins[p][band]` lists the triangles of `pieces[p]`
/// that touch `band` inside `region`, and the fragments of `frags[p]` in it (entries
/// with [`FRAGMENT_BIT`] set, made only for the interpolated-colour RGBA8 path). With
/// `snapshot`, each band refreshes its tiles of it when it has drawn its triangles.
pub(crate) fn rasterize_binned(
    pieces: &[&[ScreenTriangle]],
    frags: &[&[Fragment]],
    bins: &[&[Vec<u32>]],
    fb: &mut Framebuffer,
    region: Rect,
    state: &FragmentState,
    snapshot: Option<&DepthSnapshot>,
) {
    let region = region.intersect(&Rect::full(fb.width(), fb.height()));
    if region.is_empty() {
        return;
    }
    let job = Job {
        pieces,
        frags,
        bins,
        region,
        width: fb.width() as usize,
        depth_func: state.depth_func,
        snapshot,
    };
    let depth = &mut fb.depth;
    let phong = PhongShader {
        lights: state.lights,
        unproject: state.unproject,
        textures: state.textures,
    };
    let by_material = MaterialColor {
        lights: state.lights,
        textures: state.textures,
    };
    if state.blend {
        let bg = state.background;
        match (&mut fb.color, state.shading) {
            (ColorBuffer::Id(_), _) => {}
            (ColorBuffer::Rgba8(c), Shading::Phong) => job.run_blended(c, depth, &phong, bg),
            (ColorBuffer::Rgba8(c), _) => job.run_blended(c, depth, &by_material, bg),
            (ColorBuffer::Rgba32F(c), Shading::Phong) => job.run_blended(c, depth, &phong, bg),
            (ColorBuffer::Rgba32F(c), _) => job.run_blended(c, depth, &by_material, bg),
        }
        return;
    }
    let plain = !state.lights.needs_material_fragments();
    match (&mut fb.color, state.shading) {
        (ColorBuffer::Id(c), _) => job.run(c, depth, &InterpolatedColor),
        (ColorBuffer::Rgba8(c), Shading::Phong) => job.run(c, depth, &phong),
        (ColorBuffer::Rgba32F(c), Shading::Phong) => job.run(c, depth, &phong),
        (ColorBuffer::Rgba8(c), _) if !plain => job.run(c, depth, &by_material),
        (ColorBuffer::Rgba32F(c), _) if !plain => job.run(c, depth, &by_material),
        #[cfg(target_arch = "x86_64")]
        (ColorBuffer::Rgba8(c), _) if crate::simd_span::available() => {
            let (func, width) = (state.depth_func, job.width);
            job.run_with(
                c,
                depth,
                |y0, d| DepthBounds::new(d, width, y0),
                |bounds, t, clip, y0, d, c| {
                    // SAFETY: `available()` checked that the CPU has AVX2.
                    unsafe {
                        crate::simd_span::draw_interpolated_rgba8(
                            t, clip, width, y0, d, c, func, bounds,
                        )
                    }
                },
                |f, y0, d, c| draw_fragment(f, width, y0, d, c, func),
            )
        }
        (ColorBuffer::Rgba8(c), _) => {
            let (func, width) = (state.depth_func, job.width);
            job.run_with(
                c,
                depth,
                |_, _| (),
                |_, t, clip, y0, d, c| draw(t, clip, width, y0, d, c, &InterpolatedColor, func),
                |f, y0, d, c| draw_fragment(f, width, y0, d, c, func),
            )
        }
        (ColorBuffer::Rgba32F(c), _) => job.run(c, depth, &InterpolatedColor),
    }
}

/// For each band, the indices into `tris` of the triangles whose pixel bounds meet
/// `region` in that band.
fn bin(tris: &[ScreenTriangle], region: &Rect, bands: usize) -> Vec<Vec<u32>> {
    let mut bins: Vec<Vec<u32>> = vec![Vec::new(); bands];
    for (i, t) in tris.iter().enumerate() {
        let (x0, x1, y0, y1) = row_range(t);
        let x0 = x0.max(region.x0 as i64);
        let x1 = x1.min(region.x1 as i64 - 1);
        let y0 = y0.max(region.y0 as i64);
        let y1 = y1.min(region.y1 as i64 - 1);
        if x0 > x1 || y0 > y1 {
            continue;
        }
        push_to_bands(&mut bins, i as u32, y0, y1);
    }
    bins
}

struct Job<'a> {
    pieces: &'a [&'a [ScreenTriangle]],
    frags: &'a [&'a [Fragment]],
    bins: &'a [&'a [Vec<u32>]],
    region: Rect,
    width: usize,
    depth_func: DepthFunc,
    /// Refreshed band by band after drawing ([`DepthSnapshot::refresh_band`]).
    snapshot: Option<&'a DepthSnapshot>,
}

impl Job<'_> {
    fn run<T: Send, S: PixelShader>(&self, color: &mut [T], depth: &mut [f32], shader: &S)
    where
        [T]: ColorTarget,
    {
        let depth_func = self.depth_func;
        let width = self.width;
        self.run_with(
            color,
            depth,
            |_, _| (),
            |_, t, clip, y0, d, c| draw(t, clip, width, y0, d, c, shader, depth_func),
            |_, _, _, _| unreachable!("fragments are made for the RGBA8 colour path only"),
        )
    }

    /// Draws transparent triangles: blended, depth tested, depth not written.
    fn run_blended<T: Send, S: PixelShader>(
        &self,
        color: &mut [T],
        depth: &mut [f32],
        shader: &S,
        background: Option<[f32; 4]>,
    ) where
        [T]: BlendTarget,
    {
        let depth_func = self.depth_func;
        let width = self.width;
        self.run_with(
            color,
            depth,
            |_, _| (),
            |_, t, clip, y0, d, c| {
                draw_blended(t, clip, width, y0, d, c, shader, depth_func, background)
            },
            |_, _, _, _| unreachable!("transparent triangles are not made into fragments"),
        )
    }

    /// Draws every band's triangles in order with `draw_one(band_state, triangle, clip,
    /// band_y0, band_depth, band_colour)`, bands in parallel; `init(band_y0,
    /// band_depth)` makes each band's state before its first triangle;
    /// `draw_fragment(fragment, band_y0, band_depth, band_colour)` draws the fragments
    /// of tiny triangles ([`crate::tiny`]) in their place in the order.
    fn run_with<T: Send, B>(
        &self,
        color: &mut [T],
        depth: &mut [f32],
        init: impl Fn(u32, &[f32]) -> B + Sync,
        draw_one: impl Fn(&mut B, &ScreenTriangle, &Rect, u32, &mut [f32], &mut [T]) + Sync,
        draw_fragment: impl Fn(&Fragment, u32, &mut [f32], &mut [T]) + Sync,
    ) {
        let band_len = self.width * BAND_ROWS as usize;
        color
            .par_chunks_mut(band_len)
            .zip(depth.par_chunks_mut(band_len))
            .enumerate()
            .for_each(|(band, (c, d))| {
                let y0 = band as u32 * BAND_ROWS;
                let rows = (d.len() / self.width) as u32;
                let clip = self
                    .region
                    .intersect(&Rect::new(0, y0, self.width as u32, y0 + rows));
                if clip.is_empty() {
                    return;
                }
                let mut band_state = init(y0, d);
                let pixels = prefetch::BandPixels {
                    depth: d.as_ptr(),
                    color: c.as_ptr(),
                    width: self.width,
                    y0: y0 as usize,
                    rows: rows as usize,
                };
                for ((piece, frags), bins) in self.pieces.iter().zip(self.frags).zip(self.bins) {
                    let list = &bins[band];
                    for (j, &i) in list.iter().enumerate() {
                        // Two stages ahead: the record, then its pixels (prefetch.rs).
                        if let Some(&far) = list.get(j + prefetch::FAR) {
                            if far & FRAGMENT_BIT == 0 {
                                prefetch::triangle(&piece[far as usize]);
                            } else {
                                prefetch::fragment(&frags[(far & !FRAGMENT_BIT) as usize]);
                            }
                        }
                        if let Some(&near) = list.get(j + prefetch::NEAR) {
                            if near & FRAGMENT_BIT == 0 {
                                pixels.triangle_pixels(&piece[near as usize]);
                            } else {
                                pixels.fragment_pixels(&frags[(near & !FRAGMENT_BIT) as usize]);
                            }
                        }
                        if i & FRAGMENT_BIT != 0 {
                            draw_fragment(&frags[(i & !FRAGMENT_BIT) as usize], y0, d, c);
                        } else {
                            draw_one(&mut band_state, &piece[i as usize], &clip, y0, d, c);
                        }
                    }
                }
                if let Some(s) = self.snapshot {
                    s.refresh_band(y0, d);
                }
            });
    }
}
