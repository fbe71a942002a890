//! The driver every integrator plugs into (pbrt-v4's `ImageTileIntegrator`): the
//! film's window cut into tiles rendered in parallel with rayon, in progressive passes
//! of samples until a sample budget, a time budget or a target error is reached, with
//! periodic checkpoints of the film so that an interrupted render resumes to exactly the
//! same result, AOVs of each pixel's first sample, and progress reports.
//!
//! Sample `i` of pixel `(x, y)` is placed by the [`Sampler`] from (pixel, i) alone, moved
//! by the pixel filter ([`crate::filter`]), and each pixel adds its samples in order into
//! its own f64 sums ([`FilmPixel::add`]); so the image depends neither on the thread
//! count, the tile size or the crop window, nor on how the samples were split into
//! passes or sessions. Each tile counts its rays in its own [`Stats`]; they are merged
//! after each pass.

use crate::adaptive;
use crate::aov::Aov;
use crate::film::{Film, FilmPixel};
use crate::filter::FilterSampler;
use crate::integrator::{AovSample, Integrator};
use crate::sampler::{camera_sample, Sampler};
use crate::stats::Stats;
use irradia_core::{Image, Rgb};
use irradia_scene::camera::CameraRays;
use irradia_scene::{CropWindow, Scene};
use rayon::prelude::*;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// When to stop and where to save.
#[derive(Clone, Debug, Default)]
pub struct ProgressiveOptions {
    /// Samples per pixel to reach (counting samples already in a resumed film).
    pub spp: u32,
    /// Stop after the pass in which this much time has passed.
    pub time_limit: Option<Duration>,
    /// Stop when the film's relative error falls to this value.
    pub target_error: Option<f64>,
    /// Write the film here every `checkpoint_interval` and at the end.
    pub checkpoint: Option<PathBuf>,
    pub checkpoint_interval: Duration,
    /// Selects an independent family of random streams (0 for the default image) for
    /// the independent sampler.
    pub seed: u32,
}

/// Which sampler places the samples (the seed and sample count come from the
/// [`ProgressiveOptions`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SamplerKind {
    /// [`Sampler::Stratified`] over the target sample count.
    Stratified,
    /// [`Sampler::Independent`] with the options' seed.
    Independent,
}

/// How the driver runs an integrator (what does not depend on the budget).
#[derive(Clone, Debug)]
pub struct DriverSetup {
    pub sampler: SamplerKind,
    /// Adaptive supersampling threshold ([`adaptive`]): all samples in one pass.
    pub adaptive_threshold: Option<f32>,
    /// Side of the square tiles, in pixels.
    pub tile_size: u32,
    /// AOV images to produce (from each pixel's sample 0).
    pub aovs: Vec<Aov>,
    /// Tags checkpoints ([`crate::film::fingerprint`]).
    pub fingerprint: u64,
}

/// Where a render stands, reported after every pass.
#[derive(Clone, Copy, Debug)]
pub struct PassReport {
    pub samples: u32,
    pub target_samples: u32,
    pub relative_error: f64,
    pub elapsed: Duration,
}

/// Why the render stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    Samples,
    Time,
    TargetError,
}

/// A finished (or stopped) render.
#[derive(Debug)]
pub struct Rendered {
    pub film: Film,
    /// Raw AOV images of the film's window, in the order they were asked for.
    pub aovs: Vec<(Aov, Image)>,
    pub stats: Stats,
    pub stop: StopReason,
    pub elapsed: Duration,
}

/// A rectangle of pixels of the image.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Tile {
    pub x0: u32,
    pub y0: u32,
    pub w: u32,
    pub h: u32,
}

/// What a tile sees of the render.
pub(crate) struct TileContext<'a> {
    pub cam: &'a CameraRays,
    pub filter: &'a FilterSampler,
    pub sampler: Sampler,
    /// The whole image's size (adaptive sampling looks at neighbours outside a crop).
    pub width: u32,
    pub height: u32,
}

struct TileResult {
    pixels: Vec<FilmPixel>,
    aov: Vec<AovSample>,
    stats: Stats,
}

