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
use crate::camera_batch::{CameraBatch, Cursor};
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
use std::sync::atomic::{AtomicBool, Ordering};
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
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Tile {
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

/// A rendered tile: its pixels (row-major, the film's values plus the new samples),
/// the AOV records of its sample 0 (empty unless asked for) and its counters.
#[derive(Clone, Debug, PartialEq)]
pub struct TileResult {
    pub pixels: Vec<FilmPixel>,
    pub aov: Vec<AovSample>,
    pub stats: Stats,
}

/// The samples of one pass: `first..first + n` of every pixel, and whether sample 0's
/// AOV records are wanted (then sample 0 is among them, or `n == 0`: AOVs only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PassWork {
    pub first: u32,
    pub n: u32,
    pub want_aov: bool,
}

/// Everything needed to render any tile of a render: the integrator, the camera, the
/// pixel filter, the sampler and the adaptive threshold. Every process of a
/// distributed render builds the same one from the same scene and options, so a tile
/// renders to the same bits wherever it goes.
pub struct TileJob<'a, I> {
    integrator: &'a I,
    cam: CameraRays,
    filter: FilterSampler,
    sampler: Sampler,
    adaptive_threshold: Option<f32>,
    width: u32,
    height: u32,
}

impl<'a, I: Integrator> TileJob<'a, I> {
    /// The tiles of `scene` rendered by `integrator` as `setup` and `options` say.
    pub fn new(
        integrator: &'a I,
        scene: &Scene,
        setup: &DriverSetup,
        options: &ProgressiveOptions,
    ) -> Self {
        let s = &scene.settings;
        Self {
            integrator,
            cam: scene.camera.rays(s.width, s.height),
            filter: FilterSampler::new(s.filter),
            sampler: match setup.sampler {
                SamplerKind::Stratified => Sampler::Stratified { spp: options.spp },
                SamplerKind::Independent => Sampler::Independent { seed: options.seed },
            },
            adaptive_threshold: setup.adaptive_threshold,
            width: s.width,
            height: s.height,
        }
    }

    /// Renders the samples `work` of tile `t` onto `pixels` (the film's values there,
    /// row-major; all zero for an empty film).
    pub fn render(&self, t: Tile, mut pixels: Vec<FilmPixel>, work: PassWork) -> TileResult {
        let cx = TileContext {
            cam: &self.cam,
            filter: &self.filter,
            sampler: self.sampler,
            width: self.width,
            height: self.height,
        };
        match self.adaptive_threshold {
            Some(threshold) if work.n > 0 => {
                let mut stats = Stats::default();
                let aov = adaptive::render_tile(
                    self.integrator,
                    &cx,
                    t,
                    work.first + work.n,
                    threshold,
                    work.want_aov,
                    &mut pixels,
                    &mut stats,
                );
                TileResult { pixels, aov, stats }
            }
            _ => render_tile(
                self.integrator,
                &cx,
                t,
                pixels,
                work.first,
                work.n,
                work.want_aov,
            ),
        }
    }

    /// Whether a tile's pixels must be read from the film before rendering it (not for
    /// the first pass of a film without samples, unless adaptive sampling reads them).
    pub fn reads_film(&self, film: &Film) -> bool {
        film.samples() > 0 || self.adaptive_threshold.is_some()
    }

    /// What tile `t` starts from: the film's pixels there (row-major), or zeros where
    /// nothing needs reading (the first pass of a film without samples, unless adaptive
    /// sampling looks at them).
    pub fn start_pixels(&self, film: &Film, t: Tile) -> Vec<FilmPixel> {
        if self.reads_film(film) {
            read_tile(film, t)
        } else {
            vec![FilmPixel::default(); (t.w * t.h) as usize]
        }
    }
}

/// Where a pass's tiles are rendered: on this process's threads ([`LocalSweep`]), or
/// spread over the ranks of a distributed render (`irradia_parallel::progressive`).
/// Each tile's result is stored with [`store_tile`].
pub trait Sweep {
    /// Renders `work` on every tile of `tiles` into `sink`, calling `on_tile` with the
    /// pixel-samples of each finished tile.
    fn sweep<I: Integrator>(
        &mut self,
        job: &TileJob<'_, I>,
        tiles: &[Tile],
        sink: &mut Sink<'_>,
        work: PassWork,
        on_tile: &(dyn Fn(u64) + Sync),
    ) -> Result<(), SweepError>;
}

/// Why a sweep failed (a distributed one: a rank that died or never answered).
pub type SweepError = Box<dyn std::error::Error + Send + Sync>;

