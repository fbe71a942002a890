//! irradia-render: the integrators that turn a [`Scene`] into an image.
//!
//! - [`whitted`]: the recursive ray tracer of the lecture ("Recursive Ray Tracer"),
//!   with Phong or POV-Ray shading, shadow rays through transparent objects,
//!   reflection, refraction with nested media, and ray trees ([`raytree`]).
//! - [`path`]: the Monte Carlo path tracer.
//!
//! Both plug into one driver through the [`Integrator`] trait: [`driver`] (tiles on
//! rayon, progressive passes, sample / time / error budgets, checkpoints, AOVs,
//! progress), [`film`] (the accumulated samples), [`sampler`] (where samples go) and
//! [`filter`] (pixel filters). [`render`] picks the integrator named by
//! `scene.settings.integrator`; [`trace_pixel`] records the ray tree of one pixel with
//! the same code.

pub mod adaptive;
pub mod aov;
pub mod budget;
pub mod camera_batch;
pub mod cancel;
pub mod driver;
pub mod film;
pub mod filter;
pub mod integrator;
pub mod labels;
pub mod path;
pub mod pool;
pub mod prepared;
pub mod raytree;
pub mod sampler;
pub mod stats;
pub mod whitted;

pub use aov::Aov;
pub use budget::Budget;
pub use driver::{PassReport, StopReason};
pub use film::{CheckpointError, Film};
pub use integrator::{AovSample, Integrator};
pub use prepared::PreparedScene;
pub use raytree::{RayKind, RayNode};
pub use stats::Stats;
pub use whitted::Whitted;

use driver::{DriverSetup, LocalSweep, ProgressiveOptions, RunError, Sweep};
use filter::FilterSampler;
use irradia_core::{Image, ImageError, Rgb};
use irradia_scene::{Integrator as Method, Scene};
use path::{PathIntegrator, PathParams};
use sampler::{camera_sample, Sampler};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Duration;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum RenderError {
    #[error(transparent)]
    Image(#[from] ImageError),
    #[error("cannot start the render threads: {0}")]
    Threads(String),
    #[error("pixel ({x}, {y}) is outside the {width}x{height} image")]
    PixelOutside {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
    /// Settings that do not fit together (a crop window outside the image).
    #[error("{0}")]
    Settings(String),
    /// A checkpoint to resume from that cannot be used.
    #[error(transparent)]
    Resume(#[from] CheckpointError),
    #[error("cannot write the checkpoint: {0}")]
    CheckpointWrite(std::io::Error),
    /// A distributed render that lost a rank (the message names it).
    #[error("{0}")]
    Distributed(String),
    /// The caller set [`RenderOptions::cancel`] before the render finished.
    #[error("the render was cancelled")]
    Cancelled,
    #[error("trace-pixel records the whitted and path integrators; this scene's integrator is direct (render it with --integrator path and --max-depth 2 to trace its direct light)")]
    TraceDirect,
}

/// Where a render stands: after each tile (`pass` is `None`) and after each pass.
#[derive(Clone, Copy, Debug)]
pub struct Progress {
    /// Pixel-samples finished in this session, and how many there will be (`None`
    /// when a time or error budget decides).
    pub done: u64,
    pub total: Option<u64>,
    pub pass: Option<PassReport>,
}

/// A progress callback (called from any thread).
pub type ProgressFn = Arc<dyn Fn(&Progress) + Send + Sync>;

/// How to render (what to render is in the scene's settings).
#[derive(Clone)]
pub struct RenderOptions {
    /// Worker threads; `None` uses rayon's global pool (one per core).
    pub threads: Option<usize>,
    /// Side of the square tiles the image is cut into, in pixels.
    pub tile_size: u32,
    /// Extra images to produce.
    pub aovs: Vec<Aov>,
    pub progress: Option<ProgressFn>,
    /// Samples per pixel to reach instead of the scene's (`u32::MAX`: until a time or
    /// error budget ends the render).
    pub spp: Option<u32>,
    /// Stop after the pass in which this much time has passed.
    pub time_limit: Option<Duration>,
    /// Stop when the image's relative error estimate falls to this value.
    pub target_error: Option<f64>,
    /// Write the film here every `checkpoint_interval` and at the end.
    pub checkpoint: Option<PathBuf>,
    pub checkpoint_interval: Duration,
    /// Continue the render saved in this checkpoint (and keep writing it there unless
    /// `checkpoint` names another file).
    pub resume: Option<PathBuf>,
    /// Selects an independent family of random streams (path tracer) instead of the
    /// scene's `seed`.
    pub seed: Option<u32>,
    /// Set it (from any thread) to stop the render: tiles not yet started are
    /// skipped and [`render`] returns [`RenderError::Cancelled`] ([`cancel`]).
    pub cancel: Option<Arc<AtomicBool>>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            threads: None,
            tile_size: 32,
            aovs: Vec::new(),
            progress: None,
            spp: None,
            time_limit: None,
            target_error: None,
            checkpoint: None,
            checkpoint_interval: Duration::from_secs(30),
            resume: None,
            seed: None,
            cancel: None,
        }
    }
}

impl std::fmt::Debug for RenderOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderOptions")
            .field("threads", &self.threads)
            .field("tile_size", &self.tile_size)
            .field("aovs", &self.aovs)
            .field("spp", &self.spp)
            .field("time_limit", &self.time_limit)
            .field("target_error", &self.target_error)
            .field("checkpoint", &self.checkpoint)
            .field("resume", &self.resume)
            .finish()
    }
}