fn tiles_of(window: CropWindow, size: u32) -> Vec<Tile> {
    let ts = size.max(1);
    let mut tiles = Vec::new();
    let (x1, y1) = (window.x + window.width, window.y + window.height);
    for y0 in (window.y..y1).step_by(ts as usize) {
        for x0 in (window.x..x1).step_by(ts as usize) {
            tiles.push(Tile {
                x0,
                y0,
                w: ts.min(x1 - x0),
                h: ts.min(y1 - y0),
            });
        }
    }
    tiles
}

/// Renders (or continues rendering into `film`) until a stop condition holds.
/// `on_tile` is called from the worker threads with the pixel-samples each tile
/// finished; `on_pass` after every pass.
pub fn run<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    setup: &DriverSetup,
    options: &ProgressiveOptions,
    mut film: Film,
    on_tile: &(dyn Fn(u64) + Sync),
    mut on_pass: impl FnMut(&PassReport, &Film),
) -> std::io::Result<Rendered> {
    let start = Instant::now();
    let s = &scene.settings;
    let window = film.window();
    let tiles = tiles_of(window, setup.tile_size);
    let cam = scene.camera.rays(s.width, s.height);
    let filter = FilterSampler::new(s.filter);
    let want_aov = !setup.aovs.is_empty();
    let mut aov = vec![AovSample::default(); if want_aov { film.pixels().len() } else { 0 }];
    let mut stats = Stats {
        width: s.width,
        height: s.height,
        max_level: s.max_depth,
        ..Stats::default()
    };
    let sampler = match setup.sampler {
        SamplerKind::Stratified => Sampler::Stratified { spp: options.spp },
        SamplerKind::Independent => Sampler::Independent { seed: options.seed },
    };
    let cx = TileContext {
        cam: &cam,
        filter: &filter,
        sampler,
        width: s.width,
        height: s.height,
    };
    // A resumed film has its sample 0 already: its AOVs are traced on their own.
    if want_aov && film.samples() > 0 {
        let sink = Mutex::new(Sink {
            film: &mut film,
            aov: &mut aov,
            stats: &mut stats,
        });
        sweep(integrator, &cx, setup, &tiles, &sink, 0, 0, true, on_tile);
    }
    let mut last_checkpoint = Instant::now();
    let mut pass = 1u32;
    let stop = loop {
        if film.samples() >= options.spp {
            break StopReason::Samples;
        }
        if let Some(t) = options.target_error {
            if film.relative_error() <= t {
                break StopReason::TargetError;
            }
        }
        if let Some(limit) = options.time_limit {
            if start.elapsed() >= limit {
                break StopReason::Time;
            }
        }
        let first = film.samples();
        let n = if setup.adaptive_threshold.is_some() {
            options.spp - first
        } else {
            pass.min(options.spp - first)
        };
        let aov_now = want_aov && first == 0;
        let sink = Mutex::new(Sink {
            film: &mut film,
            aov: &mut aov,
            stats: &mut stats,
        });
        sweep(
            integrator, &cx, setup, &tiles, &sink, first, n, aov_now, on_tile,
        );
        film.finish_pass(n);
        pass = (pass * 2).min(16);
        let report = PassReport {
            samples: film.samples(),
            target_samples: options.spp,
            relative_error: film.relative_error(),
            elapsed: start.elapsed(),
        };
        on_pass(&report, &film);
        if let Some(path) = &options.checkpoint {
            if last_checkpoint.elapsed() >= options.checkpoint_interval {
                film.save_checkpoint(path, setup.fingerprint)?;
                last_checkpoint = Instant::now();
            }
        }
    };
    if let Some(path) = &options.checkpoint {
        film.save_checkpoint(path, setup.fingerprint)?;
    }
    stats.pixels = film.pixels().len() as u64;
    let aovs = setup
        .aovs
        .iter()
        .map(|&a| {
            let px = aov.iter().map(|s| a.value(s)).collect();
            (a, Image::from_pixels(window.width, window.height, px))
        })
        .collect();
    Ok(Rendered {
        film,
        aovs,
        stats,
        stop,
        elapsed: start.elapsed(),
    })
}

/// Where finished tiles go: the film, the AOV samples and the counters, behind one
/// lock. Each tile copies its pixels out before rendering and back in as soon as it is
/// done, so only the tiles in flight hold pixels of their own (not a second copy of
/// the whole film).
struct Sink<'a> {
    film: &'a mut Film,
    aov: &'a mut [AovSample],
    stats: &'a mut Stats,
}

