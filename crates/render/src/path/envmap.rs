//! Importance sampling of Mitsuba's `envmap` emitter: directions are drawn from a 2D
//! piecewise-constant distribution over the latitude-longitude image, each texel
//! weighted by its luminance times `sin θ` at its centre (the area of the sphere the
//! row covers), and turned into solid angle by the Jacobian of the lat-long map,
//! `dω = 2π² sin θ du dv` (Pharr, Jakob, Humphreys, PBRT 3rd ed., 14.2.4
//! "Infinite Area Lights"; Mitsuba 3 `envmap`, which warps the same weighted image).

use super::distribution::Piecewise2D;
use glam::{Vec2, Vec3};
use irradia_core::Rgb;
use irradia_scene::EnvMap;
use std::f32::consts::PI;
use std::sync::Arc;

/// An environment map with the distribution its directions are sampled from.
#[derive(Clone, Debug)]
pub struct EnvmapSampler {
    pub map: Arc<EnvMap>,
    dist: Piecewise2D,
    /// Mean radiance (RGB mean) over the sphere of directions.
    mean_radiance: f32,
}

/// One direction drawn from an environment map.
#[derive(Clone, Copy, Debug)]
pub struct EnvmapSample {
    /// Unit world direction towards the environment.
    pub wi: Vec3,
    /// Radiance arriving from `wi`.
    pub radiance: Rgb,
    /// Solid-angle density of `wi`.
    pub pdf: f32,
}

impl EnvmapSampler {
    pub fn new(map: Arc<EnvMap>) -> Self {
        let (w, h) = (map.image.width() as usize, map.image.height() as usize);
        let mut func = Vec::with_capacity(w * h);
        let mut sum = 0.0f64;
        for j in 0..h {
            let sin_theta = (PI * (j as f32 + 0.5) / h as f32).sin();
            // Solid angle of a texel of this row: (2π / w)(cos θ0 − cos θ1).
            let (t0, t1) = (PI * j as f32 / h as f32, PI * (j + 1) as f32 / h as f32);
            let omega = 2.0 * PI / w as f32 * (t0.cos() - t1.cos());
            for i in 0..w {
                let c = map.image.get(i as u32, j as u32) * map.scale;
                func.push(c.luminance().max(0.0) * sin_theta);
                sum += (c.mean() * omega) as f64;
            }
        }
        Self {
            dist: Piecewise2D::new(&func, w, h),
            mean_radiance: (sum / (4.0 * std::f64::consts::PI)) as f32,
            map,
        }
    }

    /// Mean radiance over all directions (for choosing among lights by power).
    pub fn mean_radiance(&self) -> f32 {
        self.mean_radiance
    }

    /// A direction drawn in proportion to luminance; `None` for a black map.
    #[inline]
    pub fn sample(&self, u: Vec2) -> Option<EnvmapSample> {
        if self.dist.integral() <= 0.0 {
            return None;
        }
        let (uv, (i, j)) = self.dist.sample(u);
        let sin_theta = (PI * uv.y).sin();
        let p = self.dist.pdf(i, j);
        if sin_theta <= 0.0 || p <= 0.0 {
            return None;
        }
        Some(EnvmapSample {
            wi: self.map.direction(uv),
            radiance: self.map.image.get(i as u32, j as u32) * self.map.scale,
            pdf: p / (2.0 * PI * PI * sin_theta),
        })
    }

    /// The solid-angle density with which `sample` produces world direction `dir`.
    #[inline]
    pub fn pdf(&self, dir: Vec3) -> f32 {
        if self.dist.integral() <= 0.0 {
            return 0.0;
        }
        let uv = self.map.uv(dir);
        let (i, j) = self.map.texel(uv);
        let sin_theta = (PI * uv.y).sin();
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.dist.pdf(i as usize, j as usize) / (2.0 * PI * PI * sin_theta)
    }
}