/// Why [`run_with`] stopped early.
#[derive(Debug, thiserror::Error)]
pub enum RunError {
    #[error("cannot write the checkpoint: {0}")]
    Checkpoint(std::io::Error),
    #[error("{0}")]
    Sweep(SweepError),
}

/// The tiles rendered in parallel on the current rayon pool; once `cancel` is set
/// (Ctrl-C in the Python binding: [`crate::cancel`]), tiles not yet started are skipped.
#[derive(Clone, Copy, Debug, Default)]
pub struct LocalSweep<'c> {
    pub cancel: Option<&'c AtomicBool>,
}

impl Sweep for LocalSweep<'_> {
    fn sweep<I: Integrator>(
        &mut self,
        job: &TileJob<'_, I>,
        tiles: &[Tile],
        sink: &mut Sink<'_>,
        work: PassWork,
        on_tile: &(dyn Fn(u64) + Sync),
    ) -> Result<(), SweepError> {
        sweep_local(job, tiles, sink, work, on_tile, self.cancel)
    }
}

/// [`LocalSweep`]'s work: the tiles in parallel on the current rayon pool; once
/// `cancel` is set, tiles not yet started are skipped and the sweep fails with
/// [`crate::cancel::Cancelled`] (the film then holds a partial pass: a cancelled
/// render returns no image).
fn sweep_local<I: Integrator>(
    job: &TileJob<'_, I>,
    tiles: &[Tile],
    sink: &mut Sink<'_>,
    work: PassWork,
    on_tile: &(dyn Fn(u64) + Sync),
    cancel: Option<&AtomicBool>,
) -> Result<(), SweepError> {
    let cancelled = || cancel.is_some_and(|c| c.load(Ordering::Relaxed));
    let sink = Mutex::new(sink);
    let lock = || sink.lock().unwrap_or_else(|e| e.into_inner());
    tiles.par_iter().for_each(|t| {
        if cancelled() {
            return;
        }
        let pixels = job.start_pixels(lock().film, *t);
        let r = job.render(*t, pixels, work);
        on_tile((t.w * t.h) as u64 * work.n as u64);
        store_tile(&mut lock(), *t, r);
    });
    if cancelled() {
        return Err(Box::new(crate::cancel::Cancelled));
    }
    Ok(())
}

/// The tiles of `window`, row by row, each `size` pixels square (smaller at the
/// right and bottom edges).
pub fn tiles_of(window: CropWindow, size: u32) -> Vec<Tile> {
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

/// Renders (or continues rendering into `film`) until a stop condition holds, on
/// the current rayon pool. `on_tile` is called from the worker threads with the
/// pixel-samples each tile finished; `on_pass` after every pass.
pub fn run<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    setup: &DriverSetup,
    options: &ProgressiveOptions,
    film: Film,
    on_tile: &(dyn Fn(u64) + Sync),
    on_pass: impl FnMut(&PassReport, &Film),
) -> std::io::Result<Rendered> {
    run_with(
        integrator,
        scene,
        setup,
        options,
        film,
        &mut LocalSweep::default(),
        on_tile,
        on_pass,
    )
    .map_err(|e| match e {
        RunError::Checkpoint(e) => e,
        RunError::Sweep(e) => std::io::Error::other(e),
    })
}

/// [`run`] with the tiles of each pass rendered by `sweep`.
#[allow(clippy::too_many_arguments)]
pub fn run_with<I: Integrator, S: Sweep>(
    integrator: &I,
    scene: &Scene,
    setup: &DriverSetup,
    options: &ProgressiveOptions,
    mut film: Film,
    sweep: &mut S,
    on_tile: &(dyn Fn(u64) + Sync),
    mut on_pass: impl FnMut(&PassReport, &Film),
) -> Result<Rendered, RunError> {
    let start = Instant::now();
    let s = &scene.settings;
    let window = film.window();
    let tiles = tiles_of(window, setup.tile_size);
    let job = TileJob::new(integrator, scene, setup, options);
    let want_aov = !setup.aovs.is_empty();
    let mut aov = vec![AovSample::default(); if want_aov { film.len() } else { 0 }];
    let mut stats = Stats {
        width: s.width,
        height: s.height,
        max_level: s.max_depth,
        ..Stats::default()
    };
    // A resumed film has its sample 0 already: its AOVs are traced on their own.
    if want_aov && film.samples() > 0 {
        let mut sink = Sink {
            film: &mut film,
            aov: &mut aov,
            stats: &mut stats,
        };
        let work = PassWork {
            first: 0,
            n: 0,
            want_aov: true,
        };
        sweep
            .sweep(&job, &tiles, &mut sink, work, on_tile)
            .map_err(RunError::Sweep)?;
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
        let mut sink = Sink {
            film: &mut film,
            aov: &mut aov,
            stats: &mut stats,
        };
        let work = PassWork {
            first,
            n,
            want_aov: want_aov && first == 0,
        };
        sweep
            .sweep(&job, &tiles, &mut sink, work, on_tile)
            .map_err(RunError::Sweep)?;
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
                film.save_checkpoint(path, setup.fingerprint)
                    .map_err(RunError::Checkpoint)?;
                last_checkpoint = Instant::now();
            }
        }
    };
    if let Some(path) = &options.checkpoint {
        film.save_checkpoint(path, setup.fingerprint)
            .map_err(RunError::Checkpoint)?;
    }
    stats.pixels = film.len() as u64;
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