/// One pass over every tile in parallel, each stored into `sink` when done.
#[allow(clippy::too_many_arguments)]
fn sweep<I: Integrator>(
    integrator: &I,
    cx: &TileContext<'_>,
    setup: &DriverSetup,
    tiles: &[Tile],
    sink: &Mutex<Sink<'_>>,
    first: u32,
    n: u32,
    want_aov: bool,
    on_tile: &(dyn Fn(u64) + Sync),
) {
    let lock = || sink.lock().unwrap_or_else(|e| e.into_inner());
    tiles.par_iter().for_each(|t| {
        let mut pixels = {
            let s = lock();
            // An empty film (the first pass of a render not resumed) has nothing to read.
            if s.film.samples() == 0 && setup.adaptive_threshold.is_none() {
                vec![FilmPixel::default(); (t.w * t.h) as usize]
            } else {
                read_tile(s.film, *t)
            }
        };
        let r = match setup.adaptive_threshold {
            Some(threshold) if n > 0 => {
                let mut stats = Stats::default();
                let aov = adaptive::render_tile(
                    integrator,
                    cx,
                    *t,
                    first + n,
                    threshold,
                    want_aov,
                    &mut pixels,
                    &mut stats,
                );
                TileResult { pixels, aov, stats }
            }
            _ => render_tile(integrator, cx, *t, pixels, first, n, want_aov),
        };
        on_tile((t.w * t.h) as u64 * n as u64);
        store_tile(&mut lock(), *t, r);
    });
}

/// Writes one tile's pixels, AOVs and counters back.
fn store_tile(sink: &mut Sink<'_>, t: Tile, r: TileResult) {
    sink.stats.merge(&r.stats);
    let fw = sink.film.width() as usize;
    let base = sink.film.index(t.x0, t.y0);
    for j in 0..t.h as usize {
        let (dst, src) = (base + j * fw, j * t.w as usize);
        let row = src..src + t.w as usize;
        sink.film.pixels_mut()[dst..dst + t.w as usize].copy_from_slice(&r.pixels[row.clone()]);
        if !r.aov.is_empty() {
            sink.aov[dst..dst + t.w as usize].copy_from_slice(&r.aov[row]);
        }
    }
}

/// The film's pixels of tile `t`, row-major.
pub(crate) fn read_tile(film: &Film, t: Tile) -> Vec<FilmPixel> {
    let mut out = Vec::with_capacity((t.w * t.h) as usize);
    for y in t.y0..t.y0 + t.h {
        let i = film.index(t.x0, y);
        out.extend_from_slice(&film.pixels()[i..i + t.w as usize]);
    }
    out
}

/// Samples `first..first + n` of every pixel of tile `t`, added to its `pixels` (the
/// film's values there);
/// with `want_aov`, sample 0 (which must be among them, or `n == 0`: AOVs only) is
/// traced with its AOV record.
fn render_tile<I: Integrator>(
    integrator: &I,
    cx: &TileContext<'_>,
    t: Tile,
    mut pixels: Vec<FilmPixel>,
    first: u32,
    n: u32,
    want_aov: bool,
) -> TileResult {
    let mut stats = Stats::default();
    let count = pixels.len();
    let coords = |p: usize| {
        (
            t.x0 + (p % t.w as usize) as u32,
            t.y0 + (p / t.w as usize) as u32,
        )
    };
    let mut aov = Vec::new();
    // Sample 0 with its AOV, one by one.
    let mut rest = first;
    if want_aov {
        aov = vec![AovSample::default(); count];
        for (p, (px, a)) in pixels.iter_mut().zip(&mut aov).enumerate() {
            let (x, y) = coords(p);
            let mut cs = camera_sample(cx.cam, cx.filter, cx.sampler, x, y, 0);
            let l = integrator.sample(&cs.ray, &mut cs.rng, &mut stats, a);
            if n > 0 {
                px.add(l, cs.weight);
            }
        }
        rest = 1;
    }
    let end = first + n;
    let m = end.saturating_sub(rest) as usize;
    if m > 0 {
        let mut out = vec![Rgb::BLACK; count * m];
        let mut weights = vec![0.0f32; count * m];
        let mut cursor = Cursor::new(t, m);
        integrator.sample_batch(
            |k| {
                let (x, y, s) = cursor.at(k);
                let cs = camera_sample(cx.cam, cx.filter, cx.sampler, x, y, rest + s);
                weights[k] = cs.weight;
                (cs.ray, cs.rng)
            },
            &mut out,
            &mut stats,
        );
        for (p, px) in pixels.iter_mut().enumerate() {
            for k in p * m..(p + 1) * m {
                px.add(out[k], weights[k]);
            }
        }
    }
    stats.samples += count as u64 * n as u64;
    TileResult { pixels, aov, stats }
}

