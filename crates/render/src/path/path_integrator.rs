//! The path tracer as an [`Integrator`] of the one driver ([`crate::driver`]): one
//! camera sample is [`radiance_in`] over the scene's [`FlatScene`]; batches run on the
//! wide kernel ([`super::wide`]) where the scene qualifies. Its camera samples come
//! from the independent sampler (Mitsuba's default for the `path` integrator).

use super::direct::{radiance_direct, DirectParams};
use super::flat_scene::FlatScene;
use super::integrator::{radiance_in, PathCounters, PathParams, PathScene};
use super::lights::LightSampler;
use super::tracer::Tracer;
use super::wide::{WideScene, KERNEL_VAR};
use crate::camera_batch::CameraBatch;
use crate::driver::{self, DriverSetup, ProgressiveOptions, Rendered, SamplerKind};
use crate::film::Film;
use crate::integrator::{AovSample, Integrator};
use crate::stats::Stats;
use irradia_core::{Ray, Rgb, Rng};
use irradia_scene::Scene;

/// Which estimator code runs the samples (the same estimator either way).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Kernel {
    /// The wide kernel ([`super::wide`]) where the scene qualifies, otherwise the
    /// scalar one; `IRRADIA_PATH_KERNEL=scalar` in the environment forces the scalar
    /// one (for A/B timings of the command-line tool).
    #[default]
    Auto,
    /// Always the scalar `radiance_in`.
    Scalar,
}

/// The path tracer over a prepared scene.
pub struct PathIntegrator<'s, 'a> {
    ps: &'s PathScene<'a, FlatScene>,
    /// The scene's `integrator = "direct"` (Mitsuba's `direct`): direct light only.
    direct: Option<DirectParams>,
    wide: Option<WideScene<'s, 'a>>,
    params: PathParams,
}

impl<'s, 'a> PathIntegrator<'s, 'a> {
    pub fn new(ps: &'s PathScene<'a, FlatScene>, params: PathParams, kernel: Kernel) -> Self {
        let scalar_only =
            kernel == Kernel::Scalar || std::env::var(KERNEL_VAR).is_ok_and(|v| v == "scalar");
        let direct = match ps.scene.settings.integrator {
            irradia_scene::Integrator::Direct {
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
            WideScene::new(ps)
        };
        Self {
            ps,
            direct,
            wide,
            params,
        }
    }

    /// One camera sample's radiance by the scene's estimator.
    #[inline]
    fn radiance(
        &self,
        ray: irradia_core::Ray,
        rng: &mut irradia_core::Rng,
        c: &mut PathCounters,
    ) -> irradia_core::Rgb {
        match &self.direct {
            Some(d) => radiance_direct(self.ps, d, ray, rng, c),
            None => radiance_in(self.ps, &self.params, ray, rng, c),
        }
    }

    /// How the driver runs it: independent samples, no adaptive supersampling.
    pub fn setup(&self, tile_size: u32, aovs: Vec<crate::Aov>) -> DriverSetup {
        DriverSetup {
            sampler: SamplerKind::Independent,
            adaptive_threshold: None,
            tile_size,
            aovs,
            fingerprint: fingerprint(self.ps.scene, &self.params),
        }
    }
}

/// The path counters as the driver's statistics.
fn count(stats: &mut Stats, c: &PathCounters) {
    stats.camera_rays += c.paths;
    stats.reflected_rays += c.rays - c.paths;
    stats.shadow_rays += c.shadow_rays;
}

impl Integrator for PathIntegrator<'_, '_> {
    /// One sample by the scalar estimator; the AOV record comes from the camera ray's
    /// nearest hit in the same [`FlatScene`] (one more query, made only for the sample
    /// that carries the AOVs; batches skip it).
    fn sample(&self, ray: &Ray, rng: &mut Rng, stats: &mut Stats, aov: &mut AovSample) -> Rgb {
        if let Some(h) = self.ps.tracer.intersect(ray, f32::INFINITY) {
            aov.depth = h.hit.t * ray.dir.length();
            aov.normal = h.hit.shading_normal;
            aov.object = h.instance as i32;
        }
        let mut c = PathCounters::default();
        let l = self.radiance(*ray, rng, &mut c);
        aov.ray_depth = c.rays as u32;
        count(stats, &c);
        l
    }

    fn sample_batch(
        &self,
        mut start: impl FnMut(usize) -> (Ray, Rng),
        out: &mut [Rgb],
        stats: &mut Stats,
    ) {
        let mut c = PathCounters::default();
        match &self.wide {
            Some(ws) => ws.radiance_batch(&self.params, start, out, &mut c),
            None => {
                for (k, o) in out.iter_mut().enumerate() {
                    let (ray, mut rng) = start(k);
                    *o = self.radiance(ray, &mut rng, &mut c);
                }
            }
        }
        count(stats, &c);
    }

    /// On the wide kernel, which makes the camera samples W at once.
    fn sample_camera_batch(
        &self,
        batch: &CameraBatch<'_>,
        out: &mut [Rgb],
        weights: &mut [f32],
        stats: &mut Stats,
    ) -> bool {
        let Some(ws) = &self.wide else {
            return false;
        };
        let mut c = PathCounters::default();
        ws.radiance_camera_batch(&self.params, batch, out, weights, &mut c);
        count(stats, &c);
        true
    }
}

/// A fingerprint of what determines a path-traced image, to refuse resuming a
/// checkpoint of another scene.
pub fn fingerprint(scene: &Scene, params: &PathParams) -> u64 {
    crate::film::fingerprint(
        scene,
        &format!(
            "path|{}|{}|{:?}",
            params.max_depth, params.rr_depth, scene.settings.integrator
        ),
    )
}

/// Path-traces `scene` (or continues rendering into `film`) until a stop condition of
/// `options` holds, on the current rayon pool.
pub fn render(
    scene: &Scene,
    params: &PathParams,
    options: &ProgressiveOptions,
    film: Film,
    on_pass: impl FnMut(&driver::PassReport, &Film),
) -> std::io::Result<Rendered> {
    render_with(scene, params, options, Kernel::Auto, film, on_pass)
}

/// [`render`] with a choice of the code that runs the samples.
pub fn render_with(
    scene: &Scene,
    params: &PathParams,
    options: &ProgressiveOptions,
    kernel: Kernel,
    film: Film,
    on_pass: impl FnMut(&driver::PassReport, &Film),
) -> std::io::Result<Rendered> {
    let lights = LightSampler::new(scene);
    let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
    let integrator = PathIntegrator::new(&ps, *params, kernel);
    let setup = integrator.setup(32, Vec::new());
    driver::run(&integrator, scene, &setup, options, film, &|_| {}, on_pass)
}
