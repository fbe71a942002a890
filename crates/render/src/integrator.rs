//! What the driver ([`crate::driver`]) asks of an integrator: the radiance of one
//! camera sample, plus the first hit's data for the AOVs; and, for integrators that
//! run many samples at once faster (the path tracer's wide kernel), a batch of
//! samples. The Whitted tracer ([`crate::Whitted`]) and the path tracer
//! ([`crate::path::PathIntegrator`]) implement it; [`crate::render`] picks one.

use crate::camera_batch::CameraBatch;
use crate::stats::Stats;
use glam::Vec3;
use irradia_core::{Ray, Rgb, Rng};

/// Data about a camera sample's first hit, for arbitrary output variables.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AovSample {
    /// Distance along the camera ray to the first hit; infinite when nothing is hit.
    pub depth: f32,
    /// World-space shading normal at the first hit (zero when nothing is hit).
    pub normal: Vec3,
    /// Index of the object hit first; -1 for the background.
    pub object: i32,
    /// Deepest level of the sample's ray tree (1 = the camera ray only).
    pub ray_depth: u32,
}

impl Default for AovSample {
    fn default() -> Self {
        Self {
            depth: f32::INFINITY,
            normal: Vec3::ZERO,
            object: -1,
            ray_depth: 0,
        }
    }
}

/// A light-transport algorithm the driver can run (pbrt-v4's `RayIntegrator`).
pub trait Integrator: Sync {
    /// Radiance arriving along the camera ray `ray` (one sample of one pixel). `rng` is
    /// the sample's own stream (seeded from pixel and sample index), `stats` the
    /// calling tile's counters; `aov` receives the first hit.
    fn sample(&self, ray: &Ray, rng: &mut Rng, stats: &mut Stats, aov: &mut AovSample) -> Rgb;

    /// Samples `0..out.len()` without AOVs: sample `k` starts from `start(k)` (its
    /// camera ray and stream) and its radiance goes to `out[k]`, exactly as
    /// [`Integrator::sample`] would compute it (up to rounding, for SIMD kernels).
    fn sample_batch(
        &self,
        mut start: impl FnMut(usize) -> (Ray, Rng),
        out: &mut [Rgb],
        stats: &mut Stats,
    ) {
        let mut scratch = AovSample::default();
        for (k, o) in out.iter_mut().enumerate() {
            let (ray, mut rng) = start(k);
            *o = self.sample(&ray, &mut rng, stats, &mut scratch);
        }
    }

    /// [`Integrator::sample_batch`] over a tile's camera samples made in lanes
    /// ([`CameraBatch`]: sample `k` is `batch.sample(k)`; its filter weight goes to
    /// `weights[k]`, unless `weights` is empty: [`CameraBatch::unit_weights`]), for
    /// integrators that make them so (the path tracer's wide kernel); returns false,
    /// having done nothing, when this one does not (then the driver calls
    /// `sample_batch`).
    fn sample_camera_batch(
        &self,
        batch: &CameraBatch<'_>,
        out: &mut [Rgb],
        weights: &mut [f32],
        stats: &mut Stats,
    ) -> bool {
        let _ = (batch, out, weights, stats);
        false
    }
}