/// Pixel and sample of the `k`-th sample of a tile's batch (pixel-major, `m` samples
/// a pixel): found by stepping from the previous one when the integrator asks in order
/// (every one does today), by division otherwise. A one-sample render asks for a
/// million of these, and three integer divisions a sample showed in its profile.
struct Cursor {
    t: Tile,
    m: u32,
    /// The next `k` in order and its (x, y, sample).
    k: usize,
    at: (u32, u32, u32),
}

impl Cursor {
    fn new(t: Tile, m: usize) -> Self {
        Self {
            t,
            m: m as u32,
            k: 0,
            at: (t.x0, t.y0, 0),
        }
    }

    #[inline]
    fn at(&mut self, k: usize) -> (u32, u32, u32) {
        if k != self.k {
            let (p, s) = (k / self.m as usize, (k % self.m as usize) as u32);
            let w = self.t.w as usize;
            self.at = (
                self.t.x0 + (p % w) as u32,
                self.t.y0 + (p / w) as u32,
                s,
            );
        }
        let here = self.at;
        // Step to k + 1: the next sample, else the next pixel, else the next row.
        let (mut x, mut y, mut s) = here;
        s += 1;
        if s == self.m {
            s = 0;
            x += 1;
            if x == self.t.x0 + self.t.w {
                x = self.t.x0;
                y += 1;
            }
        }
        self.k = k + 1;
        self.at = (x, y, s);
        here
    }
}

/// Renders `scene` at its settings' sample count in one sweep of `integrator`
/// ([`crate::render`] with fixed options), for callers that have their own integrator
/// (the parallel renderers' replaying geometry).
pub fn render_with<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    options: &crate::RenderOptions,
) -> Result<crate::RenderOutput, crate::RenderError> {
    let setup = DriverSetup {
        sampler: SamplerKind::Stratified,
        adaptive_threshold: scene.settings.adaptive_threshold,
        tile_size: options.tile_size,
        aovs: options.aovs.clone(),
        fingerprint: crate::film::fingerprint(scene, "whitted"),
    };
    crate::run_driver(integrator, scene, &setup, options)
}

/// Renders the pixels of the rectangle at (`x0`, `y0`) of `w` x `h` pixels of the
/// image exactly as [`render_with`] renders them (the same samples and adaptive
/// decisions, which depend only on the pixel), row-major, with the rays it traced:
/// image-parallel (sort-first) rendering of screen regions.
pub fn render_region<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    x0: u32,
    y0: u32,
    w: u32,
    h: u32,
) -> (Vec<Rgb>, Stats) {
    let s = &scene.settings;
    let spp = s.spp.max(1);
    let cam = scene.camera.rays(s.width, s.height);
    let filter = FilterSampler::new(s.filter);
    let cx = TileContext {
        cam: &cam,
        filter: &filter,
        sampler: Sampler::Stratified { spp },
        width: s.width,
        height: s.height,
    };
    let t = Tile { x0, y0, w, h };
    let window = CropWindow {
        x: x0,
        y: y0,
        width: w,
        height: h,
    };
    let film = Film::for_window(window).expect("a region of an image that was allocated");
    let r = match s.adaptive_threshold {
        Some(threshold) => {
            let mut pixels = read_tile(&film, t);
            let mut stats = Stats::default();
            adaptive::render_tile(
                integrator,
                &cx,
                t,
                spp,
                threshold,
                false,
                &mut pixels,
                &mut stats,
            );
            TileResult {
                pixels,
                aov: Vec::new(),
                stats,
            }
        }
        None => render_tile(integrator, &cx, t, read_tile(&film, t), 0, spp, false),
    };
    let mut stats = r.stats;
    stats.pixels = (w * h) as u64;
    (r.pixels.iter().map(FilmPixel::value).collect(), stats)
}