/// Where finished tiles go: the film, the AOV samples (one per film pixel, or none)
/// and the counters. A local sweep holds it behind one lock: each tile copies its
/// pixels out before rendering and back in as soon as it is done, so only the tiles
/// in flight hold pixels of their own (not a second copy of the whole film).
pub struct Sink<'a> {
    pub film: &'a mut Film,
    pub aov: &'a mut [AovSample],
    pub stats: &'a mut Stats,
}

/// Writes one tile's pixels, AOVs and counters back.
pub fn store_tile(sink: &mut Sink<'_>, t: Tile, r: TileResult) {
    sink.stats.merge(&r.stats);
    let fw = sink.film.width() as usize;
    let base = sink.film.index(t.x0, t.y0);
    for j in 0..t.h as usize {
        let (dst, src) = (base + j * fw, j * t.w as usize);
        let row = src..src + t.w as usize;
        sink.film.store_row(dst, &r.pixels[row.clone()]);
        if !r.aov.is_empty() {
            sink.aov[dst..dst + t.w as usize].copy_from_slice(&r.aov[row]);
        }
    }
}

/// The film's pixels of tile `t`, row-major.
pub fn read_tile(film: &Film, t: Tile) -> Vec<FilmPixel> {
    let mut out = Vec::with_capacity((t.w * t.h) as usize);
    for y in t.y0..t.y0 + t.h {
        film.read_row(film.index(t.x0, y), t.w as usize, &mut out);
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
        // The integrator may make the camera samples W at once ([`CameraBatch`]),
        // with their filter weights. No weights: every one is 1.
        let batch = CameraBatch::new(cx.cam, cx.filter, cx.sampler, t, rest, m as u32);
        let mut weights = match batch.unit_weights() {
            true => Vec::new(),
            false => vec![0.0f32; count * m],
        };
        if !integrator.sample_camera_batch(&batch, &mut out, &mut weights, &mut stats) {
            weights.resize(count * m, 0.0);
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
        }
        for (p, (px, ls)) in pixels.iter_mut().zip(out.chunks_exact(m)).enumerate() {
            for (j, &l) in ls.iter().enumerate() {
                px.add(l, weights.get(p * m + j).copied().unwrap_or(1.0));
            }
        }
    }
    stats.samples += count as u64 * n as u64;
    TileResult { pixels, aov, stats }
}

/// Renders `scene` at its settings' sample count in one sweep of `integrator`
/// ([`crate::render`] with fixed options), for callers that have their own integrator
/// (the parallel renderers' replaying geometry).
pub fn render_with<I: Integrator>(
    integrator: &I,
    scene: &Scene,
    options: &crate::RenderOptions,
) -> Result<crate::RenderOutput, crate::RenderError> {
    let setup = crate::whitted_setup(scene, options.tile_size, options.aovs.clone());
    crate::pool::with_threads(options.threads, || {
        crate::run_driver(
            integrator,
            scene,
            &setup,
            options,
            &mut LocalSweep::default(),
        )
    })?
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
    let job = TileJob {
        integrator,
        cam: scene.camera.rays(s.width, s.height),
        filter: FilterSampler::new(s.filter),
        sampler: Sampler::Stratified { spp },
        adaptive_threshold: s.adaptive_threshold,
        width: s.width,
        height: s.height,
    };
    let t = Tile { x0, y0, w, h };
    let work = PassWork {
        first: 0,
        n: spp,
        want_aov: false,
    };
    let r = job.render(t, vec![FilmPixel::default(); (w * h) as usize], work);
    let mut stats = r.stats;
    stats.pixels = (w * h) as u64;
    (r.pixels.iter().map(FilmPixel::value).collect(), stats)
}