/// A rendered image with its AOVs and statistics.
#[derive(Debug)]
pub struct RenderOutput {
    /// Linear radiance of the rendered window (the crop window, if any).
    pub image: Image,
    /// Raw AOV images in the order they were asked for.
    pub aovs: Vec<(Aov, Image)>,
    pub stats: Stats,
    /// Wall time of the render (not counting scene loading or file writing).
    pub elapsed: Duration,
    /// Samples per pixel in the image (counting a resumed checkpoint's).
    pub samples: u32,
    pub stop: StopReason,
    /// The image's relative error estimate (infinite below two samples).
    pub relative_error: f64,
}

/// Renders `scene` with the integrator its settings name.
/// The scene's `[[labels]]` are drawn over the image ([`labels::draw_labels`]).
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<RenderOutput, RenderError> {
    let mut sweep = LocalSweep {
        cancel: options.cancel.as_deref(),
    };
    pool::with_threads(options.threads, || render_on(scene, options, &mut sweep))?
}

/// [`render`] with each pass's tiles rendered by `sweep` (this process's threads, or
/// the ranks of a distributed render: `irradia_parallel::progressive`), on the
/// current rayon pool (`options.threads` is not looked at: the caller installs the
/// pool, so that `sweep` need not move to another thread).
pub fn render_on<S: Sweep>(
    scene: &Scene,
    options: &RenderOptions,
    sweep: &mut S,
) -> Result<RenderOutput, RenderError> {
    scene.settings.check_crop().map_err(RenderError::Settings)?;
    struct Run<'o, S> {
        scene: &'o Scene,
        options: &'o RenderOptions,
        sweep: &'o mut S,
    }
    impl<S: Sweep> WithIntegrator for Run<'_, S> {
        type Output = Result<RenderOutput, RenderError>;
        fn with<I: Integrator>(self, integrator: &I, setup: &DriverSetup) -> Self::Output {
            run_driver(integrator, self.scene, setup, self.options, self.sweep)
        }
    }
    let run = Run {
        scene,
        options,
        sweep,
    };
    let mut out = with_integrator(scene, options.tile_size, options.aovs.clone(), run)?;
    labels::draw_labels(scene, &mut out.image);
    Ok(out)
}

/// Something done with the integrator that a scene's settings name, whatever its type
/// (the Whitted tracer and the path tracer are different types): a visitor, for
/// [`with_integrator`].
pub trait WithIntegrator {
    type Output;
    /// Called once with the integrator and the driver setup for it.
    fn with<I: Integrator>(self, integrator: &I, setup: &DriverSetup) -> Self::Output;
}

/// Builds the integrator `scene.settings.integrator` names, with its driver setup for
/// `tile_size` and `aovs`, and hands both to `w`.
pub fn with_integrator<W: WithIntegrator>(
    scene: &Scene,
    tile_size: u32,
    aovs: Vec<Aov>,
    w: W,
) -> W::Output {
    match scene.settings.integrator {
        Method::Whitted => {
            let prepared = PreparedScene::new(scene);
            w.with(
                &Whitted::prepared(&prepared),
                &whitted_setup(scene, tile_size, aovs),
            )
        }
        Method::Path | Method::Direct { .. } => {
            let lights = path::lights::LightSampler::new(scene);
            let ps = path::integrator::PathScene::new(
                scene,
                path::flat_scene::FlatScene::new(scene),
                &lights,
            );
            let params = PathParams::for_settings(&scene.settings);
            let integrator = PathIntegrator::new(&ps, params, path::Kernel::Auto);
            let setup = integrator.setup(tile_size, aovs);
            w.with(&integrator, &setup)
        }
    }
}

