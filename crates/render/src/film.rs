//! The image plane: tiles rendered in parallel with rayon, stratified and adaptive
//! supersampling per pixel, and the AOV buffers.
//!
//! Every sample's random numbers come from `Rng::for_pixel(x, y, sample, 0)` and each
//! tile writes only its own pixels, so the image is the same for any thread count,
//! tile size and tile order. Each tile counts its rays in its own `Stats`; they are
//! merged at the end.

use crate::aov::Aov;
use crate::integrator::{AovSample, Integrator};
use crate::sampler::pixel_sample;
use crate::stats::Stats;
use crate::{RenderError, RenderOptions, RenderOutput};
use irradia_core::{Image, Ray, Rgb, Rng};
use irradia_scene::camera::CameraRays;
use irradia_scene::Scene;
use rayon::prelude::*;
use std::time::Instant;

#[derive(Clone, Copy, Debug)]
struct Tile {
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
}

struct TileResult {
    colour: Vec<Rgb>,
    aov: Vec<AovSample>,
    stats: Stats,
}

/// The camera ray and random stream of sample `s` of `n` in pixel (x, y): the one
/// place that decides where samples go, shared by the renderer and `trace-pixel`.
pub fn camera_sample(cam: &CameraRays, x: u32, y: u32, s: u32, n: u32) -> (Ray, Rng) {
    let (o, mut rng) = pixel_sample(x, y, s, n);
    if cam.needs_lens_sample() {
        // A thin lens: the aperture point from the sample's stream (pinholes draw none).
        let lens = rng.next_2d();
        return (cam.ray_lens(x as f32 + o.x, y as f32 + o.y, lens), rng);
    }
    (cam.ray(x as f32 + o.x, y as f32 + o.y), rng)
}

/// Renders the scene's image with `integrator`.
pub fn render_with<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    options: &RenderOptions,
) -> Result<RenderOutput, RenderError> {
    let start = Instant::now();
    let (width, height) = (scene.settings.width, scene.settings.height);
    // Checks the size before anything is allocated.
    let mut image = Image::new(width, height)?;
    let mut aov_images: Vec<(Aov, Image)> = options
        .aovs
        .iter()
        .map(|&a| Image::new(width, height).map(|im| (a, im)))
        .collect::<Result<_, _>>()?;
    let want_aov = !aov_images.is_empty();

    let ts = options.tile_size.max(1);
    let mut tiles = Vec::new();
    for y0 in (0..height).step_by(ts as usize) {
        for x0 in (0..width).step_by(ts as usize) {
            tiles.push(Tile {
                x0,
                y0,
                w: ts.min(width - x0),
                h: ts.min(height - y0),
            });
        }
    }
    let cam = scene.camera.rays(width, height);
    let job = || -> Vec<TileResult> {
        tiles
            .par_iter()
            .map(|t| {
                let r = render_tile(integrator, scene, &cam, *t, want_aov);
                if let Some(p) = &options.progress {
                    p((t.w * t.h) as u64);
                }
                r
            })
            .collect()
    };
    let results = match options.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build()
            .map_err(|e| RenderError::Threads(e.to_string()))?
            .install(job),
        None => job(),
    };

    let mut stats = Stats {
        width,
        height,
        max_level: scene.settings.max_depth,
        ..Stats::default()
    };
    let w = width as usize;
    for (t, r) in tiles.iter().zip(&results) {
        stats.merge(&r.stats);
        for j in 0..t.h as usize {
            let row = (t.y0 as usize + j) * w + t.x0 as usize;
            let src = j * t.w as usize;
            image.pixels_mut()[row..row + t.w as usize]
                .copy_from_slice(&r.colour[src..src + t.w as usize]);
            for (a, im) in aov_images.iter_mut() {
                for i in 0..t.w as usize {
                    im.pixels_mut()[row + i] = a.value(&r.aov[src + i]);
                }
            }
        }
    }
    Ok(RenderOutput {
        image,
        aovs: aov_images,
        stats,
        elapsed: start.elapsed(),
    })
}

