//! Adaptive supersampling (lecture: "Adaptive sampling"; Whitted 1980), the Whitted
//! tracer's way through a tile: one sample at every pixel centre, then every pixel
//! whose centre colour differs from a 4-neighbour's by more than `threshold` (in any
//! channel) is re-rendered with `max(spp, 4)` stratified samples (moved by the pixel
//! filter) instead. The centre samples of a one-pixel border around the tile are
//! computed too, so the decision does not depend on where tiles (or a crop window) end.

use crate::driver::{Tile, TileContext};
use crate::film::FilmPixel;
use crate::integrator::{AovSample, Integrator};
use crate::sampler::{camera_sample, Sampler};
use crate::stats::Stats;
use irradia_core::Rgb;

/// Adds tile `t`'s samples to `pixels` (row-major, the tile's), returning the centre
/// samples' AOV records when `want_aov`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn render_tile<I: Integrator>(
    integrator: &I,
    cx: &TileContext<'_>,
    t: Tile,
    spp: u32,
    threshold: f32,
    want_aov: bool,
    pixels: &mut [FilmPixel],
    stats: &mut Stats,
) -> Vec<AovSample> {
    let (width, height) = (cx.width, cx.height);
    let bx0 = t.x0.saturating_sub(1);
    let by0 = t.y0.saturating_sub(1);
    let bx1 = (t.x0 + t.w + 1).min(width);
    let by1 = (t.y0 + t.h + 1).min(height);
    let bw = (bx1 - bx0) as usize;
    let centre = Sampler::Stratified { spp: 1 };
    let mut base = Vec::with_capacity(bw * (by1 - by0) as usize);
    let mut base_aov = Vec::with_capacity(if want_aov { base.capacity() } else { 0 });
    for y in by0..by1 {
        for x in bx0..bx1 {
            let mut cs = camera_sample(cx.cam, cx.filter, centre, x, y, 0);
            let mut a = AovSample::default();
            base.push(integrator.sample(&cs.ray, &mut cs.rng, stats, &mut a));
            if want_aov {
                base_aov.push(a);
            }
        }
    }
    let at = |x: u32, y: u32| base[(y - by0) as usize * bw + (x - bx0) as usize];
    let fine = spp.max(4);
    let fine_sampler = Sampler::Stratified { spp: fine };
    let mut aov = Vec::with_capacity(if want_aov { pixels.len() } else { 0 });
    let mut px = pixels.iter_mut();
    for y in t.y0..t.y0 + t.h {
        for x in t.x0..t.x0 + t.w {
            let pixel = px.next().expect("one film pixel per tile pixel");
            let c = at(x, y);
            let mut differs = false;
            let neighbours = [
                (x.wrapping_sub(1), y),
                (x + 1, y),
                (x, y.wrapping_sub(1)),
                (x, y + 1),
            ];
            for (nx, ny) in neighbours {
                if nx < width && ny < height {
                    let d = at(nx, ny) - c;
                    if d.r.abs().max(d.g.abs()).max(d.b.abs()) > threshold {
                        differs = true;
                    }
                }
            }
            stats.samples += 1;
            if differs {
                stats.refined_pixels += 1;
                for s in 0..fine {
                    let mut cs = camera_sample(cx.cam, cx.filter, fine_sampler, x, y, s);
                    let mut a = AovSample::default();
                    let l: Rgb = integrator.sample(&cs.ray, &mut cs.rng, stats, &mut a);
                    pixel.add(l, cs.weight);
                }
                stats.samples += fine as u64;
            } else {
                pixel.add(c, 1.0);
            }
            if want_aov {
                aov.push(base_aov[(y - by0) as usize * bw + (x - bx0) as usize]);
            }
        }
    }
    aov
}