/// How the driver runs the Whitted tracer: stratified samples, the scene's adaptive
/// threshold.
pub(crate) fn whitted_setup(scene: &Scene, tile_size: u32, aovs: Vec<Aov>) -> DriverSetup {
    DriverSetup {
        sampler: driver::SamplerKind::Stratified,
        adaptive_threshold: scene.settings.adaptive_threshold,
        tile_size,
        aovs,
        fingerprint: film::fingerprint(scene, "whitted"),
    }
}

/// The budget of a render under `options`: samples (the scene's unless overridden),
/// time, error, checkpoints, seed.
pub fn progressive_options(scene: &Scene, options: &RenderOptions) -> ProgressiveOptions {
    ProgressiveOptions {
        spp: options.spp.unwrap_or(scene.settings.spp).max(1),
        time_limit: options.time_limit,
        target_error: options.target_error,
        checkpoint: options
            .checkpoint
            .clone()
            .or_else(|| options.resume.clone()),
        checkpoint_interval: options.checkpoint_interval,
        seed: options.seed.unwrap_or(scene.settings.seed),
    }
}

/// The driver under [`RenderOptions`] on the current rayon pool: the budget, the film
/// (new or resumed) and the progress reports.
pub(crate) fn run_driver<I: Integrator, S: Sweep>(
    integrator: &I,
    scene: &Scene,
    setup: &DriverSetup,
    options: &RenderOptions,
    sweep: &mut S,
) -> Result<RenderOutput, RenderError> {
    let progressive = progressive_options(scene, options);
    let spp = progressive.spp;
    let film = match &options.resume {
        Some(p) => Film::load_checkpoint(p, setup.fingerprint)?,
        // One sample per pixel is one pass, after which nothing reads the sums (no
        // error estimate below two samples): the film keeps the values alone.
        None if spp == 1 && progressive.checkpoint.is_none() => {
            Film::for_one_sample(scene.settings.window())?
        }
        None => Film::for_scene(scene)?,
    };
    let pixels = film.len() as u64;
    let total = (spp != u32::MAX).then(|| pixels * spp.saturating_sub(film.samples()) as u64);
    let done = AtomicU64::new(0);
    let report = |pass: Option<PassReport>, n: u64| {
        let d = done.fetch_add(n, Ordering::Relaxed) + n;
        if let Some(p) = &options.progress {
            p(&Progress {
                done: d,
                total,
                pass,
            });
        }
    };
    let on_tile = |n: u64| report(None, n);
    let r = driver::run_with(
        integrator,
        scene,
        setup,
        &progressive,
        film,
        sweep,
        &on_tile,
        |p, _| report(Some(*p), 0),
    )
    .map_err(|e| match e {
        RunError::Checkpoint(e) => RenderError::CheckpointWrite(e),
        RunError::Sweep(e) if e.is::<cancel::Cancelled>() => RenderError::Cancelled,
        RunError::Sweep(e) => RenderError::Distributed(e.to_string()),
    })?;
    let (samples, relative_error) = (r.film.samples(), r.film.relative_error());
    Ok(RenderOutput {
        image: r.film.into_image(),
        aovs: r.aovs,
        stats: r.stats,
        elapsed: r.elapsed,
        samples,
        stop: r.stop,
        relative_error,
    })
}

/// The ray tree of sample `sample` of pixel (x, y) (x right, y down from the top left),
/// traced by the scene's integrator exactly as [`render`] traces it (Whitted: the ray
/// tree; path: the path's segments and shadow rays, [`path::trace_sample`]). Returns
/// the tree and the sample's radiance.
pub fn trace_pixel(
    scene: &Scene,
    x: u32,
    y: u32,
    sample: u32,
) -> Result<(RayNode, Rgb), RenderError> {
    let s = &scene.settings;
    if x >= s.width || y >= s.height {
        return Err(RenderError::PixelOutside {
            x,
            y,
            width: s.width,
            height: s.height,
        });
    }
    match s.integrator {
        Method::Path => return Ok(path::trace_sample::trace_sample(scene, x, y, sample)),
        Method::Direct { .. } => return Err(RenderError::TraceDirect),
        Method::Whitted => {}
    }
    let cam = scene.camera.rays(s.width, s.height);
    let spp = if s.adaptive_threshold.is_some() {
        1
    } else {
        s.spp.max(1)
    };
    let filter = FilterSampler::new(s.filter);
    let mut cs = camera_sample(&cam, &filter, Sampler::Stratified { spp }, x, y, sample);
    let mut rec = raytree::TreeRecorder::default();
    let mut stats = Stats::default();
    let mut aov = AovSample::default();
    let c =
        Whitted::new(scene).sample_recorded(&cs.ray, &mut cs.rng, &mut stats, &mut aov, &mut rec);
    let root = rec
        .roots
        .pop()
        .expect("the camera ray always opens and closes a node");
    Ok((root, c))
}
