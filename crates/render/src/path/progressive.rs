//! Progressive rendering: passes of samples over the whole image until a sample budget,
//! a time budget or a target error is reached, with periodic checkpoints of the film so
//! that an interrupted render can be resumed to exactly the same result.
//!
//! Sample `i` of pixel `(x, y)` always uses the random stream `Rng::for_pixel(x, y, i,
//! ..)` and each pixel adds its samples in order, so the image depends neither on the
//! thread count nor on how the samples were split into passes or sessions.

use super::direct::{radiance_direct, DirectParams};
use super::film::{luminance, Film};
use super::flat_scene::FlatScene;
use super::integrator::{radiance_in, PathCounters, PathParams, PathScene};
use super::lights::LightSampler;
use super::wide::WideScene;
use irradia_core::{Ray, Rgb, Rng};
use irradia_scene::camera::CameraRays;
use irradia_scene::{Integrator, Scene};
use rayon::prelude::*;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Stream tag of the path tracer's samples.
const PATH_STREAM: u32 = 0x9a7b;

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
    /// Selects an independent family of random streams (0 for the default image).
    pub seed: u32,
}

/// Which estimator code runs the samples (the same estimator either way).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Kernel {
    /// The 8-wide kernel ([`super::wide`]) where the scene qualifies, otherwise the
    /// scalar one; `IRRADIA_PATH_KERNEL=scalar` in the environment forces the scalar
    /// one (for A/B timings of the command-line tool).
    #[default]
    Auto,
    /// Always the scalar `radiance_in`.
    Scalar,
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

#[derive(Debug)]
pub struct PathRender {
    pub film: Film,
    pub counters: PathCounters,
    pub stop: StopReason,
    pub elapsed: Duration,
}

/// A fingerprint of what determines the image, to refuse resuming a checkpoint of
/// another scene.
pub fn fingerprint(scene: &Scene, params: &PathParams) -> u64 {
    // Everything that changes the image, and not the sample budget.
    let s = &scene.settings;
    let text = format!(
        "{}x{}|{:?}|{:?}|{:?}|{}|{}|{}|{}|{:?}{}",
        s.width,
        s.height,
        s.background,
        scene.camera,
        scene
            .materials
            .iter()
            .map(|m| (m.emission, m.diffuse, m.specular, m.transmission))
            .collect::<Vec<_>>(),
        scene.objects.len(),
        scene.materials.len(),
        scene.lights.len(),
        params.max_depth,
        scene.source,
        // Only for the direct integrator, so that path-traced checkpoints keep theirs.
        match s.integrator {
            Integrator::Direct { .. } => format!("|{:?}", s.integrator),
            _ => String::new(),
        }
    );
    text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    })
}

/// The start of sample `i` of pixel `(x, y)`: its random stream, and the camera ray
/// through the jittered point of the pixel drawn first from that stream.
pub fn pixel_sample(cam: &CameraRays, x: u32, y: u32, i: u32, seed: u32) -> (Ray, Rng) {
    let mut rng = Rng::for_pixel(x, y, i, PATH_STREAM ^ seed.wrapping_mul(0x9e37_79b9));
    let j = rng.next_2d();
    (cam.ray(x as f32 + j.x, y as f32 + j.y), rng)
}

/// Adds one sample to a pixel's sums (non-finite samples count as black).
#[inline]
fn accumulate(sum: &mut [f64; 3], sum_sq: &mut f64, l: Rgb) {
    let v = if l.is_finite() {
        [l.r as f64, l.g as f64, l.b as f64]
    } else {
        [0.0; 3]
    };
    sum[0] += v[0];
    sum[1] += v[1];
    sum[2] += v[2];
    let y = luminance(&v);
    *sum_sq += y * y;
}

/// Renders (or continues rendering into `film`) until a stop condition holds.
pub fn render(
    scene: &Scene,
    params: &PathParams,
    options: &ProgressiveOptions,
    film: Film,
    on_pass: impl FnMut(&PassReport, &Film),
) -> std::io::Result<PathRender> {
    render_with(scene, params, options, Kernel::Auto, film, on_pass)
}

/// [`render`] with a choice of the code that runs the samples.
pub fn render_with(
    scene: &Scene,
    params: &PathParams,
    options: &ProgressiveOptions,
    kernel: Kernel,
    mut film: Film,
    mut on_pass: impl FnMut(&PassReport, &Film),
) -> std::io::Result<PathRender> {
    let start = Instant::now();
    let lights = LightSampler::new(scene);
    let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
    // Eight paths at once where the scene qualifies; the same estimator either way.
    // IRRADIA_PATH_KERNEL=scalar turns it off from outside (for A/B timings).
    let scalar_only = kernel == Kernel::Scalar
        || std::env::var("IRRADIA_PATH_KERNEL").is_ok_and(|v| v == "scalar");
    // The scene's `integrator = "direct"` estimates direct light only (Mitsuba's
    // `direct`); otherwise the path tracer.
    let direct = match scene.settings.integrator {
        Integrator::Direct {
            emitter_samples,
            bsdf_samples,
        } => Some(DirectParams {
            emitter_samples,
            bsdf_samples,
        }),
        _ => None,
    };
    let wide = if scalar_only || direct.is_some() {
        None
    } else {
        WideScene::new(&ps)
    };
    let cam = scene.camera.rays(film.width(), film.height());
    let fp = fingerprint(scene, params);
    let mut counters = PathCounters::default();
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
        let n = pass.min(options.spp - first);
        let width = film.width();
        let pass_counters: PathCounters = film
            .rows_mut()
            .enumerate()
            .map(|(y, (sum, sum_sq))| {
                let mut c = PathCounters::default();
                let y = y as u32;
                if let Some(ws) = &wide {
                    // The row's samples in pixel order, each pixel's in sample order;
                    // the kernel fills them in any order, the sums add them in this one.
                    let per_pixel = n as usize;
                    let mut out = vec![Rgb::BLACK; width as usize * per_pixel];
                    ws.radiance_batch(
                        params,
                        |k| {
                            let (x, i) = (k / per_pixel, k % per_pixel);
                            pixel_sample(&cam, x as u32, y, first + i as u32, options.seed)
                        },
                        &mut out,
                        &mut c,
                    );
                    for (x, samples) in out.chunks_exact(per_pixel).enumerate() {
                        for &l in samples {
                            accumulate(&mut sum[x], &mut sum_sq[x], l);
                        }
                    }
                    return c;
                }
                for x in 0..width {
                    let (s, s2) = (&mut sum[x as usize], &mut sum_sq[x as usize]);
                    for i in first..first + n {
                        let (ray, mut rng) = pixel_sample(&cam, x, y, i, options.seed);
                        let l = match &direct {
                            Some(d) => radiance_direct(&ps, d, ray, &mut rng, &mut c),
                            None => radiance_in(&ps, params, ray, &mut rng, &mut c),
                        };
                        accumulate(s, s2, l);
                    }
                }
                c
            })
            .reduce(PathCounters::default, |mut a, b| {
                a.add(&b);
                a
            });
        film.finish_pass(n);
        counters.add(&pass_counters);
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
                film.save_checkpoint(path, fp)?;
                last_checkpoint = Instant::now();
            }
        }
    };
    if let Some(path) = &options.checkpoint {
        film.save_checkpoint(path, fp)?;
    }
    Ok(PathRender {
        film,
        counters,
        stop,
        elapsed: start.elapsed(),
    })
}