/// Renders the pixels of the rectangle at (`x0`, `y0`) of `w` x `h` pixels exactly as
/// [`render_with`] renders them (the same samples and adaptive decisions, which depend
/// only on the pixel), row-major, with the rays it traced: image-parallel (sort-first)
/// rendering of screen regions.
pub fn render_region<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
) -> (Vec<Rgb>, Stats) {
    let cam = scene
        .camera
        .rays(scene.settings.width, scene.settings.height);
    let r = render_tile(integrator, scene, &cam, Tile { x0, y0, w, h }, false);
    (r.colour, r.stats)
}

fn render_tile<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    cam: &CameraRays,
    t: Tile,
    want_aov: bool,
) -> TileResult {
    let mut stats = Stats::default();
    let n = (t.w * t.h) as usize;
    let mut colour = Vec::with_capacity(n);
    let mut aov = Vec::with_capacity(if want_aov { n } else { 0 });
    let spp = scene.settings.spp.max(1);
    stats.pixels = n as u64;
    match scene.settings.adaptive_threshold {
        None => {
            for y in t.y0..t.y0 + t.h {
                for x in t.x0..t.x0 + t.w {
                    let mut first = AovSample::default();
                    let mut sum = Rgb::BLACK;
                    for s in 0..spp {
                        let (ray, mut rng) = camera_sample(cam, x, y, s, spp);
                        let mut a = AovSample::default();
                        sum += integrator.sample(&ray, &mut rng, &mut stats, &mut a);
                        if s == 0 {
                            first = a;
                        }
                    }
                    stats.samples += spp as u64;
                    colour.push(sum / spp as f32);
                    if want_aov {
                        aov.push(first);
                    }
                }
            }
        }
        Some(threshold) => adaptive_tile(
            integrator,
            scene,
            cam,
            t,
            spp,
            threshold,
            want_aov,
            &mut stats,
            &mut colour,
            &mut aov,
        ),
    }
    TileResult { colour, aov, stats }
}

/// Adaptive supersampling (lecture: "Adaptive sampling"; Whitted 1980): one sample at
/// every pixel centre, then every pixel whose centre colour differs from a 4-neighbour's
/// by more than `threshold` (in any channel) is re-rendered with `max(spp, 4)`
/// stratified samples. The centre samples of a one-pixel border around the tile are
/// computed too, so the decision does not depend on where tiles end.
#[allow(clippy::too_many_arguments)]
fn adaptive_tile<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    cam: &CameraRays,
    t: Tile,
    spp: u32,
    threshold: f32,
    want_aov: bool,
    stats: &mut Stats,
    colour: &mut Vec<Rgb>,
    aov: &mut Vec<AovSample>,
) {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let bx0 = t.x0.saturating_sub(1);
    let by0 = t.y0.saturating_sub(1);
    let bx1 = (t.x0 + t.w + 1).min(width);
    let by1 = (t.y0 + t.h + 1).min(height);
    let bw = (bx1 - bx0) as usize;
    let mut base = Vec::with_capacity(bw * (by1 - by0) as usize);
    let mut base_aov = Vec::with_capacity(if want_aov { base.capacity() } else { 0 });
    for y in by0..by1 {
        for x in bx0..bx1 {
            let (ray, mut rng) = camera_sample(cam, x, y, 0, 1);
            let mut a = AovSample::default();
            base.push(integrator.sample(&ray, &mut rng, stats, &mut a));
            if want_aov {
                base_aov.push(a);
            }
        }
    }
    let at = |x: u32, y: u32| base[(y - by0) as usize * bw + (x - bx0) as usize];
    let fine = spp.max(4);
    for y in t.y0..t.y0 + t.h {
        for x in t.x0..t.x0 + t.w {
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
                let mut sum = Rgb::BLACK;
                for s in 0..fine {
                    let (ray, mut rng) = camera_sample(cam, x, y, s, fine);
                    let mut a = AovSample::default();
                    sum += integrator.sample(&ray, &mut rng, stats, &mut a);
                }
                stats.samples += fine as u64;
                colour.push(sum / fine as f32);
            } else {
                colour.push(c);
            }
            if want_aov {
                aov.push(base_aov[(y - by0) as usize * bw + (x - bx0) as usize]);
            }
        }
    }
}
