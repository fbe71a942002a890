//! Importance sampling of Mitsuba's `envmap` emitter. The map is a grid of pixels
//! interpolated bilinearly (see [`irradia_scene::EnvMap`]); Mitsuba samples that grid
//! with a piecewise-bilinear warp of luminance × sin θ at the pixels. Here each of the
//! `W x (H - 1)` grid cells gets the same probability as in Mitsuba's warp (the integral
//! of the bilinear function over the cell: the mean of its four corners times its area),
//! drawn uniformly inside the cell (a 2D piecewise-constant distribution), and turned into
//! solid angle by the Jacobian of the lat-long map, `dω = 2π² sin θ du dv` (Pharr, Jakob,
//! Humphreys, PBRT 3rd ed., 14.2.4 "Infinite Area Lights"). The density differs from
//! Mitsuba's only inside a cell; the estimate is the same in expectation.

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
        let rows = h - 1;
        // Luminance × sin θ and RGB mean at every grid vertex (row y at θ = π y / (H - 1)).
        let vertex = |x: usize, y: usize| {
            let c = map.vertex(x as u32, y as u32) * map.scale;
            let sin_theta = (PI * y as f32 / rows as f32).sin();
            (c.luminance().max(0.0) * sin_theta, c.mean())
        };
        let mut func = Vec::with_capacity(w * rows);
        let mut sum = 0.0f64;
        for j in 0..rows {
            // Solid angle of a cell of this row: (2π / W)(cos θ0 − cos θ1).
            let (t0, t1) = (
                PI * j as f32 / rows as f32,
                PI * (j + 1) as f32 / rows as f32,
            );
            let omega = 2.0 * PI / w as f32 * (t0.cos() - t1.cos());
            for i in 0..w {
                let corners = [
                    vertex(i, j),
                    vertex(i + 1, j),
                    vertex(i, j + 1),
                    vertex(i + 1, j + 1),
                ];
                func.push(corners.iter().map(|c| c.0).sum::<f32>() * 0.25);
                sum += (corners.iter().map(|c| c.1).sum::<f32>() * 0.25 * omega) as f64;
            }
        }
        Self {
            dist: Piecewise2D::new(&func, w, rows),
            mean_radiance: (sum / (4.0 * std::f64::consts::PI)) as f32,
            map,
        }
    }

    /// The distribution of grid cells that `sample` draws from (for the wide
    /// kernel's lanes, [`crate::path::wide::envmap_lanes`]).
    pub(crate) fn distribution(&self) -> &Piecewise2D {
        &self.dist
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
        let (st, (i, j)) = self.dist.sample(u);
        let uv = self.map.uv_of_grid(st);
        let (wi, sin_theta) = self.map.direction_sin_theta(uv);
        let p = self.dist.pdf(i, j);
        if sin_theta <= 0.0 || p <= 0.0 {
            return None;
        }
        Some(EnvmapSample {
            wi,
            radiance: self.map.eval_uv(uv),
            pdf: p / (2.0 * PI * PI * sin_theta),
        })
    }

    /// The solid-angle density with which `sample` produces world direction `dir`.
    #[inline]
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let (uv, sin_theta) = self.map.uv_sin_theta(dir);
        self.pdf_uv(uv, sin_theta)
    }

    /// The radiance arriving from world direction `dir` and, with `want_pdf`, the
    /// density [`EnvmapSampler::pdf`] of `dir` (else 0): the map's coordinates of `dir`
    /// (two inverse trigonometric functions) found once for both.
    #[inline]
    pub fn radiance_pdf(&self, dir: Vec3, want_pdf: bool) -> (Rgb, f32) {
        let (uv, sin_theta) = self.map.uv_sin_theta(dir);
        let pdf = if want_pdf {
            self.pdf_uv(uv, sin_theta)
        } else {
            0.0
        };
        (self.map.eval_uv(uv), pdf)
    }

    /// [`EnvmapSampler::pdf`] at the map's coordinates `uv` (where `sin θ` is
    /// `sin_theta`).
    #[inline]
    fn pdf_uv(&self, uv: Vec2, sin_theta: f32) -> f32 {
        if self.dist.integral() <= 0.0 {
            return 0.0;
        }
        let (i, j) = self.map.cell(self.map.grid(uv));
        if sin_theta <= 0.0 {
            return 0.0;
        }
        self.dist.pdf(i as usize, j as usize) / (2.0 * PI * PI * sin_theta)
    }
}
